// The one table of constitutive models and the parser of their arguments.
#include "materials/material_table.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <initializer_list>

#include "io/input_help.h"

namespace fracdem
{

const std::vector<MaterialModelInfo>& material_models()
{
  static const std::vector<MaterialModelInfo> table = {
      {"elastic", MaterialModel::Elastic, 0, false, ""},
      {"rankine", MaterialModel::Rankine, kRankineStateSize, true,
       "strength FT fracture_energy GF [softening linear|exponential]"},
      {"j2", MaterialModel::J2, kPlasticStateSize, false, "yield SY hardening H [exponent N]"},
      {"johnson_cook", MaterialModel::JohnsonCook, kPlasticStateSize, false,
       "A B N C M [eps0 E0] [tmelt TM] [troom TR] [cp CP]"},
      {"zerilli_armstrong", MaterialModel::ZerilliArmstrong, kPlasticStateSize, false,
       "bcc|fcc C0 C1 C3 C4 C5 N [eps0 E0] [troom TR] [cp CP]"},
  };
  return table;
}

const MaterialModelInfo* find_material_model(const std::string& keyword)
{
  for (const MaterialModelInfo& m : material_models())
    if (keyword == m.keyword) return &m;
  return nullptr;
}

const MaterialModelInfo& material_model_info(MaterialModel model)
{
  for (const MaterialModelInfo& m : material_models())
    if (m.model == model) return m;
  return material_models().front();
}

std::vector<std::string> material_options(MaterialModel model)
{
  // Lower-case words of the syntax are option names; constants are upper case, choices hold '|'.
  std::vector<std::string> names;
  std::string word;
  for (const char c : std::string(material_model_info(model).syntax) + " ") {
    if (c != ' ' && c != '[' && c != ']') {
      word += c;
      continue;
    }
    const bool name = !word.empty() && std::islower(static_cast<unsigned char>(word[0])) &&
                      word.find_first_of("|ABCDEFGHIJKLMNOPQRSTUVWXYZ") == std::string::npos;
    if (name) names.push_back(word);
    word.clear();
  }
  return names;
}

namespace
{

// Walks a word list; every error names the keyword (`material X` / `eos`) and its syntax.
struct WordReader {
  const std::vector<std::string>& w;
  std::size_t i;
  std::string head, syntax; // e.g. "material johnson_cook", its argument syntax
  std::string err;

  bool more() const { return i < w.size(); }
  bool fail(const std::string& what)
  {
    if (err.empty()) err = head + ": " + what + " (expected '" + head + " " + syntax + "')";
    return false;
  }
  // The next word as a finite number for constant `name`.
  bool number(const char* name, double& out)
  {
    if (!more()) return fail(std::string("missing ") + name);
    const std::string& s = w[i];
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || *end != '\0' || !std::isfinite(v))
      return fail(std::string(name) + ": '" + s + "' is not a number");
    out = v;
    ++i;
    return true;
  }
};

// Where a required option is missing and the list stopped at a word near an option of `model`
// (a misspelt "fracture_enrgy"): " ('fracture_enrgy'; did you mean 'fracture_energy'?)", else "".
std::string misspelt_option(const WordReader& r, MaterialModel model)
{
  if (!r.more()) return "";
  const std::string hint = did_you_mean(r.w[r.i], material_options(model));
  return hint.empty() ? "" : " ('" + r.w[r.i] + "'" + hint + ")";
}

// Optional `key value` pairs. Stops (true) at a word that is no key when the caller takes the
// rest (`open`), else fails on it.
bool read_options(WordReader& r, bool open,
                  std::initializer_list<std::pair<const char*, double*>> keys)
{
  while (r.more()) {
    const std::string& kw = r.w[r.i];
    double* target = nullptr;
    for (const auto& k : keys)
      if (kw == k.first) target = k.second;
    if (!target) {
      if (open) return true;
      std::vector<std::string> names;
      for (const auto& k : keys)
        names.push_back(k.first);
      return r.fail("unknown word '" + kw + "'" + did_you_mean(kw, names));
    }
    ++r.i;
    if (!r.number(kw.c_str(), *target)) return false;
  }
  return true;
}

bool parse_rankine(WordReader& r, bool open, Material& mat)
{
  mat.ft = mat.gf = 0;
  mat.softening = Softening::Linear;
  bool have_ft = false, have_gf = false;
  while (r.more()) {
    const std::string& kw = r.w[r.i];
    if (kw == "softening") {
      if (r.i + 1 >= r.w.size()) return r.fail("missing softening law");
      const std::string& law = r.w[r.i + 1];
      if (law != "linear" && law != "exponential")
        return r.fail("softening: '" + law + "' is neither linear nor exponential");
      mat.softening = law == "linear" ? Softening::Linear : Softening::Exponential;
      r.i += 2;
    } else if (kw == "strength" || kw == "fracture_energy") {
      ++r.i;
      const bool ft = kw == "strength";
      if (!r.number(kw.c_str(), ft ? mat.ft : mat.gf)) return false;
      (ft ? have_ft : have_gf) = true;
    } else if (open) {
      break;
    } else {
      return r.fail("unknown word '" + kw + "'" +
                    did_you_mean(kw, material_options(MaterialModel::Rankine)));
    }
  }
  if (!have_ft || !have_gf)
    return r.fail("strength and fracture_energy are required" +
                  misspelt_option(r, MaterialModel::Rankine));
  if (!(mat.ft > 0)) return r.fail("strength FT must be > 0");
  if (!(mat.gf > 0)) return r.fail("fracture_energy GF must be > 0");
  return true;
}

bool parse_j2(WordReader& r, bool open, PlasticParams& p)
{
  p.a = p.b = std::nan(""); // "not given" (number() never yields NaN)
  if (!read_options(r, open, {{"yield", &p.a}, {"hardening", &p.b}, {"exponent", &p.n}}))
    return false;
  if (std::isnan(p.a) || std::isnan(p.b))
    return r.fail("yield and hardening are required" + misspelt_option(r, MaterialModel::J2));
  return true;
}

bool parse_johnson_cook(WordReader& r, bool open, PlasticParams& p)
{
  if (!r.number("A", p.a) || !r.number("B", p.b) || !r.number("N", p.n) || !r.number("C", p.c) ||
      !r.number("M", p.m))
    return false;
  return read_options(r, open,
                      {{"eps0", &p.eps0}, {"tmelt", &p.tmelt}, {"troom", &p.troom}, {"cp", &p.cp}});
}

bool parse_zerilli_armstrong(WordReader& r, bool open, PlasticParams& p)
{
  if (!r.more() || (r.w[r.i] != "bcc" && r.w[r.i] != "fcc"))
    return r.fail(r.more() ? "'" + r.w[r.i] + "' is neither bcc nor fcc" : "missing bcc|fcc");
  p.fcc = r.w[r.i++] == "fcc";
  if (!r.number("C0", p.a) || !r.number(p.fcc ? "C2 (fcc)" : "C1", p.c1) || !r.number("C3", p.c3) ||
      !r.number("C4", p.c4) || !r.number("C5", p.b) || !r.number("N", p.n))
    return false;
  return read_options(r, open, {{"eps0", &p.eps0}, {"troom", &p.troom}, {"cp", &p.cp}});
}

} // namespace

std::string parse_material_arguments(const std::vector<std::string>& words, Material& mat,
                                     std::size_t* consumed)
{
  std::string names;
  for (const MaterialModelInfo& m : material_models())
    names += std::string(names.empty() ? "" : ", ") + m.keyword;
  if (words.empty()) return "material: missing model (one of " + names + ")";
  const MaterialModelInfo* info = find_material_model(words[0]);
  if (!info) return "material: unknown model '" + words[0] + "' (one of " + names + ")";
  WordReader r{words, 1, std::string("material ") + info->keyword, info->syntax, ""};
  const bool open = consumed != nullptr;
  mat.model = info->model;
  bool ok = true;
  if (info->model == MaterialModel::Rankine) {
    ok = parse_rankine(r, open, mat);
  } else if (mat.plastic_model()) {
    mat.plastic = PlasticParams();
    if (info->model == MaterialModel::J2) ok = parse_j2(r, open, mat.plastic);
    if (info->model == MaterialModel::JohnsonCook) ok = parse_johnson_cook(r, open, mat.plastic);
    if (info->model == MaterialModel::ZerilliArmstrong)
      ok = parse_zerilli_armstrong(r, open, mat.plastic);
    mat.plastic.model = mat.plasticity().plastic.model;
    if (ok && mat.model == MaterialModel::JohnsonCook && mat.plastic.tmelt != 0 &&
        mat.plastic.cp == 0)
      ok = r.fail("tmelt needs cp CP (thermal softening follows the adiabatic heating)");
    const char* bad = ok ? plastic_params_check(mat.plastic) : "";
    if (*bad) ok = r.fail(bad);
  } else if (r.more() && !open) {
    ok = r.fail("unknown word '" + words[1] + "'");
  }
  if (!ok) return r.err;
  if (consumed) *consumed = r.i;
  return "";
}

std::string parse_eos_arguments(const std::vector<std::string>& words, Material& mat,
                                std::size_t* consumed)
{
  WordReader r{words, 1, "eos", "linear|mie_gruneisen C0 S GAMMA0", ""};
  if (words.empty() || (words[0] != "linear" && words[0] != "mie_gruneisen")) {
    r.fail(words.empty() ? "missing model" : "unknown model '" + words[0] + "'");
    return r.err;
  }
  EosParams e;
  if (words[0] == "mie_gruneisen") {
    e.model = EosModel::MieGruneisen;
    r.head = "eos mie_gruneisen";
    r.syntax = "C0 S GAMMA0";
    if (!r.number("C0", e.c0) || !r.number("S", e.s) || !r.number("GAMMA0", e.gamma0)) return r.err;
    const char* bad = eos_check(e);
    if (*bad) {
      r.fail(bad);
      return r.err;
    }
  }
  if (r.more() && !consumed) {
    r.fail("unknown word '" + words[r.i] + "'");
    return r.err;
  }
  mat.eos = e;
  if (consumed) *consumed = r.i;
  return "";
}

std::string material_setup_error(const Material& mat, int dim)
{
  const bool plane_stress = dim == 2 && mat.plane == PlaneMode::PlaneStress;
  if (!mat.plastic_model()) {
    if (mat.eos.model == EosModel::MieGruneisen)
      return "eos mie_gruneisen: needs a plastic material (material j2, johnson_cook or "
             "zerilli_armstrong) for the deviatoric stress";
    return "";
  }
  const StressMode mode = dim == 3                               ? StressMode::Solid
                          : plane_stress                         ? StressMode::PlaneStress
                          : mat.plane == PlaneMode::Axisymmetric ? StressMode::Axisymmetric
                                                                 : StressMode::PlaneStrain;
  const char* bad_eos = eos_check(mat.eos);
  if (*bad_eos) return std::string("eos mie_gruneisen: ") + bad_eos;
  const char* bad = plastic_check(mat.plasticity(), mode);
  if (!*bad) return "";
  std::string head = std::string("material ") + material_model_info(mat.model).keyword;
  if (plane_stress && mat.eos.model == EosModel::MieGruneisen) head += " with eos mie_gruneisen";
  return head + ": " + bad;
}

double point_failure(const Material& mat, const double* state, double normal[3])
{
  normal[0] = normal[1] = normal[2] = 0;
  if (mat.model != MaterialModel::Rankine) return 0.0;
  const double* n = rankine_crack_normal(state);
  for (int d = 0; d < 3; ++d)
    normal[d] = n[d];
  return rankine_cracked(mat.rankine(), state) ? 1.0 : rankine_damage(state);
}

double point_dissipation(const Material& mat, const double* state)
{
  if (mat.model == MaterialModel::Rankine) return rankine_dissipated(state);
  if (mat.plastic_model()) return plastic_dissipated(state);
  return 0.0;
}

} // namespace fracdem
