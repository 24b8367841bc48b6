// fix fem/body's settings: the one keyword table, its handlers, the parser and the checks.
#include "body/body_spec.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "io/input_help.h"
#include "materials/material_table.h"

namespace fracdem
{

namespace
{

[[noreturn]] void fail(const std::string& what)
{
  throw SpecError(what);
}

// Sub-model tables: one place maps words to models.
const std::map<std::string, Kinematics> kKinematicsTable = {
    {"elastic", Kinematics::SmallStrain},
    {"corotational", Kinematics::Corotational},
};
const std::map<std::string, NormalModel> kNormalModelTable = {
    {"hertz", NormalModel::Hertz},
    {"hooke", NormalModel::Hooke},
};
const std::map<std::string, PlaneMode> kPlaneModeTable = {
    {"strain", PlaneMode::PlaneStrain},
    {"axisymmetric", PlaneMode::Axisymmetric},
    {"stress", PlaneMode::PlaneStress},
};

// word(1) looked up in `table`; else "keyword 'KW' got 'V', expected one of: a b".
template <typename T> T lookup(const SpecReader& r, const std::map<std::string, T>& table)
{
  auto it = table.find(r.word(1));
  if (it == table.end()) {
    std::string msg = "keyword '" + r.keyword() + "' got '" + r.word(1) + "', expected one of:";
    for (const auto& kv : table)
      msg += " " + kv.first;
    fail(msg);
  }
  return it->second;
}

// A keyword with one value: need(1, what), the value (number(1)), take(2).
double one_number(SpecReader& r, const char* what)
{
  r.need(1, what);
  const double v = r.number(1);
  r.take(2);
  return v;
}

// ---- the handlers of the keyword table, in the documentation's order ----

void parse_type(SpecReader& r, BodySpec& s)
{
  r.need(1, "an atom type");
  s.surface_type = r.whole_number(1);
  r.take(2);
}

void parse_density(SpecReader& r, BodySpec& s)
{
  s.material.rho = one_number(r, "a value");
  s.have_density = true;
}

void parse_youngs(SpecReader& r, BodySpec& s)
{
  s.material.E = one_number(r, "a value");
  s.have_youngs = true;
}

void parse_poisson(SpecReader& r, BodySpec& s)
{
  s.material.nu = one_number(r, "a value");
  s.have_poisson = true;
}

void parse_model(SpecReader& r, BodySpec& s)
{
  r.need(1, "elastic or corotational");
  s.material.kinematics = lookup(r, kKinematicsTable);
  r.take(2);
}

void parse_plane(SpecReader& r, BodySpec& s)
{
  r.need(1, "strain, stress or axisymmetric");
  s.material.plane = lookup(r, kPlaneModeTable);
  s.have_plane = true;
  r.take(2);
}

void parse_thickness(SpecReader& r, BodySpec& s)
{
  s.material.thickness = one_number(r, "a value");
  if (s.material.thickness <= 0) fail("keyword 'thickness' must be > 0");
}

// fixed GROUP [x] [y] [z]: no component named holds all.
void parse_fixed(SpecReader& r, BodySpec& s)
{
  r.need(1, "a mesh physical group name [x] [y] [z]");
  FixedSpec f{r.word(1), 0, s.reaction_group(r.word(1))};
  r.take(2);
  const std::string axes = "xyz";
  for (; !r.done() && r.keyword().size() == 1 && axes.find(r.keyword()[0]) != std::string::npos;
       r.take(1))
    f.mask |= 1 << (r.keyword()[0] - 'x');
  if (f.mask == 0) f.mask = 7;
  s.fixed_sets.push_back(f);
}

// GROUP vx vy vz, each component a number or NULL (LAMMPS convention: that component is not
// given, its bit of the mask is cleared).
NodeVelocitySpec node_velocity(SpecReader& r)
{
  r.need(4, "GROUP vx vy vz (a component may be NULL)");
  NodeVelocitySpec v;
  v.set = r.word(1);
  for (int d = 0; d < 3; ++d) {
    if (r.word(2 + d) == "NULL")
      v.mask &= ~(1 << d);
    else
      v.v[d] = r.number(2 + d);
  }
  r.take(5);
  return v;
}

void parse_velocity(SpecReader& r, BodySpec& s)
{
  s.initial_velocity.push_back(node_velocity(r));
}

// prescribed_velocity GROUP vx vy vz [ramp T]; a NULL component is free.
void parse_prescribed_velocity(SpecReader& r, BodySpec& s)
{
  NodeVelocitySpec v = node_velocity(r);
  if (v.mask == 0)
    fail("keyword 'prescribed_velocity' got NULL for vx, vy and vz; expected a velocity for at "
         "least one component (NULL leaves a component free)");
  v.group = s.reaction_group(v.set);
  if (r.has(1) && r.keyword() == "ramp") {
    v.ramp = r.number(1);
    if (v.ramp <= 0) fail("keyword 'prescribed_velocity ... ramp T' needs T > 0");
    r.take(2);
  }
  s.prescribed_velocity.push_back(v);
}

void parse_scale(SpecReader& r, BodySpec& s)
{
  MeshTransform t{MeshTransform::Scale, {one_number(r, "a factor"), 0, 0, 0}};
  if (t.a[0] <= 0) fail("keyword 'scale' must be > 0");
  s.transforms.push_back(t);
}

void parse_move(SpecReader& r, BodySpec& s)
{
  r.need(3, "dx dy dz");
  MeshTransform t{MeshTransform::Move, {0, 0, 0, 0}};
  for (int d = 0; d < 3; ++d)
    t.a[d] = r.number(1 + d);
  s.transforms.push_back(t);
  r.take(4);
}

// rotate axis ax ay az angle DEGREES
void parse_rotate(SpecReader& r, BodySpec& s)
{
  r.need(6, "axis ax ay az angle DEGREES");
  if (r.word(1) != "axis" || r.word(5) != "angle")
    fail("keyword 'rotate' expects 'axis ax ay az angle DEGREES'");
  MeshTransform t{MeshTransform::Rotate, {0, 0, 0, 0}};
  for (int d = 0; d < 3; ++d)
    t.a[d] = r.number(2 + d);
  t.a[3] = r.number(6) * M_PI / 180.0;
  if (!valid_axis(t.a))
    fail("keyword 'rotate' got axis " + r.word(2) + " " + r.word(3) + " " + r.word(4) +
         ", expected a non-zero axis direction ax ay az");
  s.transforms.push_back(t);
  r.take(7);
}

void parse_rigid(SpecReader& r, BodySpec& s)
{
  s.rigid = r.either("yes", "no");
}

void parse_motion_linear(SpecReader& r, RigidMotion& m)
{
  r.need(4, "linear vx vy vz");
  m.kind = RigidMotion::Linear;
  for (int d = 0; d < 3; ++d)
    m.velocity[d] = r.number(2 + d);
  r.take(5);
}

void parse_motion_rotate(SpecReader& r, RigidMotion& m)
{
  r.need(11, "rotate origin ox oy oz axis ax ay az period T");
  if (r.word(2) != "origin" || r.word(6) != "axis" || r.word(10) != "period")
    fail("keyword 'motion rotate' expects 'origin ox oy oz axis ax ay az period T'");
  m.kind = RigidMotion::Rotate;
  for (int d = 0; d < 3; ++d) {
    m.origin[d] = r.number(3 + d);
    m.axis[d] = r.number(7 + d);
  }
  m.period = r.number(11);
  double* k = m.axis;
  const double n = std::sqrt(k[0] * k[0] + k[1] * k[1] + k[2] * k[2]);
  if (!valid_axis(k) || m.period == 0) fail("'motion rotate' needs a non-zero axis and period");
  for (int d = 0; d < 3; ++d)
    k[d] /= n;
  r.take(12);
}

// motion linear vx vy vz | rotate origin ox oy oz axis ax ay az period T
void parse_motion(SpecReader& r, BodySpec& s)
{
  using Kind = void (*)(SpecReader&, RigidMotion&);
  static const std::map<std::string, Kind> kinds = {{"linear", parse_motion_linear},
                                                    {"rotate", parse_motion_rotate}};
  r.need(1, "linear vx vy vz | rotate origin ox oy oz axis ax ay az period T");
  auto it = kinds.find(r.word(1));
  if (it == kinds.end()) fail("keyword 'motion' expects 'linear' or 'rotate'");
  it->second(r, s.motion);
}

// A core parser's "material rankine: strength: ..." as "keyword 'material rankine': strength: ...".
std::string keyword_error(const std::string& err)
{
  const std::size_t colon = err.find(':');
  if (colon == std::string::npos) return "keyword " + err;
  return "keyword '" + err.substr(0, colon) + "'" + err.substr(colon);
}

// `material MODEL ...` and `eos ...`: the material table reads the words up to the next
// keyword with `parse` (parse_material_arguments or parse_eos_arguments).
using MaterialParser = std::string (*)(const std::vector<std::string>&, Material&, std::size_t*);
void parse_material_words(SpecReader& r, BodySpec& s, MaterialParser parse)
{
  std::size_t used = 0;
  const std::string err = parse(r.rest(), s.material, &used);
  if (!err.empty()) fail(keyword_error(err));
  r.take(1 + used);
}

void parse_material(SpecReader& r, BodySpec& s)
{
  parse_material_words(r, s, parse_material_arguments);
}

void parse_eos(SpecReader& r, BodySpec& s)
{
  parse_material_words(r, s, parse_eos_arguments);
}

// The options after `fracture nodal`, each with one value.
using FractureOption = void (*)(const SpecReader&, BodySpec&);
const std::map<std::string, FractureOption> kFractureOptions = {
    {"every",
     [](const SpecReader& r, BodySpec& s) {
       s.fracture_every = r.whole_number(1);
       if (s.fracture_every < 1) fail("keyword 'fracture nodal every' expects N >= 1");
     }},
    {"erode_cracked",
     [](const SpecReader& r, BodySpec& s) {
       if (r.word(1) != "yes" && r.word(1) != "no")
         fail("keyword 'fracture nodal erode_cracked' expects yes or no");
       s.erode_cracked = r.word(1) == "yes";
     }},
    {"min_size",
     [](const SpecReader& r, BodySpec& s) {
       s.min_size = spec_number("fracture nodal min_size", r.word(1));
       if (!(s.min_size > 0 && s.min_size < 0.5))
         fail("keyword 'fracture nodal min_size' expects a fraction F with 0 < F < 0.5 (each "
              "piece of an element that a crack cuts keeps at least F of its area/volume), got " +
              r.word(1));
     }},
    {"track",
     [](const SpecReader& r, BodySpec& s) {
       s.track_length = spec_number("fracture nodal track", r.word(1));
       if (!(s.track_length > 0) || !std::isfinite(s.track_length))
         fail("keyword 'fracture nodal track' expects a length L > 0 (the crack tracking "
              "length, at least two element sizes), got " +
              r.word(1));
     }},
    {"exclusion",
     [](const SpecReader& r, BodySpec& s) {
       s.track_exclusion = spec_number("fracture nodal exclusion", r.word(1));
       if (!(s.track_exclusion > 0) || !std::isfinite(s.track_exclusion))
         fail("keyword 'fracture nodal exclusion' expects a radius R > 0 (no crack starts within "
              "R of a tracked crack), got " +
              r.word(1));
     }},
};

// fracture nodal [every N] [erode_cracked yes|no] [min_size F] [track L [exclusion R]]
void parse_fracture(SpecReader& r, BodySpec& s)
{
  if (!r.has(1) || r.word(1) != "nodal") fail("keyword 'fracture' expects 'nodal [every N]'");
  s.fracture_every = 1;
  r.take(2);
  for (; r.has(1) && kFractureOptions.count(r.keyword()); r.take(2))
    kFractureOptions.at(r.keyword())(r, s);
}

// bulk_viscosity off | Q1 Q2: the coefficients are checked by the core.
void parse_bulk_viscosity(SpecReader& r, BodySpec& s)
{
  const char* expected = "keyword 'bulk_viscosity' expects 'off' or 'Q1 Q2' (linear and "
                         "quadratic coefficients, e.g. 0.06 1.2)";
  if (!r.has(1)) fail(expected);
  if (r.word(1) == "off") {
    s.viscosity_mode = 0;
    r.take(2);
    return;
  }
  if (!r.has(2)) fail(expected);
  s.viscosity.q1 = r.number(1);
  s.viscosity.q2 = r.number(2);
  const char* bad = bulk_viscosity_check(s.viscosity);
  if (*bad) fail(std::string("keyword 'bulk_viscosity': ") + bad);
  s.viscosity_mode = 1;
  r.take(3);
}

// The criteria of `erosion`, each with one value.
const std::map<std::string, double ErosionCriteria::*> kErosionCriteria = {
    {"plastic_strain", &ErosionCriteria::plastic_strain},
    {"damage", &ErosionCriteria::damage},
    {"min_dt", &ErosionCriteria::min_dt}};

// erosion plastic_strain EPS | damage D | min_dt DT (any of them, in any order, on one keyword):
// the values are checked against the material by check_body_spec (erosion_setup_error).
void parse_erosion(SpecReader& r, BodySpec& s)
{
  int used = 0;
  for (r.take(1); r.has(1) && kErosionCriteria.count(r.keyword()); r.take(2), ++used)
    s.erosion.*kErosionCriteria.at(r.keyword()) = spec_number("erosion " + r.keyword(), r.word(1));
  if (used == 0 || !s.erosion.on())
    fail("keyword 'erosion' expects one or more of 'plastic_strain EPS' (EPS > 0), 'damage D' "
         "(0 < D <= 1), 'min_dt DT' (DT > 0)");
}

// erosion_mass keep|remove: whether an eroded element's mass stays on its nodes.
void parse_erosion_mass(SpecReader& r, BodySpec& s)
{
  s.erosion.remove_mass = !r.either("keep", "remove");
  s.have_erosion_mass = true;
}

void parse_contact_model(SpecReader& r, BodySpec& s)
{
  r.need(1, "hertz or hooke");
  s.normal_model = lookup(r, kNormalModelTable);
  r.take(2);
}

void parse_tangential(SpecReader& r, BodySpec& s)
{
  s.tangential_history = r.either("history", "no_history");
}

void parse_compliance(SpecReader& r, BodySpec& s)
{
  s.compliance_combined = r.either("particle", "combined") ? 0 : 1;
}

void parse_buffer(SpecReader& r, BodySpec& s)
{
  s.buffer = one_number(r, "a distance");
  if (s.buffer < 0) fail("keyword 'buffer' must be >= 0");
}

void parse_dt_check(SpecReader& r, BodySpec& s)
{
  s.dt_check_error = r.either("error", "warn");
}

// substeps auto|off|N (1 <= N <= kMaxSubsteps).
void parse_substeps(SpecReader& r, BodySpec& s)
{
  const std::string expected = "auto, off or a count 1 .. " + std::to_string(kMaxSubsteps);
  r.need(1, expected);
  const std::string& w = r.word(1);
  if (w == "auto" || w == "off") {
    s.substeps = w == "auto" ? kSubstepsAuto : kSubstepsOff;
  } else {
    char* end = nullptr;
    const long n = std::strtol(w.c_str(), &end, 10);
    if (end == w.c_str() || *end != '\0' || n < 1 || n > kMaxSubsteps)
      fail("keyword 'substeps' expects " + expected + ", got '" + w + "'");
    s.substeps = static_cast<int>(n);
  }
  s.have_substeps = true;
  r.take(2);
}

void parse_gravity(SpecReader& r, BodySpec& s)
{
  s.apply_gravity = r.either("yes", "no"); // anything else is an error, not "no"
}

void parse_energy_file(SpecReader& r, BodySpec& s)
{
  r.need(2, "FILE N");
  s.energy_file = r.word(1);
  s.energy_every = r.whole_number(2);
  if (s.energy_every <= 0) fail("keyword 'energy_file' needs N > 0");
  r.take(3);
}

void parse_parallel(SpecReader& r, BodySpec& s)
{
  s.distributed = r.either("distributed", "replicated");
  s.have_parallel = true;
  if (!s.distributed || r.done() || r.keyword() != "rebalance") return;
  r.need(1, "a threshold B > 1 (parts' largest modelled work over the mean)");
  s.rebalance = r.number(1);
  if (!(s.rebalance > 1.0))
    fail("keyword 'parallel distributed rebalance' expects a threshold B > 1 (parts' largest "
         "modelled work over the mean), got '" +
         r.word(1) + "'");
  r.take(2);
  if (r.done() || r.keyword() != "every") return;
  r.need(1, "a step count N >= 1");
  s.rebalance_every = r.whole_number(1);
  if (s.rebalance_every < 1)
    fail("keyword 'parallel distributed rebalance B every' expects a step count N >= 1, got '" +
         r.word(1) + "'");
  r.take(2);
}

void parse_contact_bodies(SpecReader& r, BodySpec& s)
{
  s.contact_bodies = r.either("yes", "no") ? 1 : 0;
}

void parse_contact_edges(SpecReader& r, BodySpec& s)
{
  s.contact_edges = r.either("yes", "no");
}

void parse_contact_penalty(SpecReader& r, BodySpec& s)
{
  s.contact_penalty = one_number(r, "a factor");
  if (s.contact_penalty <= 0) fail("keyword 'contact_penalty' must be > 0");
}

// The options after `contact_balance MODEL`, each with one value.
const std::vector<std::string> kContactBalanceOptions = {"thresh", "every", "parts", "file"};

// contact_balance a_priori|a_posteriori [thresh B] [every N] [parts K] [file PATH]
void parse_contact_balance(SpecReader& r, BodySpec& s)
{
  r.need(1, "a_priori or a_posteriori");
  ContactBalance& b = s.contact_balance;
  if (r.word(1) == "a_priori")
    b.model = ContactBalance::APriori;
  else if (r.word(1) == "a_posteriori")
    b.model = ContactBalance::APosteriori;
  else
    fail("keyword 'contact_balance' got '" + r.word(1) + "', expected a_priori or a_posteriori");
  std::size_t k = 2;
  while (r.has(k) &&
         std::count(kContactBalanceOptions.begin(), kContactBalanceOptions.end(), r.word(k))) {
    const std::string opt = r.word(k);
    if (!r.has(k + 1)) fail("keyword 'contact_balance': '" + opt + "' expects a value");
    if (opt == "thresh") {
      b.thresh = r.number(k + 1);
      if (!(b.thresh >= 1.0))
        fail("keyword 'contact_balance': 'thresh' expects B >= 1 (max / mean of the ranks' "
             "contact work)");
    } else if (opt == "every") {
      b.every = r.whole_number(k + 1);
      if (b.every < 1) fail("keyword 'contact_balance': 'every' expects a step count >= 1");
    } else if (opt == "parts") {
      b.parts = r.whole_number(k + 1);
      if (b.parts < 1) fail("keyword 'contact_balance': 'parts' expects a count >= 1");
    } else {
      b.file = r.word(k + 1);
    }
    k += 2;
  }
  s.have_contact_balance = true;
  r.take(k);
}

// A particle touches a handful of facet features at once; beyond kMaxHistorySlots it is a typo
// (the history array is per particle and would eat memory).
void parse_history_slots(SpecReader& r, BodySpec& s)
{
  r.need(1, "a count");
  s.history_slots = r.whole_number(1);
  if (s.history_slots < 1 || s.history_slots > kMaxHistorySlots)
    fail("keyword 'history_slots' expects 1 .. 64");
  r.take(2);
}

using Handler = void (*)(SpecReader&, BodySpec&);
struct Keyword {
  const char* keyword;
  Handler handle;
};

// The one keyword table of fix fem/body.
const std::vector<Keyword> kKeywords = {
    {"type", parse_type},
    {"density", parse_density},
    {"youngs", parse_youngs},
    {"poisson", parse_poisson},
    {"model", parse_model},
    {"plane", parse_plane},
    {"thickness", parse_thickness},
    {"fixed", parse_fixed},
    {"velocity", parse_velocity},
    {"prescribed_velocity", parse_prescribed_velocity},
    {"scale", parse_scale},
    {"move", parse_move},
    {"rotate", parse_rotate},
    {"rigid", parse_rigid},
    {"motion", parse_motion},
    {"material", parse_material},
    {"eos", parse_eos},
    {"fracture", parse_fracture},
    {"bulk_viscosity", parse_bulk_viscosity},
    {"erosion", parse_erosion},
    {"erosion_mass", parse_erosion_mass},
    {"contact_model", parse_contact_model},
    {"tangential", parse_tangential},
    {"compliance", parse_compliance},
    {"buffer", parse_buffer},
    {"dt_check", parse_dt_check},
    {"substeps", parse_substeps},
    {"gravity", parse_gravity},
    {"energy_file", parse_energy_file},
    {"contact_bodies", parse_contact_bodies},
    {"contact_penalty", parse_contact_penalty},
    {"contact_edges", parse_contact_edges},
    {"contact_balance", parse_contact_balance},
    {"history_slots", parse_history_slots},
    {"parallel", parse_parallel},
};

const Keyword* find_keyword(const std::string& keyword)
{
  auto it = std::find_if(kKeywords.begin(), kKeywords.end(),
                         [&](const Keyword& k) { return keyword == k.keyword; });
  return it == kKeywords.end() ? nullptr : &*it;
}

// "a b material(elastic) c": the keywords a restricted host takes.
std::string supported_list(const BodySpecHost& host)
{
  std::string list;
  for (const BodySpecHost::Supported& k : host.supported)
    list += (list.empty() ? "" : " ") + k.keyword + (k.note.empty() ? "" : "(" + k.note + ")");
  return list;
}

// The keywords a host takes: its own and the table's (all of it, or those it lists).
std::vector<std::string> host_keywords(const BodySpecHost& host)
{
  std::vector<std::string> names;
  for (const auto& own : host.own)
    names.push_back(own.first);
  if (host.supported.empty())
    for (const Keyword& k : kKeywords)
      names.push_back(k.keyword);
  for (const BodySpecHost::Supported& k : host.supported)
    names.push_back(k.keyword);
  return names;
}

// The options of the clause that keyword `prev` opened, named in `clause` ("material rankine":
// strength fracture_energy softening): a misspelt option ends the clause and so reaches the
// keyword table as an unknown keyword.
std::vector<std::string> clause_options(const std::string& prev, const BodySpec& s,
                                        std::string& clause)
{
  std::vector<std::string> names;
  clause = prev;
  if (prev == "material") {
    clause += std::string(" ") + material_model_info(s.material.model).keyword;
    names = material_options(s.material.model);
  } else if (prev == "fracture") {
    clause = "fracture nodal";
    for (const auto& option : kFractureOptions)
      names.push_back(option.first);
  } else if (prev == "erosion") {
    for (const auto& criterion : kErosionCriteria)
      names.push_back(criterion.first);
  } else if (prev == "contact_balance") {
    names = kContactBalanceOptions;
  }
  return names;
}

// "unknown keyword 'KW'", the host's list where it restricts the table, and the nearest of the
// keywords the host takes and the options of the clause before KW (`prev`).
std::string unknown_keyword(const std::string& kw, const std::string& prev, const BodySpec& s,
                            const BodySpecHost& host)
{
  std::string msg = "unknown keyword '" + kw + "'";
  if (!host.supported.empty())
    msg += " (supported under " + host.name + ": " + supported_list(host) + ")";
  std::string clause;
  const std::vector<std::string> options = clause_options(prev, s, clause);
  std::vector<std::string> names = host_keywords(host);
  names.insert(names.end(), options.begin(), options.end());
  const std::string near = nearest_word(kw, names);
  if (near.empty()) return msg;
  const bool option = std::count(options.begin(), options.end(), near) > 0;
  return msg + "; did you mean '" + near + "'" + (option ? " (in '" + clause + "')" : "") + "?";
}

// The keyword at r: the host's own handler, else the table's where the host takes it. `prev`:
// the keyword before it.
void parse_keyword(SpecReader& r, BodySpec& spec, const BodySpecHost& host, const std::string& prev)
{
  const std::string& kw = r.keyword();
  auto own = host.own.find(kw);
  if (own != host.own.end()) return own->second(r, spec);
  const Keyword* k = find_keyword(kw);
  if (!k) fail(unknown_keyword(kw, prev, spec, host));
  if (!host.takes(kw))
    fail("keyword '" + kw + "' is not yet supported under " + host.name +
         " (supported: " + supported_list(host) + ")");
  k->handle(r, spec);
}

// type, density/youngs/poisson of a deformable body, poisson's range.
void check_type_and_elasticity(const BodySpec& s, const BodySpecHost& host, int ntypes)
{
  if (s.surface_type < 1 || s.surface_type > ntypes)
    fail("keyword 'type' is required and must be an atom type between 1 and " +
         std::to_string(ntypes));
  if (s.rigid) return;
  if (!s.have_density || !s.have_youngs || !s.have_poisson)
    fail(std::string("a deformable body needs keywords 'density', 'youngs' and 'poisson'") +
         (host.takes("rigid") ? " (or 'rigid yes')" : ""));
  if (s.material.rho <= 0 || s.material.E <= 0) fail("'density' and 'youngs' must be > 0");
  if (s.material.nu <= -1.0 || s.material.nu >= 0.5) fail("'poisson' must lie in (-1, 0.5)");
  if (s.motion.kind != RigidMotion::None)
    fail("keyword 'motion' needs 'rigid yes' (deformable bodies move by forces and "
         "'prescribed_velocity')");
}

// What a rigid body cannot have; its (unused) mass density.
void check_rigid(BodySpec& s)
{
  if (!s.fixed_sets.empty() || !s.prescribed_velocity.empty() || !s.initial_velocity.empty())
    fail("'fixed', 'velocity' and 'prescribed_velocity' apply to deformable bodies; a rigid "
         "body moves by 'motion'");
  if (!s.have_density) s.material.rho = 1.0; // only used for the (unused) mass of a rigid body
  if (s.have_substeps)
    fail("keyword 'substeps' applies to deformable bodies; a rigid body moves by 'motion' and has "
         "no FE step");
  if (s.material.model != MaterialModel::Elastic || s.fracture_every > 0)
    fail("keywords 'material' and 'fracture' apply to deformable bodies; a rigid body neither "
         "deforms nor breaks");
}

// The material model against fracture, the plane formulation against the dimension.
void check_material(const BodySpec& s, int dimension)
{
  if (s.material.model == MaterialModel::Rankine) {
    try {
      rankine_check(s.material.rankine());
    } catch (const std::exception& e) {
      fail(std::string("keyword 'material rankine': ") + e.what());
    }
  }
  if (s.fracture_every > 0 && !material_model_info(s.material.model).fractures)
    fail("keyword 'fracture' needs a material that fails, e.g. 'material rankine strength FT "
         "fracture_energy GF'");
  if (s.track_exclusion > 0 && s.track_length <= 0)
    fail("keyword 'fracture nodal exclusion' belongs to crack tracking: give 'track L' with it");
  if (s.track_length > 0 && dimension == 3)
    fail("keyword 'fracture nodal track' works on 2D bodies (tri3 / quad4 meshes, 'dimension 2') "
         "only yet; leave it out in 3D");
  // A 3D mesh has no plane formulation: 'plane axisymmetric' there would silently run 3D.
  if (s.have_plane && dimension == 3)
    fail("keyword 'plane' applies to 2D runs ('dimension 2'); this run is 3D (leave out "
         "'plane')");
}

// Criteria out of range or that could never trigger are refused by the core, naming 'erosion';
// erosion_mass needs a body that erodes elements.
void check_erosion(const BodySpec& s)
{
  const ErosionCriteria& c = s.erosion;
  const bool asked = c.plastic_strain != 0 || c.damage != 0 || c.min_dt != 0;
  if (asked) {
    const std::string err = erosion_setup_error(c, s.material, s.rigid);
    if (!err.empty()) fail(keyword_error(err));
  }
  if (s.have_erosion_mass && !asked && s.fracture_every == 0)
    fail("keyword 'erosion_mass' applies to bodies that erode elements ('erosion ...' or "
         "'fracture nodal')");
}

} // namespace

const char* distributed_refusal(const BodySpec& s)
{
  return s.rigid ? "'rigid yes'" : s.track_length > 0 ? "'fracture nodal track'" : nullptr;
}

// A distributed body that breaks or erodes is gathered on rank 0 at its changes (a breaking one
// also at the checks its parts cannot decide alone: while its crack grows, or where a crack band
// is too large to keep in one part), and neither that nor its pieces' contact is timed against
// the replicated body yet (docs/distributed_bodies.md): taken when asked, not by size.
const char* distributed_default_refusal(const BodySpec& s)
{
  if (s.fracture_every > 0) return "'fracture'";
  if (const char* what = distributed_refusal(s)) return what;
  return s.erosion.on() ? "'erosion'" : s.contact_bodies > 0 ? "'contact_bodies yes'" : nullptr;
}

namespace
{

// What a distributed body does not do yet (docs/distributed_bodies.md): each refused by name.
void check_distributed(const BodySpec& s)
{
  if (!s.distributed) return;
  const char* what = distributed_refusal(s);
  if (what)
    fail(std::string("keyword 'parallel distributed' does not work with ") + what +
         " yet; use 'parallel replicated'");
}

// Defaults that depend on other settings, and the keywords they make meaningless.
void resolve_defaults(BodySpec& s)
{
  if (s.compliance_combined < 0) s.compliance_combined = s.rigid ? 1 : 0;
  // Bulk viscosity: on for shock problems (plastic materials, equations of state), off for
  // elastic and Rankine bodies, whose results stay as they were.
  if (s.viscosity_mode > 0 && s.rigid)
    fail("keyword 'bulk_viscosity' applies to deformable bodies; a rigid body does not deform");
  if (s.viscosity_mode < 0)
    s.viscosity_mode =
        !s.rigid && (s.material.plastic_model() || s.material.eos.model != EosModel::Linear);
  s.viscosity.on = s.viscosity_mode > 0;
  // A breaking body's pieces collide unless told otherwise (fragments must not pass through each
  // other); other bodies opt in, as body-body contact costs serial work every step.
  if (s.contact_bodies < 0) s.contact_bodies = s.fracture_every > 0 ? 1 : 0;
  if (s.contact_bodies && s.rigid) fail("keyword 'contact_bodies yes' needs a deformable body");
  if (s.have_contact_balance && s.contact_bodies == 0)
    fail("keyword 'contact_balance' applies to bodies with 'contact_bodies yes'");
  check_erosion(s);
  check_distributed(s);
}

} // namespace

std::string fix_message(const SpecError& e, const std::string& fix_id)
{
  return std::string("fix fem/body") + (e.names_fix() ? " " + fix_id : "") + ": " + e.what();
}

int BodySpec::reaction_group(const std::string& set)
{
  auto it = std::find(reaction_groups.begin(), reaction_groups.end(), set);
  if (it != reaction_groups.end()) return static_cast<int>(it - reaction_groups.begin());
  reaction_groups.push_back(set);
  return static_cast<int>(reaction_groups.size()) - 1;
}

/* ---- SpecReader ---- */

void SpecReader::need(std::size_t n, const std::string& what) const
{
  if (!has(n)) fail("keyword '" + keyword() + "' expects " + what);
}

double SpecReader::number(std::size_t k) const
{
  return spec_number(keyword(), word(k));
}

int SpecReader::whole_number(std::size_t k) const
{
  return spec_whole_number(keyword(), word(k));
}

bool SpecReader::either(const char* first, const char* second)
{
  const std::string expected = std::string(first) + " or " + second;
  need(1, expected);
  const bool is_first = word(1) == first;
  if (!is_first && word(1) != second) fail("keyword '" + keyword() + "' expects " + expected);
  take(2);
  return is_first;
}

std::vector<std::string> SpecReader::rest() const
{
  return std::vector<std::string>(w_.begin() + static_cast<std::ptrdiff_t>(i_ + 1), w_.end());
}

double spec_number(const std::string& keyword, const std::string& word)
{
  const char* w = word.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(w, &end);
  if (end == w || *end != '\0' || errno == ERANGE || !std::isfinite(v))
    fail("keyword '" + keyword + "' expects a finite number, got '" + word + "'");
  return v;
}

int spec_whole_number(const std::string& keyword, const std::string& word)
{
  const char* w = word.c_str();
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(w, &end, 10);
  if (end == w || *end != '\0' || errno == ERANGE || v < INT_MIN || v > INT_MAX)
    fail("keyword '" + keyword + "' expects an integer, got '" + word + "'");
  return static_cast<int>(v);
}

/* ---- parsing ---- */

bool BodySpecHost::takes(const std::string& keyword) const
{
  if (own.count(keyword)) return true;
  if (supported.empty()) return find_keyword(keyword) != nullptr;
  return std::any_of(supported.begin(), supported.end(),
                     [&](const Supported& k) { return k.keyword == keyword; });
}

std::vector<std::string> body_keywords()
{
  std::vector<std::string> names;
  for (const Keyword& k : kKeywords)
    names.push_back(k.keyword);
  return names;
}

BodySpec parse_body_spec(const std::vector<std::string>& words, const BodySpecHost& host)
{
  if (words.size() < 2 || words[0] != "file")
    fail("expected 'fix ID group fem/body file MESH.msh keyword value ...'");
  BodySpec spec;
  spec.mesh_file = words[1];
  std::string prev;
  for (SpecReader r(words, 2); !r.done();) {
    const std::string kw = r.keyword();
    parse_keyword(r, spec, host, prev);
    prev = kw;
  }
  return spec;
}

void check_body_spec(BodySpec& spec, const BodySpecHost& host, int ntypes, int dimension)
{
  check_type_and_elasticity(spec, host, ntypes);
  if (spec.rigid) check_rigid(spec);
  check_material(spec, dimension);
  resolve_defaults(spec);
}

} // namespace fracdem
