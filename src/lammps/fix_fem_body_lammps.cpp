// fix fem/body under LAMMPS: parses the LIGGGHTS adapter's keyword syntax, builds the body through
// the core's fracdem::BodyDriver and drives its step (fracture, erosion, body contact, energy
// file, restart: the driver's) from LAMMPS's Verlet.
// Particle contact: the core's ParticleFacetContact, with the law written in LAMMPS's granular
// syntax (keyword 'contact') and mapped onto the core's ContactMaterial (docs/lammps.md).
#include "fix_fem_body_lammps.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <initializer_list>
#include <limits>
#include <map>
#include <memory>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "group.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "update.h"

#include "io/input_help.h"
#include "mpi_body_host.h"

using namespace LAMMPS_NS;
using namespace FixConst;

namespace
{

const char* const kStyle = "fix fem/body";

const char* const kContactSyntax =
    "'contact granular hertz/material E COR NU damping coeff_restitution|tsuji tangential "
    "mindlin NULL XT MU|linear_nohistory XT 0 [rolling none] [twisting none]' or, with a given "
    "stiffness, 'contact granular hooke|hertz K_N DAMP [damping none|velocity|mass_velocity|"
    "viscoelastic|coeff_restitution|tsuji] tangential linear_history|mindlin K_T XT MU|"
    "linear_nohistory XT MU'";

// Steps between checks that the body is still inside the box (besides every re-neighbouring).
constexpr int kBoxCheckEvery = 100;

// The restitution that the core's Hertz damping must be given to damp as a LAMMPS granular
// damping coefficient D does: both are F_d = -D sqrt(m F_ne / delta) v_n, and the core writes
// D = sqrt(5) |beta| with beta = ln e / sqrt(ln^2 e + pi^2) (2 sqrt(5/6) |beta| sqrt(2 E* a m)
// with F_ne / delta = 4/3 E* a). coeff_restitution: D = sqrt(5) |ln e| / sqrt(ln^2 e + pi^2),
// exactly the core's law for the same e; tsuji: D from Marshall's fit, e' solved for here.
double restitution_for_damping(double D)
{
  const double b = D / std::sqrt(5.0); // |beta| < 1: D < sqrt(5) (tsuji gives D <= 1.8)
  return std::exp(-M_PI * b / std::sqrt(1.0 - b * b));
}

} // namespace

/* ---------------------------------------------------------------------- */

FixFemBodyLammps::FixFemBodyLammps(LAMMPS* lmp, int narg, char** arg) : Fix(lmp, narg, arg)
{
  parse_arguments(narg, arg);
  // Particles meet the body through their radius, mass, spin and torque: the sphere style, also
  // for FE-only bodies, so that a script stays valid when contact is added.
  const bool sphere =
      atom->radius_flag && atom->rmass_flag && atom->omega_flag && atom->torque_flag;
  if (!sphere && law_.on)
    error->all(FLERR,
               "{}: keyword 'contact' needs per-atom radius, rmass, omega and torque: it requires "
               "atom_style sphere (this run has atom_style {})",
               kStyle, atom->atom_style);
  if (!sphere)
    error->all(FLERR,
               "fix fem/body requires atom_style sphere (radius, rmass, omega); this run "
               "has atom_style {}",
               atom->atom_style);

  load_mesh();

  scalar_flag = 1;
  extscalar = 1;
  vector_flag = 1;
  // fracdem::BodyVectorIndex (docs/fix_fem_body.md), 3 reactions per group, BodyVectorTail.
  size_vector = driver_.vector_size();
  extvector = 0;
  global_freq = 1;
  // time_integrate stays 0: this fix integrates FE nodes, never the host's atoms.
  time_depend = 1;
  restart_global = 1;

  if (law_.on) {
    // Tangential history per particle: this fix's own per-atom array, grown, copied (sorting),
    // migrated (exchange) and written to restart files with the atoms through LAMMPS's
    // callbacks.
    create_attribute = 1;
    restart_peratom = 1;
    maxexchange = spec_.history_slots * fracdem::kHistorySlotDoubles;
    grow_arrays(atom->nmax);
    atom->add_callback(Atom::GROW);
    atom->add_callback(Atom::RESTART);
    for (int i = 0; i < atom->nlocal; ++i)
      set_arrays(i);
  }
}

FixFemBodyLammps::~FixFemBodyLammps()
{
  if (law_.on) {
    atom->delete_callback(id, Atom::GROW);
    atom->delete_callback(id, Atom::RESTART);
  }
  memory->destroy(history_);
}

int FixFemBodyLammps::setmask()
{
  return INITIAL_INTEGRATE | POST_FORCE | FINAL_INTEGRATE | PRE_NEIGHBOR;
}

/* ----------------------------------------------------------------------
   argument parsing: fix ID group fem/body file FILE keyword value ...
   The core's keyword table (fracdem::parse_body_spec); the contact law in
   LAMMPS's granular words (keyword 'contact').
------------------------------------------------------------------------- */

namespace
{

// The LIGGGHTS adapter's contact-law keywords: under LAMMPS the law is written after 'contact'.
void refuse_liggghts_law(fracdem::SpecReader& r, fracdem::BodySpec&)
{
  throw fracdem::SpecError(fmt::format("keyword '{}' is the LIGGGHTS adapter's; under LAMMPS the "
                                       "contact law is written in LAMMPS's granular syntax after "
                                       "keyword 'contact': {}",
                                       r.keyword(), kContactSyntax));
}

[[noreturn]] void contact_fail(const std::string& what)
{
  throw fracdem::SpecError("keyword 'contact': " + what);
}

bool one_of(const std::string& word, std::initializer_list<const char*> names)
{
  return std::any_of(names.begin(), names.end(), [&](const char* n) { return word == n; });
}

// Word j after 'contact'; `what` names it when it is missing.
const std::string& contact_word(const fracdem::SpecReader& r, std::size_t j, const char* what)
{
  if (!r.has(j)) contact_fail(fmt::format("expects {} ({})", what, kContactSyntax));
  return r.word(j);
}

double contact_value(const fracdem::SpecReader& r, std::size_t j, const char* what)
{
  const std::string& w = contact_word(r, j, what);
  try {
    return fracdem::spec_number(what, w);
  } catch (const fracdem::SpecError&) {
    contact_fail(fmt::format("{} expects a finite number, got '{}'", what, w));
  }
}

} // namespace

// The core's whole table (the step is the core's BodyDriver, as under LIGGGHTS), but the contact
// law: LAMMPS's granular words after this host's own 'contact'; the LIGGGHTS adapter's law
// keywords (contact_model, tangential) are refused naming it.
void FixFemBodyLammps::parse_arguments(int narg, char** arg)
{
  const std::string units = fracdem::body_units_error(update->unit_style);
  if (!units.empty()) error->all(FLERR, "{}: {}", kStyle, units);
  fracdem::BodySpecHost host;
  host.name = "LAMMPS";
  host.own["contact_model"] = host.own["tangential"] = refuse_liggghts_law;
  host.own["contact"] = [this](fracdem::SpecReader& r, fracdem::BodySpec&) { parse_contact(r); };
  try {
    spec_ = fracdem::parse_body_spec(std::vector<std::string>(arg + 3, arg + narg), host);
    fracdem::check_body_spec(spec_, host, atom->ntypes, domain->dimension);
  } catch (const fracdem::SpecError& e) {
    error->all(FLERR, fracdem::fix_message(e, id));
  }
}

// contact granular NORMAL ... [damping D] [tangential T ...] [rolling none] [twisting none]:
// the words of LAMMPS's pair granular / fix wall/gran for one material, the supported subset.
// What the core's law cannot express is refused by name (SpecError).
void FixFemBodyLammps::parse_contact(fracdem::SpecReader& r)
{
  using Option = std::size_t (FixFemBodyLammps::*)(const fracdem::SpecReader&, std::size_t);
  static const std::map<std::string, Option> options = {
      {"damping", &FixFemBodyLammps::parse_contact_damping},
      {"tangential", &FixFemBodyLammps::parse_contact_tangential},
      {"rolling", &FixFemBodyLammps::parse_contact_none},
      {"twisting", &FixFemBodyLammps::parse_contact_none},
      {"heat", &FixFemBodyLammps::parse_contact_unsupported},
      {"limit_damping", &FixFemBodyLammps::parse_contact_unsupported},
      {"synchronized_verlet", &FixFemBodyLammps::parse_contact_unsupported}};
  if (law_.on) contact_fail("given twice");
  law_.on = true;
  std::size_t j = parse_contact_normal(r);
  bool have_damping = false, have_tangential = false;
  while (r.has(j)) {
    auto it = options.find(r.word(j));
    if (it == options.end()) break; // the next keyword of fix fem/body
    have_damping |= it->first == "damping";
    have_tangential |= it->first == "tangential";
    j = (this->*(it->second))(r, j);
  }
  if (!have_damping && !law_.given_k)
    contact_fail("needs 'damping coeff_restitution' or 'damping tsuji': LAMMPS's default damping "
                 "(viscoelastic, where the second hertz/material value is eta_n0, not a "
                 "restitution) is not supported");
  if (!have_tangential)
    contact_fail(fmt::format("needs a tangential model, as LAMMPS's granular styles do: "
                             "'tangential mindlin NULL XT MU' or 'tangential linear_nohistory XT "
                             "0' ({})",
                             kContactSyntax));
  if (one_of(law_.damping, {"coeff_restitution", "tsuji"}) && (law_.cor <= 0 || law_.cor > 1))
    contact_fail(fmt::format("damping {} needs a coefficient of restitution COR in (0, 1] (the "
                             "normal model's second value), got {}",
                             law_.damping, law_.cor));
  r.take(j);
}

// granular hertz/material E COR NU | hooke K_N DAMP | hertz K_N DAMP (words 1 to 5 or 4 after
// 'contact'); returns the index of the word after the normal model.
std::size_t FixFemBodyLammps::parse_contact_normal(const fracdem::SpecReader& r)
{
  const std::string& style = contact_word(r, 1, "a granular style");
  if (one_of(style, {"hooke", "hooke/history", "hertz/history"}))
    contact_fail(fmt::format("style '{}' (the classic fix wall/gran styles) is not supported: "
                             "write the law with the granular models, {}",
                             style, kContactSyntax));
  if (style != "granular")
    contact_fail(fmt::format("expects 'granular', got '{}' ({})", style, kContactSyntax));
  const std::string& normal = contact_word(r, 2, "a normal model");
  if (one_of(normal, {"dmt", "jkr", "mdr"}))
    contact_fail(fmt::format("normal model '{}' is not supported: the core has no adhesion or "
                             "plastic contact; use 'hertz/material E COR NU', 'hooke K_N DAMP' or "
                             "'hertz K_N DAMP'",
                             normal));
  if (one_of(normal, {"hooke", "hertz"})) return parse_given_stiffness(r, normal);
  if (normal != "hertz/material")
    contact_fail(
        fmt::format("unknown normal model '{}' (supported: hertz/material, hooke, hertz)", normal));
  law_.E = contact_value(r, 3, "hertz/material E");
  law_.cor = contact_value(r, 4, "hertz/material COR (the damping coefficient)");
  law_.nu = contact_value(r, 5, "hertz/material NU");
  if (law_.E <= 0) contact_fail("hertz/material E must be > 0");
  if (law_.nu <= -1.0 || law_.nu >= 0.5) contact_fail("hertz/material NU must lie in (-1, 0.5)");
  return 6;
}

// hooke|hertz K_N DAMP: a given stiffness (F_ne = K_N delta | K_N a delta) and the damping
// model's coefficient (a restitution for coeff_restitution and tsuji).
std::size_t FixFemBodyLammps::parse_given_stiffness(const fracdem::SpecReader& r,
                                                    const std::string& normal)
{
  law_.given_k = true;
  law_.hooke = normal == "hooke";
  law_.kn = contact_value(r, 3, law_.hooke ? "hooke K_N" : "hertz K_N");
  law_.cor = contact_value(r, 4, law_.hooke ? "hooke DAMP" : "hertz DAMP");
  if (law_.kn <= 0) contact_fail(fmt::format("{} K_N must be > 0, got {}", normal, law_.kn));
  if (law_.cor < 0) contact_fail(fmt::format("{} DAMP must be >= 0, got {}", normal, law_.cor));
  return 5;
}

// damping none|velocity|mass_velocity|viscoelastic|coeff_restitution|tsuji (hertz/material:
// the last two only); returns the index after it.
std::size_t FixFemBodyLammps::parse_contact_damping(const fracdem::SpecReader& r, std::size_t j)
{
  const std::string& d = contact_word(r, j + 1, "a damping model");
  if (d == "mdr")
    contact_fail("damping model 'mdr' is not supported: it belongs to the mdr normal model");
  if (!one_of(d,
              {"none", "velocity", "mass_velocity", "viscoelastic", "coeff_restitution", "tsuji"}))
    contact_fail(fmt::format("unknown damping model '{}' (supported: none velocity mass_velocity "
                             "viscoelastic coeff_restitution tsuji)",
                             d));
  if (!law_.given_k && !one_of(d, {"coeff_restitution", "tsuji"}))
    contact_fail(fmt::format("damping model '{}' is not supported with hertz/material: the core's "
                             "damping force there is D sqrt(m F_ne / delta) v_n (LIGGGHTS's), as "
                             "LAMMPS's coeff_restitution and tsuji are; use 'damping "
                             "coeff_restitution' or 'damping tsuji' (every model is supported "
                             "with a given stiffness, hooke|hertz K_N DAMP)",
                             d));
  law_.damping = d;
  law_.tsuji = d == "tsuji";
  return j + 2;
}

// tangential mindlin NULL XT MU | linear_nohistory XT 0 (hertz/material); linear_history|mindlin
// K_T XT MU | linear_nohistory XT MU (hooke|hertz K_N DAMP); returns the index after it.
std::size_t FixFemBodyLammps::parse_contact_tangential(const fracdem::SpecReader& r, std::size_t j)
{
  const std::string& t = contact_word(r, j + 1, "a tangential model");
  if (t == "mindlin" || (t == "linear_history" && law_.given_k)) {
    const std::string& k = contact_word(r, j + 2, "tangential K_T");
    if (law_.given_k) {
      if (k == "NULL")
        contact_fail(fmt::format("tangential {} K_T = NULL takes the stiffness from the "
                                 "material (hertz/material); with {} K_N DAMP give K_T",
                                 t, law_.hooke ? "hooke" : "hertz"));
      law_.kt = contact_value(r, j + 2, ("tangential " + t + " K_T").c_str());
      law_.kt_times_a = t == "mindlin"; // LAMMPS's mindlin: k_t a
      // a sliding contact keeps the spring F / K_T
      if (law_.kt <= 0)
        contact_fail(fmt::format("tangential {} K_T must be > 0, got {}", t, law_.kt));
    } else if (k != "NULL") {
      contact_fail(fmt::format("tangential mindlin k_t = {} is not supported with "
                               "hertz/material: the core's tangential stiffness is 8 G* a from "
                               "the materials; write NULL",
                               k));
    }
    law_.history = true;
    const std::string xt = "tangential " + t + " XT", mu = "tangential " + t + " MU";
    law_.xt = contact_value(r, j + 3, xt.c_str());
    law_.mu = contact_value(r, j + 4, mu.c_str());
    j += 5;
  } else if (t == "linear_nohistory") {
    law_.history = false;
    law_.xt = contact_value(r, j + 2, "tangential linear_nohistory XT");
    law_.mu = contact_value(r, j + 3, "tangential linear_nohistory MU");
    if (law_.mu != 0 && !law_.given_k)
      contact_fail("tangential linear_nohistory is supported frictionless only (MU = 0) with "
                   "hertz/material: with friction write 'tangential mindlin NULL XT MU'");
    j += 4;
  } else if (one_of(t, {"linear_history", "linear_history_classic", "mindlin_classic",
                        "mindlin/force", "mindlin_rescale", "mindlin_rescale/force"})) {
    contact_fail(fmt::format("tangential model '{}' is not supported{}: the core's tangential "
                             "history is a displacement spring (Coulomb-capped); use 'tangential "
                             "mindlin NULL XT MU' with hertz/material, 'linear_history|mindlin "
                             "K_T XT MU' with hooke|hertz K_N DAMP",
                             t, law_.given_k ? "" : " with hertz/material"));
  } else {
    contact_fail(fmt::format("unknown tangential model '{}' (supported: mindlin, linear_history, "
                             "linear_nohistory; {})",
                             t, kContactSyntax));
  }
  if (law_.xt < 0 || law_.mu < 0) contact_fail("tangential XT and MU must be >= 0");
  return j;
}

// rolling none | twisting none: the core has no rolling or twisting resistance.
std::size_t FixFemBodyLammps::parse_contact_none(const fracdem::SpecReader& r, std::size_t j)
{
  const std::string& kw = r.word(j);
  const std::string& m = contact_word(r, j + 1, "a model");
  if (m != "none")
    contact_fail(fmt::format("{} model '{}' is not supported (the core has no {} resistance): "
                             "leave it out or write '{} none'",
                             kw, m, kw, kw));
  return j + 2;
}

std::size_t FixFemBodyLammps::parse_contact_unsupported(const fracdem::SpecReader& r, std::size_t j)
{
  contact_fail(fmt::format("option '{}' is not supported", r.word(j)));
}

// The core's ContactMaterial for the law: E* and G* from the particle's material (hertz/material
// E, NU) and, with 'compliance combined', the body's own youngs/poisson; the restitution that
// gives the core's damping the coefficient of LAMMPS's damping model. All particle types share it.
void FixFemBodyLammps::contact_setup()
{
  if (law_.given_k) {
    contact_setup_given_k();
    return;
  }
  // LAMMPS 22 Jul 2025's tsuji coefficient (later versions multiply it by sqrt(2), which the
  // version check at load keeps out); tests/lammps/test_contact_hertz.py checks it.
  const double D = law_.tsuji ? fracdem::tsuji_damping(law_.cor) : 0.0;
  const double e = law_.tsuji ? restitution_for_damping(D) : law_.cor;
  const double Eb = combined() ? spec_.material.E : 0.0, nub = combined() ? spec_.material.nu : 0.0;
  contact_material_ = fracdem::mix_materials(law_.E, law_.nu, Eb, nub, e, law_.mu, 1.0,
                                             fracdem::NormalModel::Hertz, law_.history);
  // The core ties the tangential damping to the normal one (LIGGGHTS): eta_t / eta_n =
  // sqrt(8 G* a / (2 E* a)). LAMMPS's XT is that ratio; it is a free input there, not here.
  const double xt_core = 2.0 * std::sqrt(contact_material_.Geff / contact_material_.Yeff);
  if (law_.history && law_.mu > 0 && std::fabs(law_.xt - xt_core) > 1e-3 * xt_core)
    error->all(FLERR,
               "{}: keyword 'contact': tangential mindlin XT = {} is not supported: the core's "
               "tangential damping is tied to its normal damping as in LIGGGHTS, XT = 2 "
               "sqrt(G*/E*) = {:.6f} for this particle material{}; write that value (any XT is "
               "accepted with MU = 0)",
               kStyle, law_.xt, xt_core, combined() ? " and body" : "");
  log_line(fmt::format("fix fem/body {}: contact hertz/material E* {:.6g} G* {:.6g} ({}), damping "
                       "{} COR {:g}{}, tangential {} XT {:.6g} MU {:g}\n",
                       id, contact_material_.Yeff, contact_material_.Geff,
                       combined() ? "particle and body compliance"
                                  : "particle compliance; the body's from its elements",
                       law_.tsuji ? "tsuji" : "coeff_restitution", law_.cor,
                       law_.tsuji ? fmt::format(" (core restitution {:.6g})", e) : "",
                       law_.history ? "mindlin" : "linear_nohistory", law_.history ? xt_core : 0.0,
                       law_.mu));
}

// The core's law with a given stiffness: LAMMPS's hooke|hertz K_N DAMP, damping and tangential
// coefficients as LAMMPS's granular models define them (fracdem::given_stiffness_law).
void FixFemBodyLammps::contact_setup_given_k()
{
  static const std::map<std::string, fracdem::DampingModel> damping = {
      {"none", fracdem::DampingModel::None},
      {"velocity", fracdem::DampingModel::Velocity},
      {"mass_velocity", fracdem::DampingModel::MassVelocity},
      {"viscoelastic", fracdem::DampingModel::Viscoelastic},
      {"coeff_restitution", fracdem::DampingModel::CoeffRestitution},
      {"tsuji", fracdem::DampingModel::Tsuji}};
  const auto model = law_.hooke ? fracdem::NormalModel::Hooke : fracdem::NormalModel::Hertz;
  contact_material_ =
      fracdem::given_stiffness_law(model, law_.kn, law_.cor, damping.at(law_.damping), law_.kt,
                                   law_.kt_times_a, law_.xt, law_.mu, law_.history);
  const std::string tangential =
      !law_.history
          ? "linear_nohistory"
          : fmt::format("{} K_T {:g}", law_.kt_times_a ? "mindlin" : "linear_history", law_.kt);
  log_line(fmt::format("fix fem/body {}: contact {} K_N {:g} DAMP {:g}, damping {} (coefficient "
                       "{:.6g}), tangential {} XT {:g} MU {:g}\n",
                       id, law_.hooke ? "hooke" : "hertz", law_.kn, law_.cor, law_.damping,
                       contact_material_.given.c, tangential, law_.xt, law_.mu));
}

/* ---------------------------------------------------------------------- */

void FixFemBodyLammps::log_line(const std::string& line) const
{
  if (comm->me == 0) utils::logmesg(lmp, line);
}

// The core's BodyDriver gets the MPI services over world and this host's output and errors.
fracdem::BodyHost FixFemBodyLammps::host() const
{
  fracdem::BodyHost h;
  fracdem::add_mpi_services(h, world);
  LAMMPS* host = lmp;
  h.print = [host](const std::string& line, bool to_screen, bool to_log) {
    if (to_screen && host->screen) fputs(line.c_str(), host->screen);
    if (to_log && host->logfile) fputs(line.c_str(), host->logfile);
  };
  Error* err = error;
  h.warning = [err](const std::string& text) { err->warning(FLERR, text); };
  h.error_all = [err](const std::string& text) { err->all(FLERR, text); };
  h.error_one = [err](const std::string& text) { err->one(FLERR, text); };
  return h;
}

void FixFemBodyLammps::load_mesh()
{
  driver_.attach(spec_, id, host());
  try {
    driver_.build(domain->dimension);
  } catch (const fracdem::SpecError& e) {
    error->all(FLERR, fracdem::fix_message(e, id));
  }
  log_line(driver_.describe() +
           (law_.on ? " (LAMMPS host)\n" : " (LAMMPS host, no particle contact)\n"));
  if (law_.on) contact_setup();
  check_in_box("as placed");
}

/* ---------------------------------------------------------------------- */

void FixFemBodyLammps::init()
{
  if (law_.on) {
    fracdem::ParticleFacetOptions opt;
    opt.model = fracdem::NormalModel::Hertz;
    opt.tangential_history = law_.history;
    // A deformable body carrying its own compliance: Hertz's contact radius from the total
    // approach and the reaction spread as Hertz pressure (as the LIGGGHTS adapter).
    opt.hertz_patch = !spec_.rigid && !combined();
    opt.buffer = spec_.buffer >= 0 ? spec_.buffer : neighbor->skin;
    driver_.configure_contact(
        opt, std::vector<fracdem::ContactMaterial>(atom->ntypes + 1, contact_material_));
  }
  if (spec_.contact_bodies > 0) find_contact_partners();
  const std::string failed = driver_.open_energy_file();
  if (!failed.empty()) error->one(FLERR, failed);
  driver_.check_time_step(update->dt);
}

void FixFemBodyLammps::reset_dt()
{
  driver_.check_time_step(update->dt);
}

// This body computes the contact with its own pieces and every later fix fem/body with
// contact_bodies yes (as the LIGGGHTS adapter). LAMMPS has no per-type friction table: the
// friction between bodies is the MU of this body's keyword 'contact' (0 without it).
void FixFemBodyLammps::find_contact_partners()
{
  std::vector<fracdem::BodyDriver*> later, earlier;
  bool after = false;
  for (int i = 0; i < modify->nfix; ++i) {
    auto* other = dynamic_cast<FixFemBodyLammps*>(modify->fix[i]);
    if (other == this)
      after = true;
    else if (other && other->spec_.contact_bodies > 0)
      (after ? later : earlier).push_back(&other->driver_);
  }
  const double mu = law_.on ? law_.mu : 0.0;
  driver_.set_partners(later, earlier, [mu](int, int) { return mu; });
}

// The acceleration of every fix gravity (LAMMPS's FixGravity::extract("gvec")), read at set-up:
// fix gravity sets it in its own init(), which may run after this fix's.
void FixFemBodyLammps::read_gravity()
{
  double g[3] = {0, 0, 0};
  if (spec_.apply_gravity) {
    for (Fix* f : modify->get_fix_by_style("^gravity")) {
      int dim = 0;
      const auto* gvec = static_cast<const double*>(f->extract("gvec", dim));
      if (!gvec || dim != 1)
        error->all(FLERR, "{} {}: cannot read the acceleration of fix {} (style {})", kStyle, id,
                   f->id, f->style);
      for (int d = 0; d < 3; ++d)
        g[d] += gvec[d];
    }
  }
  driver_.set_gravity(g);
}

void FixFemBodyLammps::setup(int /*vflag*/)
{
  driver_.start_run();
  driver_.particles_regrouped();
  read_gravity();
  check_in_box("at the start of the run"); // restart, change_box and earlier runs move it
  if (law_.on) {
    driver_.contact().invalidate_search();
  } else if (!warned_no_contact_ && group->count(igroup) > 0) {
    warned_no_contact_ = true;
    if (comm->me == 0)
      error->warning(FLERR,
                     "fix fem/body {}: group '{}' has particles but the fix has no keyword "
                     "'contact': they pass through the body (add 'contact granular "
                     "hertz/material ...')",
                     id, group->names[igroup]);
  }
  compute_forces();
  driver_.log_memory();
  driver_.write_energy_row_if_due(update->ntimestep);
}

// Atoms change rank and index when LAMMPS re-neighbours, and particles outside the box are
// dropped then: the search is rebuilt and the body checked.
void FixFemBodyLammps::pre_neighbor()
{
  driver_.particles_regrouped(); // a distributed body exchanges its particle boxes
  driver_.contact().invalidate_search();
  check_in_box(nullptr);
}

/* ----------------------------------------------------------------------
   velocity Verlet, in step with the host: half kick + drift here,
   forces in post_force, second half kick in final_integrate.
------------------------------------------------------------------------- */

void FixFemBodyLammps::initial_integrate(int /*vflag*/)
{
  driver_.begin_step(update->dt);
  if (update->ntimestep % kBoxCheckEvery == 0) check_in_box(nullptr);
}

void FixFemBodyLammps::post_force(int /*vflag*/)
{
  compute_forces();
}

// Second half kick, fracture check and energy row (the driver's).
void FixFemBodyLammps::final_integrate()
{
  driver_.end_step(update->ntimestep, update->dt);
}

fracdem::ParticleArrays FixFemBodyLammps::particle_arrays() const
{
  fracdem::ParticleArrays p;
  p.n = atom->nlocal;
  p.x = atom->x;
  p.v = atom->v;
  p.omega = atom->omega;
  p.f = atom->f;
  p.torque = atom->torque;
  p.radius = atom->radius;
  p.rmass = atom->rmass;
  p.type = atom->type;
  p.mask = atom->mask;
  p.groupbit = groupbit;
  // In 2D the z period is the slab thickness, never a direction of contact.
  for (int d = 0; d < domain->dimension; ++d)
    if (domain->periodicity[d]) p.period[d] = domain->prd[d];
  p.history = history_;
  p.slots = spec_.history_slots;
  return p;
}

// The driver's force evaluation: internal forces of this rank's elements, body-body contact,
// contact of this rank's particles (owned atoms: the body is replicated, so no ghosts are
// needed), one reduction, then the body finishes (gravity, reactions, work).
void FixFemBodyLammps::compute_forces()
{
  const fracdem::ParticleArrays particles = law_.on ? particle_arrays() : fracdem::ParticleArrays{};
  // A distributed body in a run without particles exchanges nothing for contact.
  const bool none = !law_.on || (driver_.distributed() && atom->natoms == 0);
  driver_.compute_forces(none ? nullptr : &particles, update->ntimestep, update->dt,
                         update->setupflag == 0);
}

/* ----------------------------------------------------------------------
   the body in the simulation box (as in the LIGGGHTS adapter)
------------------------------------------------------------------------- */

// The body must stay where particles can reach it (fracdem::body_box_violation says why).
std::string FixFemBodyLammps::box_violation() const
{
  fracdem::HostBox box;
  const double* blo = domain->triclinic ? domain->boxlo_bound : domain->boxlo;
  const double* bhi = domain->triclinic ? domain->boxhi_bound : domain->boxhi;
  for (int d = 0; d < 3; ++d) {
    box.lo[d] = blo[d];
    box.hi[d] = bhi[d];
    box.periodic[d] = domain->periodicity[d];
    for (int side = 0; side < 2; ++side)
      box.fixed[d][side] = domain->boundary[d][side] == 1; // 2, 3: shrink-wrapped
  }
  box.dimension = domain->dimension;
  box.slack = spec_.buffer >= 0 ? spec_.buffer : neighbor->skin;
  return fracdem::body_box_violation(driver_.contact().facets(), body().positions().data(), box);
}

// A body placed outside, or a rigid body outside (carried there by its prescribed motion, or
// left there by 'change_box'), is an input mistake: refused. A deformable body that gets out by
// its own dynamics is warned about once: only the part outside is out of the particles' reach.
// when: "as placed" (fix command), "at the start of the run", or nullptr: at this step.
void FixFemBodyLammps::check_in_box(const char* when)
{
  const bool placed = when && !strcmp(when, "as placed");
  if (!placed && !spec_.rigid && warned_outside_) return;
  const std::string where = box_violation();
  if (where.empty()) return;
  std::string msg =
      fmt::format("{} {}: mesh '{}' {}: ", kStyle, id, spec_.mesh_file,
                  when ? std::string(when) : fmt::format("at step {}", update->ntimestep));
  // A distributed body's rank sees its own part only: it stops the run by itself.
  auto stop = [this](const std::string& text) {
    if (driver_.distributed()) error->one(FLERR, text);
    error->all(FLERR, text);
  };
  if (placed) stop(msg + where + " (keywords 'move', 'scale', 'rotate' place it)");
  if (spec_.rigid) {
    if (spec_.motion.kind != fracdem::RigidMotion::None)
      msg += "its prescribed 'motion' has carried it out of the box: ";
    stop(msg + where);
  }
  warned_outside_ = true;
  if (comm->me == 0 || driver_.distributed())
    error->warning(FLERR, msg + "its nodes have moved out of the box: " + where +
                              " (warned once; the run goes on)");
}

/* ---------------------------------------------------------------------- */

double FixFemBodyLammps::compute_scalar()
{
  return driver_.scalar();
}

// The core's entries of the global vector, the reactions and the erosion / shield tail.
double FixFemBodyLammps::compute_vector(int i)
{
  return driver_.vector_entry(i);
}

/* ----------------------------------------------------------------------
   restart: the core's record (fracdem::BodyDriver::restart_record), the
   same bytes as the LIGGGHTS adapter writes; the mesh is re-read from the
   same file when the input re-creates the fix
------------------------------------------------------------------------- */

void FixFemBodyLammps::write_restart(FILE* fp)
{
  driver_.write_restart(fp); // every rank: a distributed body gathers its parts
}

void FixFemBodyLammps::restart(char* raw)
{
  driver_.read_restart(reinterpret_cast<const double*>(raw));
}

/* ----------------------------------------------------------------------
   per-atom tangential history (with keyword 'contact')
------------------------------------------------------------------------- */

void FixFemBodyLammps::grow_arrays(int nmax)
{
  memory->grow(history_, nmax, spec_.history_slots * fracdem::kHistorySlotDoubles,
               "fem/body:history");
}

void FixFemBodyLammps::copy_arrays(int i, int j, int /*delflag*/)
{
  std::memcpy(history_[j], history_[i],
              sizeof(double) * spec_.history_slots * fracdem::kHistorySlotDoubles);
}

void FixFemBodyLammps::set_arrays(int i)
{
  std::fill_n(history_[i], spec_.history_slots * fracdem::kHistorySlotDoubles, 0.0);
  fracdem::clear_history_row(history_[i], spec_.history_slots);
}

int FixFemBodyLammps::pack_exchange(int i, double* buf)
{
  const int n = spec_.history_slots * fracdem::kHistorySlotDoubles;
  std::memcpy(buf, history_[i], sizeof(double) * n);
  return n;
}

int FixFemBodyLammps::unpack_exchange(int nlocal, double* buf)
{
  const int n = spec_.history_slots * fracdem::kHistorySlotDoubles;
  std::memcpy(history_[nlocal], buf, sizeof(double) * n);
  return n;
}

// Per-atom history in a restart file (with keyword 'contact'): its length, then the slots.
int FixFemBodyLammps::pack_restart(int i, double* buf)
{
  const int n = spec_.history_slots * fracdem::kHistorySlotDoubles;
  buf[0] = n + 1;
  std::memcpy(buf + 1, history_[i], sizeof(double) * n);
  return n + 1;
}

void FixFemBodyLammps::unpack_restart(int nlocal, int nth)
{
  double** extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; ++k)
    m += static_cast<int>(extra[nlocal][m]);
  const int n = static_cast<int>(extra[nlocal][m]) - 1;
  if (n != spec_.history_slots * fracdem::kHistorySlotDoubles) {
    set_arrays(nlocal); // written with another history_slots: the contacts start afresh
    return;
  }
  std::memcpy(history_[nlocal], &extra[nlocal][m + 1], sizeof(double) * n);
}

int FixFemBodyLammps::size_restart(int)
{
  return spec_.history_slots * fracdem::kHistorySlotDoubles + 1;
}

int FixFemBodyLammps::maxsize_restart()
{
  return spec_.history_slots * fracdem::kHistorySlotDoubles + 1;
}

// The body (replicated on every rank), its contact structures and the per-particle history.
double FixFemBodyLammps::memory_usage()
{
  double bytes = static_cast<double>(driver_.memory_bytes());
  if (law_.on)
    bytes += static_cast<double>(atom->nmax) * spec_.history_slots * fracdem::kHistorySlotDoubles *
             sizeof(double);
  return bytes;
}
