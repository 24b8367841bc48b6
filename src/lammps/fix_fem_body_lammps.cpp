// fix fem/body under LAMMPS: parses the LIGGGHTS adapter's keyword syntax (the supported part),
// builds a fracdem::Body from a Gmsh mesh and drives its explicit update from LAMMPS's Verlet.
// Particle contact: the core's ParticleFacetContact, with the law written in LAMMPS's granular
// syntax (keyword 'contact') and mapped onto the core's ContactMaterial (docs/lammps.md).
#include "fix_fem_body_lammps.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "group.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "update.h"

#include "fem/body_motion.h"
#include "fem/node_split.h"
#include "io/gmsh_reader.h"
#include "materials/material_table.h"

using namespace LAMMPS_NS;
using namespace FixConst;

namespace
{

const char* const kStyle = "fix fem/body";

const std::map<std::string, fracdem::Kinematics> kKinematicsTable = {
    {"elastic", fracdem::Kinematics::SmallStrain},
    {"corotational", fracdem::Kinematics::Corotational},
};
const std::map<std::string, fracdem::PlaneMode> kPlaneModeTable = {
    {"strain", fracdem::PlaneMode::PlaneStrain},
    {"axisymmetric", fracdem::PlaneMode::Axisymmetric},
    {"stress", fracdem::PlaneMode::PlaneStress},
};

// Keywords of docs/fix_fem_body.md that this preview does not implement yet: refused by name, so
// that a LIGGGHTS input never runs silently without them.
const char* const kNotYetSupported[] = {
    "rigid", "motion", "eos", "fracture", "energy_file", "contact_bodies", "contact_penalty"};
// The LIGGGHTS adapter's contact-law keywords: under LAMMPS the law is written after 'contact'.
const char* const kLiggghtsLawKeywords[] = {"contact_model", "tangential"};

const char* const kSupported = "type density youngs poisson model material(elastic) plane "
                               "thickness fixed velocity prescribed_velocity scale move rotate "
                               "dt_check gravity contact compliance buffer history_slots";

const char* const kContactSyntax =
    "'contact granular hertz/material E COR NU damping coeff_restitution|tsuji tangential "
    "mindlin NULL XT MU|linear_nohistory XT 0 [rolling none] [twisting none]'";

// Steps between checks that the body is still inside the box (besides every re-neighbouring).
constexpr int kBoxCheckEvery = 100;

// Global vector layout: the indices of the LIGGGHTS adapter (docs/fix_fem_body.md). Contact
// entries stay 0 until particle contact is supported here.
enum VectorIndex {
  kKinetic = 0,
  kStrain,
  kExternalWork,
  kContactWork,
  kNodes,
  kElements,
  kContacts,
  kForceX,
  kForceY,
  kForceZ,
  kStableDt,
  kSearchRebuilds,
  kMomentumX,
  kMomentumY,
  kMomentumZ,
  kDissipated,
  kSplitNodes,
  kFragments,
  kBoundaryWork,
  kVectorSize
};

// LAMMPS's 'damping tsuji' coefficient for a coefficient of restitution: Marshall 2009, eq. 53
// (GranSubModDampingTsuji::init of LAMMPS 22 Jul 2025; later LAMMPS versions multiply it by
// sqrt(2), which the version check at load keeps out). tests/lammps/test_contact_hertz.py checks
// it against LAMMPS's own fix wall/gran.
double tsuji_coefficient(double cor)
{
  const double p[] = {1.2728, -4.2783, 11.087, -22.348, 27.467, -18.022, 4.8218};
  double d = 0, c = 1;
  for (double a : p) {
    d += a * c;
    c *= cor;
  }
  return d;
}

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
  size_vector = kVectorSize + 3 * static_cast<int>(reaction_groups_.size());
  extvector = 0;
  global_freq = 1;
  // time_integrate stays 0: this fix integrates FE nodes, never the host's atoms.
  time_depend = 1;

  if (law_.on) {
    // Tangential history per particle: this fix's own per-atom array, grown, copied (sorting)
    // and migrated (exchange) with the atoms through LAMMPS's callbacks.
    create_attribute = 1;
    maxexchange = nslots_ * fracdem::kHistorySlotDoubles;
    grow_arrays(atom->nmax);
    atom->add_callback(Atom::GROW);
    for (int i = 0; i < atom->nlocal; ++i)
      set_arrays(i);
  }
}

FixFemBodyLammps::~FixFemBodyLammps()
{
  if (law_.on) atom->delete_callback(id, Atom::GROW);
  memory->destroy(history_);
}

int FixFemBodyLammps::setmask()
{
  return INITIAL_INTEGRATE | POST_FORCE | FINAL_INTEGRATE | PRE_NEIGHBOR;
}

/* ----------------------------------------------------------------------
   argument parsing: fix ID group fem/body file FILE keyword value ...
------------------------------------------------------------------------- */

double FixFemBodyLammps::number(const char* keyword, const char* word)
{
  char* end = nullptr;
  errno = 0;
  const double v = strtod(word, &end);
  if (end == word || *end != '\0' || errno == ERANGE || !std::isfinite(v))
    error->all(FLERR, "{}: keyword '{}' expects a finite number, got '{}'", kStyle, keyword, word);
  return v;
}

int FixFemBodyLammps::whole_number(const char* keyword, const char* word)
{
  char* end = nullptr;
  errno = 0;
  const long long v = strtoll(word, &end, 10);
  if (end == word || *end != '\0' || errno == ERANGE || v < INT_MIN || v > INT_MAX)
    error->all(FLERR, "{}: keyword '{}' expects an integer, got '{}'", kStyle, keyword, word);
  return static_cast<int>(v);
}

void FixFemBodyLammps::parse_arguments(int narg, char** arg)
{
  auto need = [&](int iarg, int n, const char* keyword, const char* what) {
    if (iarg + n >= narg) error->all(FLERR, "{}: keyword '{}' expects {}", kStyle, keyword, what);
  };
  auto either = [&](int iarg, const char* keyword, const char* first, const char* second) {
    need(iarg, 1, keyword, (std::string(first) + " or " + second).c_str());
    if (!strcmp(arg[iarg + 1], first)) return true;
    if (strcmp(arg[iarg + 1], second) != 0)
      error->all(FLERR, "{}: keyword '{}' expects {} or {}", kStyle, keyword, first, second);
    return false;
  };
  auto lookup = [&](const auto& table, const char* keyword, const char* value) {
    auto it = table.find(value);
    if (it == table.end()) {
      std::string expected;
      for (const auto& kv : table)
        expected += " " + kv.first;
      error->all(FLERR, "{}: keyword '{}' got '{}', expected one of:{}", kStyle, keyword, value,
                 expected);
    }
    return it->second;
  };
  if (narg < 5 || strcmp(arg[3], "file") != 0)
    error->all(FLERR,
               "fix fem/body: expected 'fix ID group fem/body file MESH.msh keyword value ...'");
  mesh_file_ = arg[4];

  int iarg = 5;
  while (iarg < narg) {
    const char* kw = arg[iarg];
    if (!strcmp(kw, "type")) {
      need(iarg, 1, kw, "an atom type");
      surface_type_ = whole_number(kw, arg[iarg + 1]);
      iarg += 2;
    } else if (!strcmp(kw, "density")) {
      need(iarg, 1, kw, "a value");
      material_.rho = number(kw, arg[iarg + 1]);
      have_density_ = true;
      iarg += 2;
    } else if (!strcmp(kw, "youngs")) {
      need(iarg, 1, kw, "a value");
      material_.E = number(kw, arg[iarg + 1]);
      have_youngs_ = true;
      iarg += 2;
    } else if (!strcmp(kw, "poisson")) {
      need(iarg, 1, kw, "a value");
      material_.nu = number(kw, arg[iarg + 1]);
      have_poisson_ = true;
      iarg += 2;
    } else if (!strcmp(kw, "model")) {
      need(iarg, 1, kw, "elastic or corotational");
      material_.kinematics = lookup(kKinematicsTable, kw, arg[iarg + 1]);
      iarg += 2;
    } else if (!strcmp(kw, "material")) {
      // Only the default model; the others (rankine, j2, ...) come with fracture/history support.
      need(iarg, 1, kw, "elastic");
      if (strcmp(arg[iarg + 1], "elastic") != 0)
        error->all(FLERR,
                   "{}: keyword 'material {}' is not yet supported under LAMMPS (only "
                   "'material elastic')",
                   kStyle, arg[iarg + 1]);
      iarg += 2;
    } else if (!strcmp(kw, "plane")) {
      need(iarg, 1, kw, "strain, stress or axisymmetric");
      material_.plane = lookup(kPlaneModeTable, kw, arg[iarg + 1]);
      have_plane_ = true;
      iarg += 2;
    } else if (!strcmp(kw, "thickness")) {
      need(iarg, 1, kw, "a value");
      material_.thickness = number(kw, arg[iarg + 1]);
      if (material_.thickness <= 0)
        error->all(FLERR, "{}: keyword 'thickness' must be > 0", kStyle);
      iarg += 2;
    } else if (!strcmp(kw, "fixed")) {
      need(iarg, 1, kw, "a mesh physical group name [x] [y] [z]");
      FixedSpec f{arg[iarg + 1], 0, reaction_group(arg[iarg + 1])};
      iarg += 2;
      for (; iarg < narg && strlen(arg[iarg]) == 1 && strchr("xyz", arg[iarg][0]); ++iarg)
        f.mask |= 1 << (arg[iarg][0] - 'x');
      if (f.mask == 0) f.mask = 7; // no component named: all
      fixed_sets_.push_back(f);
    } else if (!strcmp(kw, "velocity") || !strcmp(kw, "prescribed_velocity")) {
      need(iarg, 4, kw, "GROUP vx vy vz");
      NodeVelocitySpec s;
      s.set = arg[iarg + 1];
      for (int d = 0; d < 3; ++d)
        s.v[d] = number(kw, arg[iarg + 2 + d]);
      iarg += 5;
      if (kw[0] == 'v') {
        initial_velocity_.push_back(s);
        continue;
      }
      s.group = reaction_group(s.set);
      if (iarg + 1 < narg && !strcmp(arg[iarg], "ramp")) {
        s.ramp = number("prescribed_velocity ... ramp", arg[iarg + 1]);
        if (s.ramp <= 0)
          error->all(FLERR, "{}: keyword 'prescribed_velocity ... ramp T' needs T > 0", kStyle);
        iarg += 2;
      }
      prescribed_velocity_.push_back(s);
    } else if (!strcmp(kw, "scale")) {
      need(iarg, 1, kw, "a factor");
      fracdem::MeshTransform t{fracdem::MeshTransform::Scale, {number(kw, arg[iarg + 1]), 0, 0, 0}};
      if (t.a[0] <= 0) error->all(FLERR, "{}: keyword 'scale' must be > 0", kStyle);
      transforms_.push_back(t);
      iarg += 2;
    } else if (!strcmp(kw, "move")) {
      need(iarg, 3, kw, "dx dy dz");
      fracdem::MeshTransform t{fracdem::MeshTransform::Move, {0, 0, 0, 0}};
      for (int d = 0; d < 3; ++d)
        t.a[d] = number(kw, arg[iarg + 1 + d]);
      transforms_.push_back(t);
      iarg += 4;
    } else if (!strcmp(kw, "rotate")) {
      need(iarg, 6, kw, "axis ax ay az angle DEGREES");
      if (strcmp(arg[iarg + 1], "axis") || strcmp(arg[iarg + 5], "angle"))
        error->all(FLERR, "{}: keyword 'rotate' expects 'axis ax ay az angle DEGREES'", kStyle);
      fracdem::MeshTransform t{fracdem::MeshTransform::Rotate, {0, 0, 0, 0}};
      for (int d = 0; d < 3; ++d)
        t.a[d] = number(kw, arg[iarg + 2 + d]);
      t.a[3] = number(kw, arg[iarg + 6]) * M_PI / 180.0;
      if (!fracdem::valid_axis(t.a))
        error->all(FLERR,
                   "{}: keyword 'rotate' got axis {} {} {}, expected a non-zero axis "
                   "direction ax ay az",
                   kStyle, arg[iarg + 2], arg[iarg + 3], arg[iarg + 4]);
      transforms_.push_back(t);
      iarg += 7;
    } else if (!strcmp(kw, "dt_check")) {
      dt_check_error_ = either(iarg, kw, "error", "warn");
      iarg += 2;
    } else if (!strcmp(kw, "gravity")) {
      apply_gravity_ = either(iarg, kw, "yes", "no");
      iarg += 2;
    } else if (!strcmp(kw, "contact")) {
      iarg = parse_contact(iarg, narg, arg);
    } else if (!strcmp(kw, "compliance")) {
      law_.combined = !either(iarg, kw, "particle", "combined");
      iarg += 2;
    } else if (!strcmp(kw, "buffer")) {
      need(iarg, 1, kw, "a length");
      buffer_ = number(kw, arg[iarg + 1]);
      if (buffer_ < 0) error->all(FLERR, "{}: keyword 'buffer' must be >= 0", kStyle);
      iarg += 2;
    } else if (!strcmp(kw, "history_slots")) {
      need(iarg, 1, kw, "an integer 1 .. 64");
      nslots_ = whole_number(kw, arg[iarg + 1]);
      if (nslots_ < 1 || nslots_ > 64)
        error->all(FLERR, "{}: keyword 'history_slots' expects 1 .. 64", kStyle);
      iarg += 2;
    } else if (std::any_of(std::begin(kLiggghtsLawKeywords), std::end(kLiggghtsLawKeywords),
                           [&](const char* k) { return !strcmp(k, kw); })) {
      error->all(FLERR,
                 "{}: keyword '{}' is the LIGGGHTS adapter's; under LAMMPS the contact law is "
                 "written in LAMMPS's granular syntax after keyword 'contact': {}",
                 kStyle, kw, kContactSyntax);
    } else if (std::any_of(std::begin(kNotYetSupported), std::end(kNotYetSupported),
                           [&](const char* k) { return !strcmp(k, kw); })) {
      error->all(FLERR, "{}: keyword '{}' is not yet supported under LAMMPS (supported: {})",
                 kStyle, kw, kSupported);
    } else {
      error->all(FLERR, "{}: unknown keyword '{}' (supported under LAMMPS: {})", kStyle, kw,
                 kSupported);
    }
  }
  check_arguments();
}

int FixFemBodyLammps::reaction_group(const std::string& set)
{
  auto it = std::find(reaction_groups_.begin(), reaction_groups_.end(), set);
  if (it != reaction_groups_.end()) return static_cast<int>(it - reaction_groups_.begin());
  reaction_groups_.push_back(set);
  return static_cast<int>(reaction_groups_.size()) - 1;
}

// contact granular NORMAL ... [damping D] [tangential T ...] [rolling none] [twisting none]:
// the words of LAMMPS's pair granular / fix wall/gran for one material, the supported subset.
// What the core's law cannot express is refused by name. Returns the index after the law.
int FixFemBodyLammps::parse_contact(int iarg, int narg, char** arg)
{
  auto fail = [&](const std::string& what) {
    error->all(FLERR, "{}: keyword 'contact': {}", kStyle, what);
  };
  auto word = [&](int i, const char* what) -> const char* {
    if (i >= narg) fail(fmt::format("expects {} ({})", what, kContactSyntax));
    return arg[i];
  };
  auto value = [&](int i, const char* what) {
    const char* w = word(i, what);
    char* end = nullptr;
    errno = 0;
    const double v = strtod(w, &end);
    if (end == w || *end != '\0' || errno == ERANGE || !std::isfinite(v))
      fail(fmt::format("{} expects a finite number, got '{}'", what, w));
    return v;
  };
  if (law_.on) fail("given twice");
  law_.on = true;

  const char* style = word(iarg + 1, "a granular style");
  if (!strcmp(style, "hooke") || !strcmp(style, "hooke/history") || !strcmp(style, "hertz/history"))
    fail(fmt::format("style '{}' (the classic fix wall/gran styles) is not supported: write the "
                     "law with the granular models, {}",
                     style, kContactSyntax));
  if (strcmp(style, "granular") != 0)
    fail(fmt::format("expects 'granular', got '{}' ({})", style, kContactSyntax));

  // normal model
  const char* normal = word(iarg + 2, "a normal model");
  if (!strcmp(normal, "hooke") || !strcmp(normal, "hertz"))
    fail(fmt::format("normal model '{}' is not supported: the core's laws take the stiffness from "
                     "the materials' elastic moduli (Hertz with E*), not a given k_n; use "
                     "'hertz/material E COR NU'",
                     normal));
  if (!strcmp(normal, "dmt") || !strcmp(normal, "jkr") || !strcmp(normal, "mdr"))
    fail(fmt::format("normal model '{}' is not supported: the core has no adhesion or plastic "
                     "contact; use 'hertz/material E COR NU'",
                     normal));
  if (strcmp(normal, "hertz/material") != 0)
    fail(fmt::format("unknown normal model '{}' (supported: hertz/material)", normal));
  law_.E = value(iarg + 3, "hertz/material E");
  law_.cor = value(iarg + 4, "hertz/material COR (the damping coefficient)");
  law_.nu = value(iarg + 5, "hertz/material NU");
  if (law_.E <= 0) fail("hertz/material E must be > 0");
  if (law_.nu <= -1.0 || law_.nu >= 0.5) fail("hertz/material NU must lie in (-1, 0.5)");
  iarg += 6;

  bool have_damping = false, have_tangential = false;
  while (iarg < narg) {
    const char* kw = arg[iarg];
    if (!strcmp(kw, "damping")) {
      const char* d = word(iarg + 1, "a damping model");
      if (!strcmp(d, "coeff_restitution") || !strcmp(d, "tsuji")) {
        law_.tsuji = d[0] == 't';
      } else if (!strcmp(d, "viscoelastic") || !strcmp(d, "velocity") ||
                 !strcmp(d, "mass_velocity") || !strcmp(d, "none") || !strcmp(d, "mdr")) {
        fail(fmt::format("damping model '{}' is not supported: the core's damping force is "
                         "D sqrt(m F_ne / delta) v_n (LIGGGHTS's), as LAMMPS's "
                         "coeff_restitution and tsuji are; use 'damping coeff_restitution' or "
                         "'damping tsuji'",
                         d));
      } else {
        fail(fmt::format("unknown damping model '{}' (supported: coeff_restitution tsuji)", d));
      }
      have_damping = true;
      iarg += 2;
    } else if (!strcmp(kw, "tangential")) {
      const char* t = word(iarg + 1, "a tangential model");
      if (!strcmp(t, "mindlin")) {
        const char* k = word(iarg + 2, "tangential mindlin k_t");
        if (strcmp(k, "NULL") != 0)
          fail(fmt::format("tangential mindlin k_t = {} is not supported: the core's tangential "
                           "stiffness is 8 G* a from the materials; write NULL",
                           k));
        law_.history = true;
        law_.xt = value(iarg + 3, "tangential mindlin XT");
        law_.mu = value(iarg + 4, "tangential mindlin MU");
        iarg += 5;
      } else if (!strcmp(t, "linear_nohistory")) {
        law_.history = false;
        law_.xt = value(iarg + 2, "tangential linear_nohistory XT");
        law_.mu = value(iarg + 3, "tangential linear_nohistory MU");
        if (law_.mu != 0)
          fail("tangential linear_nohistory is supported frictionless only (MU = 0): with "
               "friction write 'tangential mindlin NULL XT MU'");
        iarg += 4;
      } else if (!strcmp(t, "linear_history") || !strcmp(t, "linear_history_classic") ||
                 !strcmp(t, "mindlin_classic") || !strcmp(t, "mindlin/force") ||
                 !strcmp(t, "mindlin_rescale") || !strcmp(t, "mindlin_rescale/force")) {
        fail(fmt::format("tangential model '{}' is not supported: the core's tangential spring "
                         "is Mindlin's 8 G* a with Coulomb friction; use 'tangential mindlin "
                         "NULL XT MU'",
                         t));
      } else {
        fail(fmt::format("unknown tangential model '{}' (supported: mindlin NULL XT MU, "
                         "linear_nohistory XT 0)",
                         t));
      }
      if (law_.xt < 0 || law_.mu < 0) fail("tangential XT and MU must be >= 0");
      have_tangential = true;
    } else if (!strcmp(kw, "rolling") || !strcmp(kw, "twisting")) {
      const char* m = word(iarg + 1, "a model");
      if (strcmp(m, "none") != 0)
        fail(fmt::format("{} model '{}' is not supported (the core has no {} resistance): leave "
                         "it out or write '{} none'",
                         kw, m, kw, kw));
      iarg += 2;
    } else if (!strcmp(kw, "heat") || !strcmp(kw, "limit_damping") ||
               !strcmp(kw, "synchronized_verlet")) {
      fail(fmt::format("option '{}' is not supported", kw));
    } else {
      break; // the next keyword of fix fem/body
    }
  }
  if (!have_damping)
    fail("needs 'damping coeff_restitution' or 'damping tsuji': LAMMPS's default damping "
         "(viscoelastic, where the second hertz/material value is eta_n0, not a restitution) "
         "is not supported");
  if (!have_tangential)
    fail(fmt::format("needs a tangential model, as LAMMPS's granular styles do: 'tangential "
                     "mindlin NULL XT MU' or 'tangential linear_nohistory XT 0' ({})",
                     kContactSyntax));
  if (law_.cor <= 0 || law_.cor > 1)
    fail(fmt::format("damping {} needs a coefficient of restitution COR in (0, 1] (the second "
                     "hertz/material value), got {}",
                     law_.tsuji ? "tsuji" : "coeff_restitution", law_.cor));
  return iarg;
}

// The core's ContactMaterial for the law: E* and G* from the particle's material (hertz/material
// E, NU) and, with 'compliance combined', the body's own youngs/poisson; the restitution that
// gives the core's damping the coefficient of LAMMPS's damping model. All particle types share it.
void FixFemBodyLammps::contact_setup()
{
  const double D = law_.tsuji ? tsuji_coefficient(law_.cor) : 0.0;
  const double e = law_.tsuji ? restitution_for_damping(D) : law_.cor;
  const double Eb = law_.combined ? material_.E : 0.0, nub = law_.combined ? material_.nu : 0.0;
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
               kStyle, law_.xt, xt_core, law_.combined ? " and body" : "");
  log_line(fmt::format("fix fem/body {}: contact hertz/material E* {:.6g} G* {:.6g} ({}), damping "
                       "{} COR {:g}{}, tangential {} XT {:.6g} MU {:g}\n",
                       id, contact_material_.Yeff, contact_material_.Geff,
                       law_.combined ? "particle and body compliance"
                                     : "particle compliance; the body's from its elements",
                       law_.tsuji ? "tsuji" : "coeff_restitution", law_.cor,
                       law_.tsuji ? fmt::format(" (core restitution {:.6g})", e) : "",
                       law_.history ? "mindlin" : "linear_nohistory", law_.history ? xt_core : 0.0,
                       law_.mu));
}

void FixFemBodyLammps::check_arguments()
{
  // 'type' names the atom type of the body's surface for particle contact; required now, as in
  // the LIGGGHTS adapter, so that inputs need no change when contact arrives.
  if (surface_type_ < 1 || surface_type_ > atom->ntypes)
    error->all(FLERR, "{}: keyword 'type' is required and must be an atom type between 1 and {}",
               kStyle, atom->ntypes);
  if (!have_density_ || !have_youngs_ || !have_poisson_)
    error->all(FLERR, "{}: a deformable body needs keywords 'density', 'youngs' and 'poisson'",
               kStyle);
  if (material_.rho <= 0 || material_.E <= 0)
    error->all(FLERR, "{}: 'density' and 'youngs' must be > 0", kStyle);
  if (material_.nu <= -1.0 || material_.nu >= 0.5)
    error->all(FLERR, "{}: 'poisson' must lie in (-1, 0.5)", kStyle);
  if (have_plane_ && domain->dimension == 3)
    error->all(FLERR,
               "{}: keyword 'plane' applies to 2D runs ('dimension 2'); this run is 3D "
               "(leave out 'plane')",
               kStyle);
}

/* ---------------------------------------------------------------------- */

void FixFemBodyLammps::log_line(const std::string& line) const
{
  if (comm->me == 0) utils::logmesg(lmp, line);
}

void FixFemBodyLammps::load_mesh()
{
  fracdem::Mesh mesh;
  try {
    mesh = fracdem::read_gmsh(mesh_file_, domain->dimension);
  } catch (const std::exception& e) {
    error->all(FLERR, "{} {}: cannot use mesh: {}", kStyle, id, e.what());
  }
  if (mesh.dim != domain->dimension)
    error->all(FLERR, "{}: mesh '{}' is {}D but the simulation is {}D", kStyle, mesh_file_,
               mesh.dim, domain->dimension);
  bool in_plane = false;
  try {
    in_plane = fracdem::apply_transforms(mesh, transforms_);
  } catch (const std::exception& e) {
    error->all(FLERR, "{} {}: keyword 'rotate': {}", kStyle, id, e.what());
  }
  if (!in_plane)
    error->all(FLERR, "{}: 2D mesh must stay in the z = 0 plane after 'move'/'rotate'", kStyle);
  for (int e = 0; e < mesh.num_elems(); ++e)
    if (!fracdem::element_geometry_finite(mesh, e))
      error->all(FLERR,
                 "{} {}: keyword 'scale'/'move'/'rotate': element {} of '{}' overflows "
                 "double precision",
                 kStyle, id, e, mesh_file_);
  const std::string material_error = fracdem::material_setup_error(material_, mesh.dim);
  if (!material_error.empty()) error->all(FLERR, "{} {}: {}", kStyle, id, material_error);

  try {
    body_.build(std::move(mesh), material_, false);
  } catch (const std::exception& e) {
    error->all(FLERR, "{} {}: bad mesh '{}': {}", kStyle, id, mesh_file_, e.what());
  }
  for (const auto& s : fixed_sets_)
    body_.set_fixed(node_set(s.set, "fixed"), s.mask, s.group);
  for (const auto& s : prescribed_velocity_)
    body_.set_prescribed_velocity(node_set(s.set, "prescribed_velocity"), s.v, s.ramp, s.group);
  for (const auto& s : initial_velocity_)
    node_set(s.set, "velocity"); // validate names now

  // As in the LIGGGHTS adapter: every rank holds the whole body; the element work of a material
  // without history is split evenly and the forces summed, so all replicas stay identical.
  split_element_work_ = body_.space().state_size() == 0 && comm->nprocs > 1;
  if (split_element_work_) {
    const long long ne = body_.mesh().num_elems();
    body_.set_element_range(static_cast<int>((ne * comm->me) / comm->nprocs),
                            static_cast<int>((ne * (comm->me + 1)) / comm->nprocs));
  }
  if (law_.on) contact_.rebuild_surface(body_.mesh());
  log_line(fmt::format(
      "fix fem/body {}: {}, {} nodes, {} elements, {} boundary facets, "
      "deformable {} (LAMMPS host{})\n",
      id, mesh_file_, body_.num_nodes(), body_.mesh().num_elems(), contact_.facets().size(),
      material_.kinematics == fracdem::Kinematics::Corotational ? "corotational"
                                                                : "small-strain elastic",
      law_.on ? "" : ", no particle contact"));
  if (law_.on) {
    contact_setup();
    check_in_box("as placed");
  }
}

std::vector<int> FixFemBodyLammps::node_set(const std::string& name, const char* keyword) const
{
  const fracdem::Mesh& mesh = body_.mesh();
  if (name == "all") {
    std::vector<int> all(mesh.num_nodes());
    for (int i = 0; i < mesh.num_nodes(); ++i)
      all[i] = i;
    return all;
  }
  auto it = mesh.node_sets.find(name);
  if (it == mesh.node_sets.end()) {
    std::string have;
    for (const auto& kv : mesh.node_sets)
      have += " " + kv.first;
    error->all(FLERR,
               "{}: keyword '{}': mesh '{}' has no physical group '{}'; it has:{} (and "
               "'all')",
               kStyle, keyword, mesh_file_, name, have);
  }
  return it->second;
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
    opt.hertz_patch = !law_.combined;
    opt.buffer = buffer_ >= 0 ? buffer_ : neighbor->skin;
    contact_.configure(opt);
    contact_.set_materials(
        std::vector<fracdem::ContactMaterial>(atom->ntypes + 1, contact_material_));
  }
  check_time_step();
}

void FixFemBodyLammps::reset_dt()
{
  check_time_step();
}

void FixFemBodyLammps::check_time_step()
{
  dt_stable_ = body_.stable_time_step();
  const double dt = update->dt;
  log_line(fmt::format("fix fem/body {}: stable FE time step {:.6g}, host time step {:.6g} "
                       "({:.1f}%)\n",
                       id, dt_stable_, dt, 100.0 * dt / dt_stable_));
  if (dt > dt_stable_) {
    const std::string msg =
        fmt::format("fix fem/body {}: host timestep {} exceeds the stable FE time step {} of "
                    "mesh '{}'; reduce 'timestep' or coarsen the mesh (keyword 'dt_check warn' "
                    "runs anyway)",
                    id, dt, dt_stable_, mesh_file_);
    if (dt_check_error_)
      error->all(FLERR, msg);
    else if (comm->me == 0)
      error->warning(FLERR, msg);
  }
}

// The acceleration of every fix gravity (LAMMPS's FixGravity::extract("gvec")), read at set-up:
// fix gravity sets it in its own init(), which may run after this fix's.
void FixFemBodyLammps::read_gravity()
{
  gravity_[0] = gravity_[1] = gravity_[2] = 0;
  if (!apply_gravity_) return;
  for (Fix* f : modify->get_fix_by_style("^gravity")) {
    int dim = 0;
    const auto* g = static_cast<const double*>(f->extract("gvec", dim));
    if (!g || dim != 1)
      error->all(FLERR, "{} {}: cannot read the acceleration of fix {} (style {})", kStyle, id,
                 f->id, f->style);
    for (int d = 0; d < 3; ++d)
      gravity_[d] += g[d];
  }
}

void FixFemBodyLammps::setup(int /*vflag*/)
{
  if (!initial_velocity_applied_) {
    for (const auto& s : initial_velocity_)
      body_.set_velocity(node_set(s.set, "velocity"), s.v);
    body_.impose_velocity_conditions();
  }
  initial_velocity_applied_ = true;
  read_gravity();
  if (law_.on) {
    check_in_box("at the start of the run"); // change_box and earlier runs move it
    contact_.invalidate_search();
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
}

// Atoms change rank and index when LAMMPS re-neighbours, and particles outside the box are
// dropped then: the search is rebuilt and the body checked.
void FixFemBodyLammps::pre_neighbor()
{
  if (!law_.on) return;
  contact_.invalidate_search();
  check_in_box(nullptr);
}

/* ----------------------------------------------------------------------
   velocity Verlet, in step with the host: half kick + drift here,
   forces in post_force, second half kick in final_integrate.
------------------------------------------------------------------------- */

void FixFemBodyLammps::initial_integrate(int /*vflag*/)
{
  body_.advance_time(update->dt);
  body_.half_kick_drift(update->dt);
  if (law_.on && update->ntimestep % kBoxCheckEvery == 0) check_in_box(nullptr);
}

void FixFemBodyLammps::post_force(int /*vflag*/)
{
  compute_forces();
}

void FixFemBodyLammps::final_integrate()
{
  body_.half_kick(update->dt);
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
  p.slots = nslots_;
  return p;
}

// The force evaluation of the LIGGGHTS adapter: internal forces of this rank's elements and
// contact forces of this rank's particles (owned atoms: the body is replicated, so no ghosts are
// needed), one reduction, then the body finishes (gravity, reactions, work).
void FixFemBodyLammps::compute_forces()
{
  const int nn = body_.num_nodes();
  body_.begin_forces();
  int first_inverted = -1;
  const double local_energy = body_.add_internal_forces(&first_inverted);
  fracdem::ParticleFacetResult res;
  if (law_.on) {
    res = contact_.evaluate(particle_arrays(), body_.mesh().X.data(), body_.positions().data(),
                            body_.velocities().data(), update->dt, body_.contact_forces());
    if (res.history_exhausted && !warned_slots_) {
      error->warning(FLERR,
                     "fix fem/body {}: a particle has more simultaneous facet contacts "
                     "than 'history_slots'; extra contacts run without tangential history",
                     id);
      warned_slots_ = true;
    }
  }
  // energy, contacts, unresolved contacts (summed); first inverted element + 1 (max)
  double scalars[4] = {local_energy, static_cast<double>(res.contacts),
                       res.unresolved_speed > 0 ? 1.0 : 0.0,
                       static_cast<double>(first_inverted >= 0 ? first_inverted + 1 : 0)};
  if (split_element_work_) {
    MPI_Allreduce(MPI_IN_PLACE, body_.forces_data(), 3 * nn, MPI_DOUBLE, MPI_SUM, world);
    if (law_.on)
      MPI_Allreduce(MPI_IN_PLACE, body_.contact_forces(), 3 * nn, MPI_DOUBLE, MPI_SUM, world);
    MPI_Allreduce(MPI_IN_PLACE, scalars, 3, MPI_DOUBLE, MPI_SUM, world);
    MPI_Allreduce(MPI_IN_PLACE, &scalars[3], 1, MPI_DOUBLE, MPI_MAX, world);
  } else if (comm->nprocs > 1 && law_.on) { // element work replicated: contact shares summed
    MPI_Allreduce(MPI_IN_PLACE, body_.contact_forces(), 3 * nn, MPI_DOUBLE, MPI_SUM, world);
    MPI_Allreduce(MPI_IN_PLACE, &scalars[1], 2, MPI_DOUBLE, MPI_SUM, world);
  }
  ncontacts_ = static_cast<int>(scalars[1]);
  if (scalars[2] > 0 && !warned_unresolved_) warn_unresolved_contact(res);
  if (scalars[3] > 0)
    error->all(FLERR,
               "fix fem/body {}: element {} inverted (det F <= 0) at step {}; the time step "
               "is too large or the load too severe for this mesh",
               id, static_cast<int>(scalars[3]) - 1, update->ntimestep);
  if (!std::isfinite(scalars[0]))
    error->all(FLERR,
               "fix fem/body {}: non-finite strain energy at step {} (NaN/Inf in the body "
               "state)",
               id, update->ntimestep);
  body_.finish_forces(scalars[0], gravity_, update->dt, update->setupflag == 0);
}

// Once per run: a particle hits the body faster than the time step can follow (every rank
// enters; the worst speed and the time step that resolves it come from all ranks).
void FixFemBodyLammps::warn_unresolved_contact(const fracdem::ParticleFacetResult& res)
{
  warned_unresolved_ = true;
  double speed = res.unresolved_speed, dt_ok = res.resolving_dt;
  MPI_Allreduce(MPI_IN_PLACE, &speed, 1, MPI_DOUBLE, MPI_MAX, world);
  MPI_Allreduce(MPI_IN_PLACE, &dt_ok, 1, MPI_DOUBLE, MPI_MIN, world);
  if (comm->me == 0)
    error->warning(FLERR,
                   "fix fem/body {}: at step {} a particle approaches the surface at {:g} m/s, "
                   "more than {:g} % of its Hertz penetration per time step; the contact is not "
                   "resolved in time and may gain or lose energy: timestep {:g} or smaller "
                   "resolves it",
                   id, update->ntimestep, speed, 100 * fracdem::kMaxApproachPerStep, dt_ok);
}

/* ----------------------------------------------------------------------
   the body in the simulation box (as in the LIGGGHTS adapter)
------------------------------------------------------------------------- */

// Particles live inside the box. Beyond a fixed face they are lost, so the body's surface must
// lie inside the fixed faces. Across a periodic boundary the particles' images meet the body, so
// it may cross the boundary, but not be longer than the period nor lie more than a period
// outside. A shrink-wrapped face follows the particles. Only surface nodes count. Slack: the
// contact search buffer.
std::string FixFemBodyLammps::box_violation() const
{
  const std::vector<fracdem::Facet>& facets = contact_.facets();
  if (facets.empty()) return "";
  const std::vector<double>& x = body_.positions();
  double lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    lo[d] = std::numeric_limits<double>::infinity();
    hi[d] = -lo[d];
  }
  for (const fracdem::Facet& fc : facets)
    for (int k = 0; k < fc.nn; ++k)
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], x[3 * fc.n[k] + d]);
        hi[d] = std::max(hi[d], x[3 * fc.n[k] + d]);
      }
  const double* blo = domain->triclinic ? domain->boxlo_bound : domain->boxlo;
  const double* bhi = domain->triclinic ? domain->boxhi_bound : domain->boxhi;
  const double slack = buffer_ >= 0 ? buffer_ : neighbor->skin;
  const int dim = domain->dimension; // 2D: z is periodic by rule and the body lies in z = 0
  for (int d = 0; d < dim; ++d) {
    const char axis = "xyz"[d];
    std::string why;
    if (domain->periodicity[d]) {
      const double period = bhi[d] - blo[d];
      if (hi[d] - lo[d] > period + slack)
        why = fmt::format(" is longer than its period in the periodic dimension {0}; it would "
                          "overlap its own periodic image: shorten it or enlarge the box in {0}",
                          axis);
      else if (lo[d] < blo[d] - period - slack || hi[d] > bhi[d] + period + slack)
        why = fmt::format(" lies more than a period outside it in the periodic dimension {}, "
                          "beyond the reach of the particles' images: move it into the box",
                          axis);
    } else {
      for (int side = 0; side < 2 && why.empty(); ++side) {
        const bool out = side == 0 ? lo[d] < blo[d] - slack : hi[d] > bhi[d] + slack;
        if (out && domain->boundary[d][side] == 1) // 2, 3: shrink-wrapped
          why = fmt::format(" reaches beyond its fixed {}-{} face; particles are lost beyond a "
                            "fixed face, so they cannot hit that part: keep the body inside or "
                            "enlarge the box",
                            axis, side ? "high" : "low");
      }
    }
    if (why.empty()) continue;
    std::string extent = "the body (", box = " in the box (";
    for (int e = 0; e < dim; ++e) {
      extent += fmt::format("{}{} {:g} to {:g}", e ? ", " : "", "xyz"[e], lo[e], hi[e]);
      box += fmt::format("{}{} {:g} to {:g}", e ? ", " : "", "xyz"[e], blo[e], bhi[e]);
    }
    return extent + ")" + box + ")" + why;
  }
  return "";
}

// A body placed outside is an input mistake: refused. A deformable body that gets out by its own
// dynamics is warned about once: only the part outside is out of the particles' reach.
// when: "as placed" (fix command), "at the start of the run", or nullptr: at this step.
void FixFemBodyLammps::check_in_box(const char* when)
{
  const bool placed = when && !strcmp(when, "as placed");
  if (!placed && warned_outside_) return;
  const std::string where = box_violation();
  if (where.empty()) return;
  const std::string msg =
      fmt::format("{} {}: mesh '{}' {}: ", kStyle, id, mesh_file_,
                  when ? std::string(when) : fmt::format("at step {}", update->ntimestep));
  if (placed) error->all(FLERR, msg + where + " (keywords 'move', 'scale', 'rotate' place it)");
  warned_outside_ = true;
  if (comm->me == 0)
    error->warning(FLERR, msg + "its nodes have moved out of the box: " + where +
                              " (warned once; the run goes on)");
}

/* ---------------------------------------------------------------------- */

double FixFemBodyLammps::compute_scalar()
{
  return body_.kinetic_energy() + body_.strain_energy();
}

double FixFemBodyLammps::compute_vector(int i)
{
  switch (i) {
  case kKinetic:
    return body_.kinetic_energy();
  case kStrain:
    return body_.strain_energy();
  case kExternalWork:
    return body_.external_work();
  case kContactWork:
    return body_.contact_work();
  case kNodes:
    return body_.num_nodes();
  case kElements:
    return body_.mesh().num_active_elems();
  case kContacts:
    return ncontacts_;
  case kForceX:
  case kForceY:
  case kForceZ:
    return body_.contact_force_total()[i - kForceX];
  case kStableDt:
    return dt_stable_;
  case kSearchRebuilds: {
    double local = contact_.search_rebuilds(), total = 0;
    MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_MAX, world);
    return total;
  }
  case kMomentumX:
  case kMomentumY:
  case kMomentumZ:
    return body_.momentum(i - kMomentumX);
  case kDissipated:
    return body_.dissipated_energy();
  case kSplitNodes: {
    const auto& parents = body_.parents();
    return static_cast<double>(parents.size() - std::count(parents.begin(), parents.end(), -1));
  }
  case kFragments: {
    std::vector<int> comp;
    return fracdem::element_components(body_.mesh(), comp);
  }
  case kBoundaryWork:
    return body_.boundary_work();
  }
  if (i >= kVectorSize && i < size_vector) {
    const auto& r = body_.reactions();
    const size_t k = static_cast<size_t>(i - kVectorSize);
    return k < r.size() ? r[k] : 0.0;
  }
  return 0.0;
}

/* ----------------------------------------------------------------------
   per-atom tangential history (with keyword 'contact')
------------------------------------------------------------------------- */

void FixFemBodyLammps::grow_arrays(int nmax)
{
  memory->grow(history_, nmax, nslots_ * fracdem::kHistorySlotDoubles, "fem/body:history");
}

void FixFemBodyLammps::copy_arrays(int i, int j, int /*delflag*/)
{
  std::memcpy(history_[j], history_[i], sizeof(double) * nslots_ * fracdem::kHistorySlotDoubles);
}

void FixFemBodyLammps::set_arrays(int i)
{
  std::fill_n(history_[i], nslots_ * fracdem::kHistorySlotDoubles, 0.0);
  fracdem::clear_history_row(history_[i], nslots_);
}

int FixFemBodyLammps::pack_exchange(int i, double* buf)
{
  const int n = nslots_ * fracdem::kHistorySlotDoubles;
  std::memcpy(buf, history_[i], sizeof(double) * n);
  return n;
}

int FixFemBodyLammps::unpack_exchange(int nlocal, double* buf)
{
  const int n = nslots_ * fracdem::kHistorySlotDoubles;
  std::memcpy(history_[nlocal], buf, sizeof(double) * n);
  return n;
}

// The per-particle history; the body itself is logged by the core's own count.
double FixFemBodyLammps::memory_usage()
{
  if (!law_.on) return 0.0;
  return static_cast<double>(atom->nmax) * nslots_ * fracdem::kHistorySlotDoubles * sizeof(double);
}
