// fix fem/body: host adapter that owns a replicated FE body, integrates it and couples it to
// particles.
#include "fix_fem_body.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <stdexcept>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_gravity.h"
#include "fix_property_global.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "update.h"

#include "contact/contact_resolution.h"
#include "contact/contact_spread.h"
#include "contact/geometry.h"
#include "io/gmsh_reader.h"
#include "fracture/nodal_fracture.h"
#include "materials/material_table.h"

using namespace LAMMPS_NS;
using namespace FixConst;

namespace
{

const char* const kStyle = "fix fem/body";
// Steps between checks that the body is still inside the box (besides every re-neighbouring):
// a pass over its surface nodes, cheap beside the element work of as many steps.
constexpr int kBoxCheckEvery = 100;

// Sub-model tables: one place maps keywords to models.
const std::map<std::string, fracdem::Kinematics> kKinematicsTable = {
    {"elastic", fracdem::Kinematics::SmallStrain},
    {"corotational", fracdem::Kinematics::Corotational},
};
const std::map<std::string, fracdem::NormalModel> kNormalModelTable = {
    {"hertz", fracdem::NormalModel::Hertz},
    {"hooke", fracdem::NormalModel::Hooke},
};
const std::map<std::string, fracdem::PlaneMode> kPlaneModeTable = {
    {"strain", fracdem::PlaneMode::PlaneStrain},
    {"axisymmetric", fracdem::PlaneMode::Axisymmetric},
    {"stress", fracdem::PlaneMode::PlaneStress},
};

template <typename T>
T lookup(Error* error, const std::map<std::string, T>& table, const char* keyword,
         const char* value)
{
  auto it = table.find(value);
  if (it == table.end()) {
    std::string msg =
        std::string(kStyle) + ": keyword '" + keyword + "' got '" + value + "', expected one of:";
    for (const auto& kv : table)
      msg += " " + kv.first;
    error->all(FLERR, msg.c_str());
  }
  return it->second;
}

// Global vector layout, documented in docs/fix_fem_body.md.
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
// After the reaction forces (3 per group), so that the indices above and of the reactions stay.
enum TailIndex { kErodedElements = 0, kErodedMass, kErodedEnergy, kShieldWork, kTailSize };

} // namespace

/* ---------------------------------------------------------------------- */

FixFemBody::FixFemBody(LAMMPS* lmp, int narg, char** arg) : Fix(lmp, narg, arg)
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag)
    error->all(FLERR, "fix fem/body requires atom_style granular (radius, rmass, omega)");

  parse_arguments(narg, arg);
  load_mesh();
  find_restart_records();

  scalar_flag = 1;
  extscalar = 1;
  vector_flag = 1;
  size_vector = kVectorSize + 3 * static_cast<int>(reaction_groups_.size()) + kTailSize;
  extvector = 0;
  global_freq = 1;
  // time_integrate stays 0: this fix integrates FE nodes, never the host's atoms.
  time_depend = 1;
  restart_global = 1;
  restart_peratom = 1;
  create_attribute = 1;

  grow_arrays(atom->nmax);
  atom->add_callback(0);
  atom->add_callback(1);
  for (int i = 0; i < atom->nlocal; ++i)
    set_arrays(i);
}

FixFemBody::~FixFemBody()
{
  atom->delete_callback(id, 0);
  atom->delete_callback(id, 1);
  memory->destroy(history_);
  if (energy_fp_) fclose(energy_fp_);
}

int FixFemBody::setmask()
{
  return INITIAL_INTEGRATE | POST_FORCE | FINAL_INTEGRATE | PRE_NEIGHBOR;
}

/* ----------------------------------------------------------------------
   argument parsing: fix ID group fem/body file FILE keyword value ...
------------------------------------------------------------------------- */

// The value of `keyword`: a finite number written in full ("1e999", "abc", "2x" are refused by
// keyword, where the host's numeric() names neither the fix nor the keyword).
double FixFemBody::number(const char* keyword, const char* word)
{
  char* end = nullptr;
  errno = 0;
  const double v = strtod(word, &end);
  if (end == word || *end != '\0' || errno == ERANGE || !std::isfinite(v)) {
    const std::string msg = std::string(kStyle) + ": keyword '" + keyword +
                            "' expects a finite number, got '" + word + "'";
    error->all(FLERR, msg.c_str());
  }
  return v;
}

// The value of `keyword`: an integer that fits an int.
int FixFemBody::whole_number(const char* keyword, const char* word)
{
  char* end = nullptr;
  errno = 0;
  const long long v = strtoll(word, &end, 10);
  if (end == word || *end != '\0' || errno == ERANGE || v < INT_MIN || v > INT_MAX) {
    const std::string msg =
        std::string(kStyle) + ": keyword '" + keyword + "' expects an integer, got '" + word + "'";
    error->all(FLERR, msg.c_str());
  }
  return static_cast<int>(v);
}

void FixFemBody::parse_arguments(int narg, char** arg)
{
  auto need = [&](int iarg, int n, const char* keyword, const char* what) {
    if (iarg + n >= narg) {
      std::string msg = std::string(kStyle) + ": keyword '" + keyword + "' expects " + what;
      error->all(FLERR, msg.c_str());
    }
  };
  // A keyword that takes one of two words: true for the first, false for the second.
  auto either = [&](int iarg, const char* keyword, const char* first, const char* second) {
    const std::string expected = std::string(first) + " or " + second;
    need(iarg, 1, keyword, expected.c_str());
    if (!strcmp(arg[iarg + 1], first)) return true;
    if (!strcmp(arg[iarg + 1], second)) return false;
    const std::string msg = std::string(kStyle) + ": keyword '" + keyword + "' expects " + expected;
    error->all(FLERR, msg.c_str());
    return false;
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
      surface_type_ = whole_number(arg[iarg], arg[iarg + 1]);
      iarg += 2;
    } else if (!strcmp(kw, "density")) {
      need(iarg, 1, kw, "a value");
      material_.rho = number(arg[iarg], arg[iarg + 1]);
      have_density_ = true;
      iarg += 2;
    } else if (!strcmp(kw, "youngs")) {
      need(iarg, 1, kw, "a value");
      material_.E = number(arg[iarg], arg[iarg + 1]);
      have_youngs_ = true;
      iarg += 2;
    } else if (!strcmp(kw, "poisson")) {
      need(iarg, 1, kw, "a value");
      material_.nu = number(arg[iarg], arg[iarg + 1]);
      have_poisson_ = true;
      iarg += 2;
    } else if (!strcmp(kw, "model")) {
      need(iarg, 1, kw, "elastic or corotational");
      material_.kinematics = lookup(error, kKinematicsTable, kw, arg[iarg + 1]);
      iarg += 2;
    } else if (!strcmp(kw, "plane")) {
      need(iarg, 1, kw, "strain, stress or axisymmetric");
      material_.plane = lookup(error, kPlaneModeTable, kw, arg[iarg + 1]);
      have_plane_ = true;
      iarg += 2;
    } else if (!strcmp(kw, "thickness")) {
      need(iarg, 1, kw, "a value");
      material_.thickness = number(arg[iarg], arg[iarg + 1]);
      if (material_.thickness <= 0)
        error->all(FLERR, "fix fem/body: keyword 'thickness' must be > 0");
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
        s.v[d] = number(arg[iarg], arg[iarg + 2 + d]);
      iarg += 5;
      if (kw[0] == 'v') {
        initial_velocity_.push_back(s);
        continue;
      }
      s.group = reaction_group(s.set);
      if (iarg + 1 < narg && !strcmp(arg[iarg], "ramp")) {
        s.ramp = number(arg[iarg], arg[iarg + 1]);
        if (s.ramp <= 0)
          error->all(FLERR, "fix fem/body: keyword 'prescribed_velocity ... ramp T' needs T > 0");
        iarg += 2;
      }
      prescribed_velocity_.push_back(s);
    } else if (!strcmp(kw, "scale")) {
      need(iarg, 1, kw, "a factor");
      fracdem::MeshTransform t{fracdem::MeshTransform::Scale,
                               {number(arg[iarg], arg[iarg + 1]), 0, 0, 0}};
      if (t.a[0] <= 0) error->all(FLERR, "fix fem/body: keyword 'scale' must be > 0");
      transforms_.push_back(t);
      iarg += 2;
    } else if (!strcmp(kw, "move")) {
      need(iarg, 3, kw, "dx dy dz");
      fracdem::MeshTransform t{fracdem::MeshTransform::Move, {0, 0, 0, 0}};
      for (int d = 0; d < 3; ++d)
        t.a[d] = number(arg[iarg], arg[iarg + 1 + d]);
      transforms_.push_back(t);
      iarg += 4;
    } else if (!strcmp(kw, "rotate")) {
      need(iarg, 6, kw, "axis ax ay az angle DEGREES");
      if (strcmp(arg[iarg + 1], "axis") || strcmp(arg[iarg + 5], "angle"))
        error->all(FLERR, "fix fem/body: keyword 'rotate' expects 'axis ax ay az angle DEGREES'");
      fracdem::MeshTransform t{fracdem::MeshTransform::Rotate, {0, 0, 0, 0}};
      for (int d = 0; d < 3; ++d)
        t.a[d] = number(arg[iarg], arg[iarg + 2 + d]);
      t.a[3] = number(arg[iarg], arg[iarg + 6]) * M_PI / 180.0;
      if (!fracdem::valid_axis(t.a)) {
        const std::string msg = std::string(kStyle) + ": keyword 'rotate' got axis " +
                                arg[iarg + 2] + " " + arg[iarg + 3] + " " + arg[iarg + 4] +
                                ", expected a non-zero axis direction ax ay az";
        error->all(FLERR, msg.c_str());
      }
      transforms_.push_back(t);
      iarg += 7;
    } else if (!strcmp(kw, "rigid")) {
      rigid_ = either(iarg, kw, "yes", "no");
      iarg += 2;
    } else if (!strcmp(kw, "motion")) {
      parse_motion(narg, arg, iarg);
    } else if (!strcmp(kw, "material")) {
      parse_material_words(narg, arg, iarg, fracdem::parse_material_arguments);
    } else if (!strcmp(kw, "eos")) {
      parse_material_words(narg, arg, iarg, fracdem::parse_eos_arguments);
    } else if (!strcmp(kw, "fracture")) {
      parse_fracture(narg, arg, iarg);
    } else if (!strcmp(kw, "bulk_viscosity")) {
      parse_bulk_viscosity(narg, arg, iarg);
    } else if (!strcmp(kw, "erosion")) {
      parse_erosion(narg, arg, iarg);
    } else if (!strcmp(kw, "erosion_mass")) {
      erosion_.remove_mass = !either(iarg, kw, "keep", "remove");
      have_erosion_mass_ = true;
      iarg += 2;
    } else if (!strcmp(kw, "contact_model")) {
      need(iarg, 1, kw, "hertz or hooke");
      normal_model_ = lookup(error, kNormalModelTable, kw, arg[iarg + 1]);
      iarg += 2;
    } else if (!strcmp(kw, "tangential")) {
      tangential_history_ = either(iarg, kw, "history", "no_history");
      iarg += 2;
    } else if (!strcmp(kw, "compliance")) {
      compliance_combined_ = either(iarg, kw, "particle", "combined") ? 0 : 1;
      iarg += 2;
    } else if (!strcmp(kw, "buffer")) {
      need(iarg, 1, kw, "a distance");
      buffer_ = number(arg[iarg], arg[iarg + 1]);
      if (buffer_ < 0) error->all(FLERR, "fix fem/body: keyword 'buffer' must be >= 0");
      iarg += 2;
    } else if (!strcmp(kw, "dt_check")) {
      dt_check_error_ = either(iarg, kw, "error", "warn");
      iarg += 2;
    } else if (!strcmp(kw, "gravity")) {
      apply_gravity_ = either(iarg, kw, "yes", "no"); // anything else is an error, not "no"
      iarg += 2;
    } else if (!strcmp(kw, "energy_file")) {
      need(iarg, 2, kw, "FILE N");
      energy_file_ = arg[iarg + 1];
      energy_every_ = whole_number(arg[iarg], arg[iarg + 2]);
      if (energy_every_ <= 0) error->all(FLERR, "fix fem/body: keyword 'energy_file' needs N > 0");
      iarg += 3;
    } else if (!strcmp(kw, "contact_bodies")) {
      contact_bodies_ = either(iarg, kw, "yes", "no") ? 1 : 0;
      iarg += 2;
    } else if (!strcmp(kw, "contact_penalty")) {
      need(iarg, 1, kw, "a factor");
      contact_penalty_ = number(arg[iarg], arg[iarg + 1]);
      if (contact_penalty_ <= 0)
        error->all(FLERR, "fix fem/body: keyword 'contact_penalty' must be > 0");
      iarg += 2;
    } else if (!strcmp(kw, "history_slots")) {
      need(iarg, 1, kw, "a count");
      nslots_ = whole_number(arg[iarg], arg[iarg + 1]);
      // A particle touches a handful of facet features at once; beyond this it is a typo (the
      // history array is per particle and would eat memory).
      if (nslots_ < 1 || nslots_ > kMaxHistorySlots)
        error->all(FLERR, "fix fem/body: keyword 'history_slots' expects 1 .. 64");
      iarg += 2;
    } else {
      std::string msg = std::string(kStyle) + ": unknown keyword '" + kw + "'";
      error->all(FLERR, msg.c_str());
    }
  }

  check_arguments();
}

void FixFemBody::parse_motion(int narg, char** arg, int& iarg)
{
  auto need = [&](int n, const char* what) {
    if (iarg + n >= narg) {
      std::string msg = std::string(kStyle) + ": keyword 'motion' expects " + what;
      error->all(FLERR, msg.c_str());
    }
  };
  need(1, "linear vx vy vz | rotate origin ox oy oz axis ax ay az period T");
  if (!strcmp(arg[iarg + 1], "linear")) {
    need(4, "linear vx vy vz");
    motion_.kind = fracdem::RigidMotion::Linear;
    for (int d = 0; d < 3; ++d)
      motion_.velocity[d] = number(arg[iarg], arg[iarg + 2 + d]);
    iarg += 5;
  } else if (!strcmp(arg[iarg + 1], "rotate")) {
    need(10, "rotate origin ox oy oz axis ax ay az period T");
    if (strcmp(arg[iarg + 2], "origin") || strcmp(arg[iarg + 6], "axis") ||
        strcmp(arg[iarg + 10], "period"))
      error->all(FLERR, "fix fem/body: keyword 'motion rotate' expects 'origin ox oy oz axis ax "
                        "ay az period T'");
    motion_.kind = fracdem::RigidMotion::Rotate;
    for (int d = 0; d < 3; ++d) {
      motion_.origin[d] = number(arg[iarg], arg[iarg + 3 + d]);
      motion_.axis[d] = number(arg[iarg], arg[iarg + 7 + d]);
    }
    motion_.period = number(arg[iarg], arg[iarg + 11]);
    double* k = motion_.axis;
    const double n = std::sqrt(k[0] * k[0] + k[1] * k[1] + k[2] * k[2]);
    if (!fracdem::valid_axis(k) || motion_.period == 0)
      error->all(FLERR, "fix fem/body: 'motion rotate' needs a non-zero axis and period");
    for (int d = 0; d < 3; ++d)
      k[d] /= n;
    iarg += 12;
  } else {
    error->all(FLERR, "fix fem/body: keyword 'motion' expects 'linear' or 'rotate'");
  }
}

// A core parser's "material rankine: strength: ..." as "keyword 'material rankine': strength: ...".
static std::string keyword_error(const std::string& err)
{
  const std::size_t colon = err.find(':');
  if (colon == std::string::npos) return "keyword " + err;
  return "keyword '" + err.substr(0, colon) + "'" + err.substr(colon);
}

// `material MODEL ...` and `eos ...`: the core's material table reads the words up to the next
// fix fem/body keyword with `parse` (parse_material_arguments or parse_eos_arguments); the
// adapter only hands them over and reports the error by keyword.
void FixFemBody::parse_material_words(int narg, char** arg, int& iarg, MaterialParser parse)
{
  std::vector<std::string> words(arg + iarg + 1, arg + narg);
  std::size_t used = 0;
  const std::string err = parse(words, material_, &used);
  if (!err.empty()) {
    const std::string msg = std::string(kStyle) + ": " + keyword_error(err);
    error->all(FLERR, msg.c_str());
  }
  iarg += 1 + static_cast<int>(used);
}

// fracture nodal [every N]
void FixFemBody::parse_fracture(int narg, char** arg, int& iarg)
{
  if (iarg + 1 >= narg || strcmp(arg[iarg + 1], "nodal") != 0)
    error->all(FLERR, "fix fem/body: keyword 'fracture' expects 'nodal [every N]'");
  fracture_every_ = 1;
  iarg += 2;
  while (iarg + 1 < narg) {
    if (!strcmp(arg[iarg], "every")) {
      fracture_every_ = whole_number(arg[iarg], arg[iarg + 1]);
      if (fracture_every_ < 1)
        error->all(FLERR, "fix fem/body: keyword 'fracture nodal every' expects N >= 1");
    } else if (!strcmp(arg[iarg], "erode_cracked")) {
      if (strcmp(arg[iarg + 1], "yes") && strcmp(arg[iarg + 1], "no"))
        error->all(FLERR, "fix fem/body: keyword 'fracture nodal erode_cracked' expects yes or no");
      erode_cracked_ = !strcmp(arg[iarg + 1], "yes");
    } else if (!strcmp(arg[iarg], "min_size")) {
      error->all(FLERR, "fix fem/body: keyword 'fracture nodal min_size': cracks through "
                        "elements are not available yet; cracks follow element boundaries "
                        "(leave out min_size)");
    } else {
      break;
    }
    iarg += 2;
  }
}

// bulk_viscosity off | Q1 Q2: the coefficients are checked by the core.
void FixFemBody::parse_bulk_viscosity(int narg, char** arg, int& iarg)
{
  const char* expected = "fix fem/body: keyword 'bulk_viscosity' expects 'off' or 'Q1 Q2' (linear "
                         "and quadratic coefficients, e.g. 0.06 1.2)";
  if (iarg + 1 >= narg) error->all(FLERR, expected);
  if (!strcmp(arg[iarg + 1], "off")) {
    viscosity_mode_ = 0;
    iarg += 2;
    return;
  }
  if (iarg + 2 >= narg) error->all(FLERR, expected);
  viscosity_.q1 = number(arg[iarg], arg[iarg + 1]);
  viscosity_.q2 = number(arg[iarg], arg[iarg + 2]);
  const char* bad = fracdem::bulk_viscosity_check(viscosity_);
  if (*bad) {
    const std::string msg = std::string(kStyle) + ": keyword 'bulk_viscosity': " + bad;
    error->all(FLERR, msg.c_str());
  }
  viscosity_mode_ = 1;
  iarg += 3;
}

// erosion plastic_strain EPS | damage D | min_dt DT (any of them, in any order, on one keyword):
// the values are checked against the material by the core (erosion_setup_error).
void FixFemBody::parse_erosion(int narg, char** arg, int& iarg)
{
  const std::map<std::string, double*> criteria = {{"plastic_strain", &erosion_.plastic_strain},
                                                   {"damage", &erosion_.damage},
                                                   {"min_dt", &erosion_.min_dt}};
  int used = 0;
  for (iarg += 1; iarg + 1 < narg && criteria.count(arg[iarg]); iarg += 2, ++used) {
    const std::string keyword = std::string("erosion ") + arg[iarg];
    *criteria.at(arg[iarg]) = number(keyword.c_str(), arg[iarg + 1]);
  }
  if (used == 0 || !erosion_.on())
    error->all(FLERR, "fix fem/body: keyword 'erosion' expects one or more of 'plastic_strain "
                      "EPS' (EPS > 0), 'damage D' (0 < D <= 1), 'min_dt DT' (DT > 0)");
}

// Index of the reaction account of a node group (one per group name, in order of appearance).
int FixFemBody::reaction_group(const std::string& set)
{
  auto it = std::find(reaction_groups_.begin(), reaction_groups_.end(), set);
  if (it != reaction_groups_.end()) return static_cast<int>(it - reaction_groups_.begin());
  reaction_groups_.push_back(set);
  return static_cast<int>(reaction_groups_.size()) - 1;
}

void FixFemBody::check_arguments()
{
  if (surface_type_ < 1 || surface_type_ > atom->ntypes) {
    std::string msg = std::string(kStyle) +
                      ": keyword 'type' is required and must be an atom type "
                      "between 1 and " +
                      std::to_string(atom->ntypes);
    error->all(FLERR, msg.c_str());
  }
  if (!rigid_) {
    if (!have_density_ || !have_youngs_ || !have_poisson_)
      error->all(FLERR, "fix fem/body: a deformable body needs keywords 'density', 'youngs' and "
                        "'poisson' (or 'rigid yes')");
    if (material_.rho <= 0 || material_.E <= 0)
      error->all(FLERR, "fix fem/body: 'density' and 'youngs' must be > 0");
    if (material_.nu <= -1.0 || material_.nu >= 0.5)
      error->all(FLERR, "fix fem/body: 'poisson' must lie in (-1, 0.5)");
    if (motion_.kind != fracdem::RigidMotion::None)
      error->all(FLERR, "fix fem/body: keyword 'motion' needs 'rigid yes' (deformable bodies move "
                        "by forces and 'prescribed_velocity')");
  } else {
    if (!fixed_sets_.empty() || !prescribed_velocity_.empty() || !initial_velocity_.empty())
      error->all(FLERR, "fix fem/body: 'fixed', 'velocity' and 'prescribed_velocity' apply to "
                        "deformable bodies; a rigid body moves by 'motion'");
    if (!have_density_) material_.rho = 1.0; // only used for the (unused) mass of a rigid body
    if (material_.model != fracdem::MaterialModel::Elastic || fracture_every_ > 0)
      error->all(FLERR, "fix fem/body: keywords 'material' and 'fracture' apply to deformable "
                        "bodies; a rigid body neither deforms nor breaks");
  }
  if (material_.model == fracdem::MaterialModel::Rankine) {
    try {
      fracdem::rankine_check(material_.rankine());
    } catch (const std::exception& e) {
      const std::string msg = std::string(kStyle) + ": keyword 'material rankine': " + e.what();
      error->all(FLERR, msg.c_str());
    }
  }
  if (fracture_every_ > 0 && !fracdem::material_model_info(material_.model).fractures) {
    const std::string msg = std::string(kStyle) + ": keyword 'fracture' needs a material that " +
                            "fails, e.g. 'material rankine strength FT fracture_energy GF'";
    error->all(FLERR, msg.c_str());
  }
  // A 3D mesh has no plane formulation: 'plane axisymmetric' there would silently run 3D.
  if (have_plane_ && domain->dimension == 3)
    error->all(FLERR, "fix fem/body: keyword 'plane' applies to 2D runs ('dimension 2'); this run "
                      "is 3D (leave out 'plane')");
  if (compliance_combined_ < 0) compliance_combined_ = rigid_ ? 1 : 0;
  // Default: on for shock problems (plastic materials, equations of state), off for elastic and
  // Rankine bodies, whose results stay as they were.
  if (viscosity_mode_ > 0 && rigid_)
    error->all(FLERR, "fix fem/body: keyword 'bulk_viscosity' applies to deformable bodies; a "
                      "rigid body does not deform");
  if (viscosity_mode_ < 0)
    viscosity_mode_ =
        !rigid_ && (material_.plastic_model() || material_.eos.model != fracdem::EosModel::Linear);
  viscosity_.on = viscosity_mode_ > 0;
  // Off unless asked for: with the rotating crack, contact between fragments can feed energy into
  // fully cracked elements (docs/fracture.md, restrictions).
  if (contact_bodies_ < 0) contact_bodies_ = 0;
  if (contact_bodies_ && rigid_)
    error->all(FLERR, "fix fem/body: keyword 'contact_bodies yes' needs a deformable body");
  check_erosion();
}

// Criteria out of range or that could never trigger are refused by the core, naming 'erosion'.
void FixFemBody::check_erosion()
{
  const bool asked = erosion_.plastic_strain != 0 || erosion_.damage != 0 || erosion_.min_dt != 0;
  if (asked) {
    const std::string err = fracdem::erosion_setup_error(erosion_, material_, rigid_);
    if (!err.empty()) error->all(FLERR, (std::string(kStyle) + ": " + keyword_error(err)).c_str());
  }
  if (have_erosion_mass_ && !asked && fracture_every_ == 0)
    error->all(FLERR, "fix fem/body: keyword 'erosion_mass' applies to bodies that erode "
                      "elements ('erosion ...' or 'fracture nodal')");
}

/* ---------------------------------------------------------------------- */

void FixFemBody::load_mesh()
{
  fracdem::Mesh mesh;
  try {
    mesh = fracdem::read_gmsh(mesh_file_, domain->dimension);
  } catch (const std::exception& e) {
    std::string msg = std::string(kStyle) + " " + id + ": cannot use mesh: " + e.what();
    error->all(FLERR, msg.c_str());
  }
  if (mesh.dim != domain->dimension) {
    std::string msg = std::string(kStyle) + ": mesh '" + mesh_file_ + "' is " +
                      std::to_string(mesh.dim) + "D but the simulation is " +
                      std::to_string(domain->dimension) + "D";
    error->all(FLERR, msg.c_str());
  }
  if (!fracdem::apply_transforms(mesh, transforms_))
    error->all(FLERR, "fix fem/body: 2D mesh must stay in the z = 0 plane after 'move'/'rotate'");
  for (int e = 0; e < mesh.num_elems(); ++e)
    if (!fracdem::element_geometry_finite(mesh, e)) {
      const std::string msg = std::string(kStyle) + " " + id +
                              ": keyword 'scale'/'move'/'rotate': element " + std::to_string(e) +
                              " of '" + mesh_file_ + "' overflows double precision";
      error->all(FLERR, msg.c_str());
    }
  const std::string material_error = fracdem::material_setup_error(material_, mesh.dim);
  if (!material_error.empty()) {
    const std::string msg = std::string(kStyle) + " " + id + ": " + material_error;
    error->all(FLERR, msg.c_str());
  }

  try {
    body_.build(std::move(mesh), material_, rigid_);
  } catch (const std::exception& e) {
    std::string msg =
        std::string(kStyle) + " " + id + ": bad mesh '" + mesh_file_ + "': " + e.what();
    error->all(FLERR, msg.c_str());
  }
  body_.set_rigid_motion(motion_);
  body_.set_bulk_viscosity(viscosity_);
  for (const auto& s : fixed_sets_)
    body_.set_fixed(node_set(s.set, "fixed"), s.mask, s.group);
  for (const auto& s : prescribed_velocity_)
    body_.set_prescribed_velocity(node_set(s.set, "prescribed_velocity"), s.v, s.ramp, s.group);
  for (const auto& s : initial_velocity_)
    node_set(s.set, "velocity"); // validate names now

  // Every rank holds the whole body (replicated). The element work of a material without
  // history is split evenly; one with history (softening, cracks, the viscous work of the bulk
  // viscosity) is advanced on every rank, so that every replica holds the whole material state
  // (fracture decisions, restart, energy accounts). So is an eroding body's, so that every
  // replica sees every inverted element and erodes the same elements.
  split_element_work_ =
      body_.space().state_size() == 0 && !viscosity_.on && !erosion_.on() && comm->nprocs > 1;
  if (split_element_work_) {
    const long long ne = body_.mesh().num_elems();
    body_.set_element_range(static_cast<int>((ne * comm->me) / comm->nprocs),
                            static_cast<int>((ne * (comm->me + 1)) / comm->nprocs));
  }
  rebuild_surfaces();
  check_crack_band();
  check_in_box("as placed");
  log_body();
}

// The softening law snaps back in elements wider than 2 E G_f / f_t^2: refuse them by name.
void FixFemBody::check_crack_band()
{
  if (material_.model != fracdem::MaterialModel::Rankine) return;
  const double limit = fracdem::rankine_snapback_length(material_.rankine());
  const fracdem::Mesh& mesh = body_.mesh();
  int worst = -1;
  double hmax = 0;
  for (int e = 0; e < mesh.num_elems(); ++e) {
    const double h = fracdem::element_diameter(mesh, e);
    if (h > hmax) {
      hmax = h;
      worst = e;
    }
  }
  if (hmax >= limit) {
    char msg[512];
    snprintf(msg, sizeof(msg),
             "fix fem/body %s: keyword 'material rankine': element %d of mesh '%s' is %g wide, "
             "above the snap-back limit 2 E G_f / f_t^2 = %g of its softening law; refine the "
             "mesh to elements below %g (or raise fracture_energy / lower strength)",
             id, worst, mesh_file_.c_str(), hmax, limit, limit);
    error->all(FLERR, msg);
  }
}

/* ----------------------------------------------------------------------
   the body in the simulation box
------------------------------------------------------------------------- */

// Particles live inside the box. Beyond a fixed face they are lost, so the body's surface must
// lie inside the fixed faces. Across a periodic boundary the particles' images (one period away)
// meet the body, so it may cross the boundary, but not be longer than the period (it would
// overlap its own image) nor lie more than a period outside. A shrink-wrapped face follows the
// particles to wherever the body is. Only surface nodes count: nothing else can be hit (the free
// nodes of eroded elements may fly anywhere). Slack: the contact search buffer.
std::string FixFemBody::box_violation() const
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
    const std::string axis(1, "xyz"[d]);
    std::string why;
    if (domain->periodicity[d]) {
      const double period = bhi[d] - blo[d];
      if (hi[d] - lo[d] > period + slack)
        why = " is longer than its period in the periodic dimension " + axis +
              "; it would overlap its own periodic image: shorten it or enlarge the box in " + axis;
      else if (lo[d] < blo[d] - period - slack || hi[d] > bhi[d] + period + slack)
        why = " lies more than a period outside it in the periodic dimension " + axis +
              ", beyond the reach of the particles' images: move it into the box";
    } else {
      for (int side = 0; side < 2 && why.empty(); ++side) {
        const bool out = side == 0 ? lo[d] < blo[d] - slack : hi[d] > bhi[d] + slack;
        if (out && domain->boundary[d][side] == 1) // 2, 3: shrink-wrapped
          why = " reaches beyond its fixed " + axis + (side ? "-high" : "-low") +
                " face; particles are lost beyond a fixed face, so they cannot hit "
                "that part: keep the body inside or enlarge the box";
      }
    }
    if (why.empty()) continue;
    std::string extent = "the body (", box = " in the box (";
    for (int e = 0; e < dim; ++e) {
      char r[96];
      snprintf(r, sizeof r, "%s%c %g to %g", e ? ", " : "", "xyz"[e], lo[e], hi[e]);
      extent += r;
      snprintf(r, sizeof r, "%s%c %g to %g", e ? ", " : "", "xyz"[e], blo[e], bhi[e]);
      box += r;
    }
    return extent + ")" + box + ")" + why;
  }
  return "";
}

// A body placed outside, or a rigid body outside (carried there by its prescribed motion, or
// left there by 'change_box'), is an input mistake: refused. A deformable body gets out by its
// own dynamics (fragments thrown off, a body pushed out): only the part outside is out of the
// particles' reach, so the run goes on with one warning.
// when: "as placed" (fix command), "at the start of the run", or nullptr: at this step.
void FixFemBody::check_in_box(const char* when)
{
  const bool placed = when && !strcmp(when, "as placed");
  if (!placed && !rigid_ && warned_outside_) return;
  const std::string where = box_violation();
  if (where.empty()) return;
  char step[64];
  snprintf(step, sizeof step, "at step " BIGINT_FORMAT, update->ntimestep);
  std::string msg =
      std::string(kStyle) + " " + id + ": mesh '" + mesh_file_ + "' " + (when ? when : step) + ": ";
  if (placed) {
    error->all(FLERR, (msg + where + " (keywords 'move', 'scale', 'rotate' place it)").c_str());
  } else if (rigid_) {
    if (motion_.kind != fracdem::RigidMotion::None)
      msg += "its prescribed 'motion' has carried it out of the box: ";
    error->all(FLERR, (msg + where).c_str());
  }
  warned_outside_ = true;
  msg += "its nodes have moved out of the box: " + where + " (warned once; the run goes on)";
  if (comm->me == 0) error->warning(FLERR, msg.c_str());
}

void FixFemBody::log_body()
{
  if (comm->me != 0) return;
  char line[512];
  char viscosity[96] = "";
  if (viscosity_.on)
    snprintf(viscosity, sizeof(viscosity), ", bulk viscosity %g %g", viscosity_.q1, viscosity_.q2);
  snprintf(line, sizeof(line),
           "fix fem/body %s: %s, %d nodes, %d elements, %zu boundary facets, %s%s%s\n", id,
           mesh_file_.c_str(), body_.num_nodes(), body_.mesh().num_elems(),
           contact_.facets().size(), rigid_ ? "rigid" : "deformable ",
           rigid_ ? ""
                  : (material_.kinematics == fracdem::Kinematics::Corotational
                         ? "corotational"
                         : "small-strain elastic"),
           viscosity);
  if (screen) fputs(line, screen);
  if (logfile) fputs(line, logfile);
}

std::vector<int> FixFemBody::node_set(const std::string& name, const char* keyword) const
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
    std::string msg = std::string(kStyle) + ": keyword '" + keyword + "': mesh '" + mesh_file_ +
                      "' has no physical group '" + name + "'; it has:";
    for (const auto& kv : mesh.node_sets)
      msg += " " + kv.first;
    msg += " (and 'all')";
    error->all(FLERR, msg.c_str());
  }
  return it->second;
}

/* ---------------------------------------------------------------------- */

void FixFemBody::read_contact_properties()
{
  const int ntypes = atom->ntypes;
  auto global = [&](const char* name, const char* kind, int n1, int n2) {
    return static_cast<FixPropertyGlobal*>(
        modify->find_fix_property(name, "property/global", kind, n1, n2, style));
  };
  FixPropertyGlobal* E = global("youngsModulus", "peratomtype", ntypes, 0);
  FixPropertyGlobal* nu = global("poissonsRatio", "peratomtype", ntypes, 0);
  FixPropertyGlobal* e = global("coefficientRestitution", "peratomtypepair", ntypes, ntypes);
  FixPropertyGlobal* mu = global("coefficientFriction", "peratomtypepair", ntypes, ntypes);
  double char_vel = 1.0;
  if (normal_model_ == fracdem::NormalModel::Hooke) {
    Fix* cv = modify->find_fix_property("characteristicVelocity", "property/global", "scalar", 0, 0,
                                        style);
    char_vel = static_cast<FixPropertyGlobal*>(cv)->compute_scalar();
  }
  // The surface's own compliance enters only where the law carries it (rigid bodies by default).
  const double surface_E = compliance_combined_ ? E->compute_vector(surface_type_ - 1) : 0.0;
  const double surface_nu = compliance_combined_ ? nu->compute_vector(surface_type_ - 1) : 0.0;
  std::vector<fracdem::ContactMaterial> per_type(ntypes + 1);
  for (int t = 1; t <= ntypes; ++t)
    per_type[t] = fracdem::mix_materials(
        E->compute_vector(t - 1), nu->compute_vector(t - 1), surface_E, surface_nu,
        e->compute_array(t - 1, surface_type_ - 1), mu->compute_array(t - 1, surface_type_ - 1),
        char_vel, normal_model_, tangential_history_);
  contact_.set_materials(std::move(per_type));
}

void FixFemBody::init()
{
  check_restart_records();
  fe_only_.init(this);
  fracdem::ParticleFacetOptions opt;
  opt.model = normal_model_;
  opt.tangential_history = tangential_history_;
  opt.hertz_patch =
      !rigid_ && !compliance_combined_ && normal_model_ == fracdem::NormalModel::Hertz;
  buffer_ = buffer_ >= 0 ? buffer_ : neighbor->skin;
  opt.buffer = buffer_;
  contact_.configure(opt);
  read_contact_properties();
  if (contact_bodies_) find_contact_partners();

  gravity_[0] = gravity_[1] = gravity_[2] = 0;
  if (apply_gravity_ && !rigid_) {
    for (int i = 0; i < modify->nfix; ++i)
      if (!strcmp(modify->fix[i]->style, "gravity"))
        static_cast<FixGravity*>(modify->fix[i])->get_gravity(gravity_);
  }
  if (!energy_file_.empty() && comm->me == 0 && !energy_fp_) {
    energy_fp_ = fopen(energy_file_.c_str(), "w");
    if (!energy_fp_) {
      std::string msg = std::string(kStyle) + ": keyword 'energy_file': cannot open '" +
                        energy_file_ + "' for writing";
      error->one(FLERR, msg.c_str());
    }
    // The material's dissipation: cracking, or the plastic work of a plastic material (which
    // does not crack); the bulk viscosity's work has a column of its own.
    fprintf(energy_fp_,
            "step,time,kinetic,strain,external_work,contact_work,total,nodes,elements,"
            "%s,split_nodes,fragments,boundary_work%s%s%s",
            material_.plastic_model() ? "plastic_work" : "fracture_energy",
            viscosity_.on ? ",viscous_work" : "",
            can_erode() ? ",eroded_elements,eroded_mass,eroded_energy" : "",
            body_.space().axisymmetric() ? ",shield_work" : "");
    for (const std::string& g : reaction_groups_)
      fprintf(energy_fp_, ",reaction_%s_x,reaction_%s_y,reaction_%s_z", g.c_str(), g.c_str(),
              g.c_str());
    for (const std::string& g : reaction_groups_)
      fprintf(energy_fp_, ",displacement_%s_x,displacement_%s_y,displacement_%s_z", g.c_str(),
              g.c_str(), g.c_str());
    fputc('\n', energy_fp_);
  }
  check_time_step();
}

void FixFemBody::reset_dt()
{
  check_time_step();
}

// With 'erosion min_dt DT' the elements below DT leave at the first force evaluation: the step
// that counts is that of the others.
void FixFemBody::check_time_step()
{
  if (rigid_) return;
  dt_stable_ = fracdem::stable_time_step_after_erosion(body_, erosion_);
  const double dt = update->dt;
  if (comm->me == 0) {
    char line[256];
    snprintf(line, sizeof(line),
             "fix fem/body %s: stable FE time step %.6g, host time step %.6g (%.1f%%)%s\n", id,
             dt_stable_, dt, 100.0 * dt / dt_stable_,
             erosion_.min_dt > 0 ? " without the elements below erosion min_dt" : "");
    if (screen) fputs(line, screen);
    if (logfile) fputs(line, logfile);
  }
  if (dt > dt_stable_) {
    char msg[512];
    snprintf(msg, sizeof(msg),
             "fix fem/body %s: host timestep %g exceeds the stable FE time step %g of mesh '%s'; "
             "reduce 'timestep' or coarsen the mesh (keyword 'dt_check warn' runs anyway)",
             id, dt, dt_stable_, mesh_file_.c_str());
    if (dt_check_error_)
      error->all(FLERR, msg);
    else if (comm->me == 0)
      error->warning(FLERR, msg);
  }
}

/* ---------------------------------------------------------------------- */

void FixFemBody::setup(int /*vflag*/)
{
  if (!initial_velocity_applied_ && !restarted_state_) {
    for (const auto& s : initial_velocity_)
      body_.set_velocity(node_set(s.set, "velocity"), s.v);
    body_.impose_velocity_conditions();
  }
  initial_velocity_applied_ = true;
  if (rigid_) body_.move_rigid();
  check_in_box("at the start of the run"); // restart, change_box and earlier runs move it
  contact_.invalidate_search();
  compute_forces();
  log_memory();
  if (energy_fp_ && update->ntimestep % energy_every_ == 0) write_energy_row();
}

// The host drops particles outside the box when it re-neighbours: the body is checked then too,
// and every kBoxCheckEvery steps (a scene without moving particles never re-neighbours).
void FixFemBody::pre_neighbor()
{
  contact_.invalidate_search();
  check_in_box(nullptr);
}

/* ----------------------------------------------------------------------
   velocity Verlet, in step with the host: half kick + drift here,
   forces in post_force, second half kick in final_integrate.
------------------------------------------------------------------------- */

void FixFemBody::initial_integrate(int /*vflag*/)
{
  body_.advance_time(update->dt);
  if (rigid_)
    body_.move_rigid();
  else
    body_.half_kick_drift(update->dt);
  if (update->ntimestep % kBoxCheckEvery == 0) check_in_box(nullptr);
}

void FixFemBody::post_force(int /*vflag*/)
{
  compute_forces();
}

void FixFemBody::final_integrate()
{
  if (rigid_) return;
  body_.half_kick(update->dt);
  if (fracture_every_ > 0 && update->ntimestep % fracture_every_ == 0) fracture();
  if (energy_fp_ && update->ntimestep % energy_every_ == 0) write_energy_row();
}

fracdem::ParticleArrays FixFemBody::particle_arrays() const
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
  const int* periodic[3] = {&domain->xperiodic, &domain->yperiodic, &domain->zperiodic};
  for (int d = 0; d < domain->dimension; ++d)
    if (*periodic[d]) p.period[d] = domain->prd[d];
  p.history = history_;
  p.slots = nslots_;
  return p;
}

void FixFemBody::compute_forces()
{
  const int nn = body_.num_nodes();
  body_.begin_forces();

  // Local shares: internal forces of this rank's elements, contact forces of this rank's
  // particles; one reduction makes every replica identical.
  int first_inverted = -1;
  const double local_energy = internal_forces(first_inverted);
  // Contact between the body's pieces and with other bodies: taken once, on rank 0, into the
  // contact forces that the ranks sum.
  if (contact_bodies_ && comm->me == 0) body_contacts();
  const fracdem::ParticleFacetResult res =
      contact_.evaluate(particle_arrays(), body_.mesh().X.data(), body_.positions().data(),
                        body_.velocities().data(), update->dt, body_.contact_forces());
  if (res.history_exhausted && !warned_slots_) {
    error->warning(FLERR, "fix fem/body: a particle has more simultaneous facet contacts than "
                          "'history_slots'; extra contacts run without tangential history");
    warned_slots_ = true;
  }

  // energy, contacts, unresolved contacts (summed); first inverted element + 1 (max)
  double scalars[4] = {local_energy, static_cast<double>(res.contacts),
                       res.unresolved_speed > 0 ? 1.0 : 0.0,
                       static_cast<double>(first_inverted >= 0 ? first_inverted + 1 : 0)};
  if (split_element_work_) {
    MPI_Allreduce(MPI_IN_PLACE, body_.forces_data(), 3 * nn, MPI_DOUBLE, MPI_SUM, world);
    MPI_Allreduce(MPI_IN_PLACE, body_.contact_forces(), 3 * nn, MPI_DOUBLE, MPI_SUM, world);
    MPI_Allreduce(MPI_IN_PLACE, scalars, 3, MPI_DOUBLE, MPI_SUM, world);
    MPI_Allreduce(MPI_IN_PLACE, &scalars[3], 1, MPI_DOUBLE, MPI_MAX, world);
  } else if (comm->nprocs > 1) { // element work replicated: only the contact shares are summed
    MPI_Allreduce(MPI_IN_PLACE, body_.contact_forces(), 3 * nn, MPI_DOUBLE, MPI_SUM, world);
    MPI_Allreduce(MPI_IN_PLACE, &scalars[1], 2, MPI_DOUBLE, MPI_SUM, world);
  }
  ncontacts_ = static_cast<int>(scalars[1]);
  if (scalars[2] > 0 && !warned_unresolved_) warn_unresolved_contact(res);
  if (scalars[3] > 0) {
    char msg[256];
    snprintf(msg, sizeof(msg),
             "fix fem/body %s: element %d inverted (det F <= 0) at step " BIGINT_FORMAT
             "; the time step is too large or the load too severe for this mesh",
             id, static_cast<int>(scalars[3]) - 1, update->ntimestep);
    error->all(FLERR, msg);
  }
  if (!std::isfinite(scalars[0])) {
    char msg[256];
    snprintf(msg, sizeof(msg),
             "fix fem/body %s: non-finite strain energy at step " BIGINT_FORMAT
             " (NaN/Inf in the body state)",
             id, update->ntimestep);
    error->all(FLERR, msg);
  }
  body_.finish_forces(scalars[0], gravity_, update->dt, update->setupflag == 0);
}

// Internal forces of this rank's elements; returns their strain energy. A breaking or eroding
// body erodes an element that inverts (it would only produce garbage), an eroding body also the
// elements that meet its criteria, and the step's internal forces are taken again (the material
// history does not advance twice). Its element work is replicated, so every rank does the same.
// Otherwise an inverted element is left in first_inverted (the run stops).
double FixFemBody::internal_forces(int& first_inverted)
{
  first_inverted = -1;
  double energy = body_.add_internal_forces(&first_inverted);
  if (erosion_.on()) return forces_after_erosion(energy, first_inverted);
  while (first_inverted >= 0 && fracture_every_ > 0 && !split_element_work_) {
    erode_inverted(first_inverted);
    body_.clear_internal_forces();
    first_inverted = -1;
    energy = body_.add_internal_forces(&first_inverted);
  }
  return energy;
}

// erosion ...: the elements that meet a criterion and any that inverted leave in one batch, then
// the forces are taken again until no element inverts; one log line per step. energy: that of
// the evaluation before.
double FixFemBody::forces_after_erosion(double energy, int& first_inverted)
{
  std::vector<int> elems;
  std::vector<fracdem::ErosionCause> causes;
  fracdem::select_eroding(body_, erosion_, elems, causes);
  int counts[fracdem::kErosionCauses] = {0, 0, 0, 0};
  std::vector<int> batch; // every element this step, for the log
  for (;;) {
    if (first_inverted >= 0 &&
        std::find(elems.begin(), elems.end(), first_inverted) == elems.end()) {
      elems.push_back(first_inverted);
      causes.push_back(fracdem::ErosionCause::Inverted);
    }
    if (elems.empty()) break;
    for (fracdem::ErosionCause c : causes)
      ++counts[static_cast<int>(c)];
    batch.insert(batch.end(), elems.begin(), elems.end());
    body_.erode(elems, erosion_.remove_mass);
    elems.clear();
    causes.clear();
    body_.clear_internal_forces();
    first_inverted = -1;
    energy = body_.add_internal_forces(&first_inverted);
  }
  if (!batch.empty()) after_erosion(counts, batch);
  return energy;
}

// After an erosion batch: the exposed faces join contact at once, the batch is logged in one
// line, and the stable step is taken again. With 'erosion min_dt DT' at or above the host step
// no element is left below the host step; otherwise a squeezed element that no criterion removes
// is warned about (once), as erosion never stops the run.
void FixFemBody::after_erosion(const int* counts, const std::vector<int>& batch)
{
  rebuild_surfaces();
  if (comm->me == 0) log_erosion(counts, batch);
  dt_stable_ = body_.stable_time_step();
  if (dt_stable_ >= update->dt || warned_dt_after_erosion_) return;
  warned_dt_after_erosion_ = true;
  char msg[400];
  snprintf(msg, sizeof(msg),
           "fix fem/body %s: after the erosion at step " BIGINT_FORMAT
           " the stable FE time step is %g, below the host time step %g (an element squeezed "
           "that no erosion criterion removes); 'erosion min_dt %g' erodes such elements "
           "(warned once)",
           id, update->ntimestep, dt_stable_, update->dt, update->dt);
  if (comm->me == 0) error->warning(FLERR, msg);
}

// One line per step: how many left, why, which (the first kMaxListed), and the totals.
void FixFemBody::log_erosion(const int* counts, const std::vector<int>& batch)
{
  constexpr std::size_t kMaxListed = 12;
  std::string why, which;
  for (int c = 0; c < fracdem::kErosionCauses; ++c)
    if (counts[c] > 0)
      why += (why.empty() ? "" : ", ") +
             std::string(fracdem::erosion_cause_name(static_cast<fracdem::ErosionCause>(c))) + " " +
             std::to_string(counts[c]);
  for (std::size_t k = 0; k < batch.size() && k < kMaxListed; ++k)
    which += " " + std::to_string(batch[k]);
  if (batch.size() > kMaxListed) which += " ...";
  const fracdem::ErosionAccount& acc = body_.eroded();
  char tail[160];
  snprintf(tail, sizeof(tail), "; %d eroded in all, mass %.6g removed, energy %.6g\n", acc.elements,
           acc.mass, acc.energy);
  const std::string line = "fix fem/body " + std::string(id) + ": step " +
                           std::to_string(update->ntimestep) + ": eroded " +
                           std::to_string(batch.size()) + " elements (" + why + "):" + which + tail;
  if (logfile) fputs(line.c_str(), logfile);
  if (screen) fputs(line.c_str(), screen);
}

// Once per run: a particle hits the body faster than the time step can follow (every rank
// enters; the worst speed and the time step that resolves it come from all ranks).
void FixFemBody::warn_unresolved_contact(const fracdem::ParticleFacetResult& res)
{
  warned_unresolved_ = true;
  double speed = res.unresolved_speed, dt_ok = res.resolving_dt;
  MPI_Allreduce(MPI_IN_PLACE, &speed, 1, MPI_DOUBLE, MPI_MAX, world);
  MPI_Allreduce(MPI_IN_PLACE, &dt_ok, 1, MPI_DOUBLE, MPI_MIN, world);
  char msg[400];
  snprintf(msg, sizeof(msg),
           "fix fem/body %s: at step " BIGINT_FORMAT " a particle approaches the surface at "
           "%g m/s, more than %g %% of its Hertz penetration per time step; the contact is not "
           "resolved in time and may gain or lose energy: timestep %g or smaller resolves it",
           id, update->ntimestep, speed, 100 * fracdem::kMaxApproachPerStep, dt_ok);
  if (comm->me == 0) error->warning(FLERR, msg);
}

/* ---------------------------------------------------------------------- */

double FixFemBody::compute_scalar()
{
  return body_.kinetic_energy() + body_.strain_energy();
}

double FixFemBody::compute_vector(int i)
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
  case kDissipated: // the material's and the bulk viscosity's: the energy balance's dissipation
    return body_.dissipated_energy() + body_.viscous_work();
  case kSplitNodes:
    return split_nodes();
  case kFragments:
    return fragments();
  case kBoundaryWork:
    return body_.boundary_work();
  }
  const int tail = kVectorSize + 3 * static_cast<int>(reaction_groups_.size());
  if (i >= kVectorSize && i < tail) {
    const auto& r = body_.reactions();
    const size_t k = static_cast<size_t>(i - kVectorSize);
    return k < r.size() ? r[k] : 0.0;
  }
  switch (i - tail) {
  case kErodedElements:
    return body_.eroded().elements;
  case kErodedMass:
    return body_.eroded().mass;
  case kErodedEnergy:
    return body_.eroded().energy;
  case kShieldWork:
    return body_.shield_work();
  }
  return 0.0;
}

// After a topology change: particle contact and the contact between the body's own pieces.
void FixFemBody::rebuild_surfaces()
{
  contact_.rebuild_surface(body_.mesh());
  if (!contact_bodies_) return;
  surface_.build(body_.mesh(), contact_.facets());
  self_contact_.invalidate();
  for (Partner& p : partners_) {
    p.mine_on_theirs.invalidate();
    p.theirs_on_mine.invalidate();
  }
  for (FixFemBody* other : contact_partner_of_)
    other->partner_changed(this);
}

// Penalty and friction of the contact between the surfaces of types ti and tj (bodies of
// moduli Ei, Ej): the softer body's modulus, coefficientFriction of the type pair.
fracdem::SurfaceContactOptions FixFemBody::surface_options(int other_type, double other_E) const
{
  fracdem::SurfaceContactOptions so;
  so.youngs = std::min(material_.E, other_E);
  so.penalty_scale = contact_penalty_;
  so.thickness = domain->dimension == 2 ? material_.thickness : 1.0;
  so.axisymmetric = body_.space().axisymmetric();
  auto* mu = static_cast<FixPropertyGlobal*>(
      modify->find_fix_property("coefficientFriction", "property/global", "peratomtypepair",
                                atom->ntypes, atom->ntypes, style));
  so.friction = mu->compute_array(surface_type_ - 1, other_type - 1);
  return so;
}

// This body handles its own pieces and every later fix fem/body with contact_bodies yes.
void FixFemBody::find_contact_partners()
{
  self_contact_.configure(surface_options(surface_type_, material_.E));
  partners_.clear();
  contact_partner_of_.clear();
  bool after = false;
  for (int i = 0; i < modify->nfix; ++i) {
    auto* other = dynamic_cast<FixFemBody*>(modify->fix[i]);
    if (other == this) {
      after = true;
    } else if (other && other->contact_bodies_ > 0) {
      if (after) {
        partners_.emplace_back();
        partners_.back().other = other;
        const auto so = surface_options(other->surface_type_, other->material_.E);
        partners_.back().mine_on_theirs.configure(so);
        partners_.back().theirs_on_mine.configure(so);
      } else {
        contact_partner_of_.push_back(other);
      }
    }
  }
  rebuild_surfaces();
}

void FixFemBody::partner_changed(FixFemBody* other)
{
  for (Partner& p : partners_)
    if (p.other == other) {
      p.mine_on_theirs.invalidate();
      p.theirs_on_mine.invalidate();
    }
}

int FixFemBody::body_contacts()
{
  fracdem::ContactBodyState me{body_.positions().data(), body_.velocities().data(),
                               body_.masses().data(), body_.contact_forces()};
  int n = self_contact_.evaluate(surface_, me, surface_, me, true, update->dt);
  for (Partner& p : partners_) {
    fracdem::Body& ob = p.other->body_;
    fracdem::ContactBodyState them{ob.positions().data(), ob.velocities().data(),
                                   ob.masses().data(), ob.pending_contact_forces()};
    n += p.mine_on_theirs.evaluate(surface_, me, p.other->surface_, them, false, update->dt);
    n += p.theirs_on_mine.evaluate(p.other->surface_, them, surface_, me, false, update->dt);
  }
  return n;
}

void FixFemBody::erode_inverted(int e)
{
  body_.erode({e}, erosion_.remove_mass);
  rebuild_surfaces();
  if (comm->me == 0) {
    char line[256];
    snprintf(line, sizeof(line),
             "fix fem/body %s: step " BIGINT_FORMAT
             ": element %d inverted (det F <= 0) and was eroded; its nodes keep their mass\n",
             id, update->ntimestep, e);
    if (logfile) fputs(line, logfile);
    if (screen) fputs(line, screen);
  }
}

// When the body has come apart into more pieces: their count and masses, largest first.
void FixFemBody::log_fragments()
{
  const std::vector<double> mass = fracdem::fragment_masses(body_);
  const int count = static_cast<int>(mass.size());
  if (count == last_fragments_ || comm->me != 0) {
    last_fragments_ = count;
    return;
  }
  last_fragments_ = count;
  std::string line = "fix fem/body " + std::string(id) + ": step " +
                     std::to_string(update->ntimestep) + ": " + std::to_string(count) +
                     " fragments, masses";
  for (size_t k = 0; k < mass.size() && k < 8; ++k) {
    char m[32];
    snprintf(m, sizeof(m), " %.4g", mass[k]);
    line += m;
  }
  line += mass.size() > 8 ? " ...\n" : "\n";
  if (logfile) fputs(line.c_str(), logfile);
  if (screen) fputs(line.c_str(), screen);
}

int FixFemBody::split_nodes() const
{
  const auto& parents = body_.parents();
  return static_cast<int>(parents.size() - std::count(parents.begin(), parents.end(), -1));
}

int FixFemBody::fragments() const
{
  std::vector<int> comp;
  return fracdem::element_components(body_.mesh(), comp);
}

/* ----------------------------------------------------------------------
   nodal fracture: failure map, crack points, node splits (every replica
   makes the same splits from the same state), then the new crack faces
   join the contact surface at once
------------------------------------------------------------------------- */

void FixFemBody::fracture()
{
  // An intact body (no damaged point in the last force evaluation; the element work of a
  // breaking body is done on every rank, so all see the same count) has nothing to check.
  if (body_.damaged_points() == 0) return;
  fracdem::FailureMap& map = failure_map_; // kept between checks: no allocation per check
  if (fracdem::build_failure_map(body_, map) == 0) return;
  const std::vector<int> points = fracdem::crack_points(map);
  std::vector<fracdem::SplitEvent> events;
  if (!points.empty()) events = fracdem::insert_cracks(body_, points);
  const int eroded = erode_collapsed(map.element_measure);
  if (events.empty() && eroded == 0) return;
  // Replicas must stay identical: a rank that split differently stops the run at once.
  int counts[2] = {body_.num_nodes(), -body_.num_nodes()};
  MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_INT, MPI_MAX, world);
  if (counts[0] != -counts[1])
    error->all(FLERR, "fix fem/body: ranks disagree on the cracked topology (replicas diverged)");
  rebuild_surfaces();
  log_splits(events);
  log_fragments();
  dt_stable_ = body_.stable_time_step();
  if (dt_stable_ < update->dt) {
    char msg[256];
    snprintf(msg, sizeof(msg),
             "fix fem/body %s: at step " BIGINT_FORMAT
             " the stable FE time step of the cracked body is %g < host time step %g",
             id, update->ntimestep, dt_stable_, update->dt);
    if (dt_check_error_)
      error->all(FLERR, msg);
    else if (comm->me == 0)
      error->warning(FLERR, msg);
  }
}

// A failed element (no tension left) that has been squeezed into a sliver would collapse the
// stable time step of the whole body: it is eroded (logged; its nodes keep their mass).
int FixFemBody::erode_collapsed(const std::vector<double>& failure)
{
  std::vector<int> eroded;
  const fracdem::Mesh& mesh = body_.mesh();
  for (int e = 0; e < static_cast<int>(failure.size()); ++e) {
    if (!mesh.active[e] || failure[e] < 1.0) continue;
    if (!erode_cracked_ && body_.element_time_step(e) >= update->dt) continue;
    eroded.push_back(e);
    if (comm->me != 0) continue;
    char line[256];
    snprintf(line, sizeof(line),
             "fix fem/body %s: step " BIGINT_FORMAT ": failed element %d %s, eroded\n", id,
             update->ntimestep, e,
             erode_cracked_ ? "carries no more tension" : "squeezed below the host time step");
    if (logfile) fputs(line, logfile);
    if (screen) fputs(line, screen);
  }
  body_.erode(eroded, erosion_.remove_mass);
  return static_cast<int>(eroded.size());
}

void FixFemBody::log_splits(const std::vector<fracdem::SplitEvent>& events)
{
  if (comm->me != 0) return;
  for (const fracdem::SplitEvent& ev : events) {
    char line[256];
    snprintf(line, sizeof(line),
             "fix fem/body %s: step " BIGINT_FORMAT
             ": crack at node %d -> new node %d, normal (%.3f %.3f %.3f), %d elements moved\n",
             id, update->ntimestep, ev.node, ev.copy, ev.normal[0], ev.normal[1], ev.normal[2],
             ev.elements_moved);
    if (logfile) fputs(line, logfile);
    if (screen && events.size() <= 4) fputs(line, screen);
  }
  if (screen && events.size() > 4)
    fprintf(screen, "fix fem/body %s: step " BIGINT_FORMAT ": %zu node splits (see log)\n", id,
            update->ntimestep, events.size());
}

void FixFemBody::write_energy_row()
{
  if (update->ntimestep == last_energy_step_) return; // a new run starts where the last ended
  last_energy_step_ = update->ntimestep;
  const double ke = body_.kinetic_energy(), se = body_.strain_energy();
  fprintf(energy_fp_, BIGINT_FORMAT ",%.10g,%.12g,%.12g,%.12g,%.12g,%.12g,%d,%d,%.12g,%d,%d,%.12g",
          update->ntimestep, body_.time(), ke, se, body_.external_work(), body_.contact_work(),
          ke + se, body_.num_nodes(), body_.mesh().num_active_elems(), body_.dissipated_energy(),
          split_nodes(), fragments(), body_.boundary_work());
  if (viscosity_.on) fprintf(energy_fp_, ",%.12g", body_.viscous_work());
  if (can_erode())
    fprintf(energy_fp_, ",%d,%.12g,%.12g", body_.eroded().elements, body_.eroded().mass,
            body_.eroded().energy);
  if (body_.space().axisymmetric()) fprintf(energy_fp_, ",%.12g", body_.shield_work());
  const auto& r = body_.reactions();
  for (size_t k = 0; k < 3 * reaction_groups_.size(); ++k)
    fprintf(energy_fp_, ",%.12g", k < r.size() ? r[k] : 0.0);
  // Mean displacement of each group's nodes (load-displacement curves).
  for (const std::string& g : reaction_groups_) {
    const std::vector<int> nodes = node_set(g, "energy_file");
    double u[3] = {0, 0, 0};
    for (int n : nodes)
      for (int d = 0; d < 3; ++d)
        u[d] += (body_.positions()[3 * n + d] - body_.mesh().X[3 * n + d]) / nodes.size();
    fprintf(energy_fp_, ",%.12g,%.12g,%.12g", u[0], u[1], u[2]);
  }
  fputc('\n', energy_fp_);
  fflush(energy_fp_);
}

/* ----------------------------------------------------------------------
   restart: the mesh is re-read from the same file when the input script
   re-creates the fix; the body's state, topology included, is restored
   from the restart file.
------------------------------------------------------------------------- */

namespace
{

// The adapter's head of the record, before the body's own (Body::pack_state): this marker (a body
// record starts with its version, 1 or 2), the number of doubles that follow in the head, then
// rigid (0 / 1), the number of placement transforms and 5 doubles per transform (kind, a[4]).
// Records written without the head start with the body record and are read as before.
constexpr double kRecordHead = -1.0;

// The placement keywords as the input writes them.
std::string placement_text(bool rigid, const std::vector<fracdem::MeshTransform>& transforms)
{
  std::string text = rigid ? "rigid yes" : "rigid no";
  for (const fracdem::MeshTransform& t : transforms) {
    char w[160];
    if (t.kind == fracdem::MeshTransform::Scale)
      snprintf(w, sizeof w, " scale %g", t.a[0]);
    else if (t.kind == fracdem::MeshTransform::Move)
      snprintf(w, sizeof w, " move %g %g %g", t.a[0], t.a[1], t.a[2]);
    else
      snprintf(w, sizeof w, " rotate axis %g %g %g angle %g", t.a[0], t.a[1], t.a[2],
               t.a[3] * 180.0 / M_PI);
    text += w;
  }
  return text;
}

bool same_placement(const std::vector<fracdem::MeshTransform>& a,
                    const std::vector<fracdem::MeshTransform>& b)
{
  if (a.size() != b.size()) return false;
  for (size_t k = 0; k < a.size(); ++k) {
    if (a[k].kind != b[k].kind) return false;
    for (int i = 0; i < 4; ++i)
      if (std::fabs(a[k].a[i] - b[k].a[i]) > 1e-12 * std::max(1.0, std::fabs(a[k].a[i])))
        return false;
  }
  return true;
}

} // namespace

void FixFemBody::write_restart(FILE* fp)
{
  if (comm->me != 0) return;
  std::vector<double> buf = {kRecordHead, 0.0, rigid_ ? 1.0 : 0.0,
                             static_cast<double>(transforms_.size())};
  for (const fracdem::MeshTransform& t : transforms_) {
    buf.push_back(static_cast<double>(t.kind));
    buf.insert(buf.end(), t.a, t.a + 4);
  }
  buf[1] = static_cast<double>(buf.size() - 2);
  std::vector<double> body;
  body_.pack_state(body);
  buf.insert(buf.end(), body.begin(), body.end());
  // The host reads the size in bytes, then that many bytes.
  const int nbytes = static_cast<int>(buf.size() * sizeof(double));
  fwrite(&nbytes, sizeof(int), 1, fp);
  fwrite(buf.data(), sizeof(double), buf.size(), fp);
}

// The stored state keeps the stored placement (reference coordinates included), so a command
// that places the body otherwise, or changes 'rigid', would be silently overruled: refused.
void FixFemBody::check_stored_placement(const double* head, int n)
{
  const int nt = n >= 2 ? static_cast<int>(head[1]) : -1;
  if (nt < 0 || n < 2 + 5 * nt) error->all(FLERR, "fix fem/body: corrupt restart record");
  std::vector<fracdem::MeshTransform> stored(nt);
  for (int k = 0; k < nt; ++k) {
    stored[k].kind = static_cast<fracdem::MeshTransform::Kind>(static_cast<int>(head[2 + 5 * k]));
    std::copy(head + 3 + 5 * k, head + 7 + 5 * k, stored[k].a);
  }
  const bool rigid = head[0] != 0.0;
  if (rigid == rigid_ && same_placement(stored, transforms_)) return;
  const std::string msg = std::string(kStyle) + " " + id +
                          ": the restart file holds this body with '" +
                          placement_text(rigid, stored) + "' but this command gives '" +
                          placement_text(rigid_, transforms_) +
                          "'; the body continues from the stored state and placement, so give "
                          "the stored keywords (to start the body afresh from its mesh instead, "
                          "put 'run 0' before this fix command: a run drops the file's fix "
                          "states)";
  error->all(FLERR, msg.c_str());
}

void FixFemBody::restart(char* raw)
{
  const double* record = reinterpret_cast<const double*>(raw);
  if (record[0] == kRecordHead) {
    check_stored_placement(record + 2, static_cast<int>(record[1]));
    record += 2 + static_cast<int>(record[1]);
  }
  try {
    body_.unpack_state(record);
  } catch (const std::exception& e) {
    std::string msg = std::string(kStyle) + " " + id + ": " + e.what() + " (mesh '" + mesh_file_ +
                      "'); use the same mesh file and transforms as the run that wrote it";
    error->all(FLERR, msg.c_str());
  }
  rebuild_surfaces();
  restarted_state_ = true;
}

// The host hands a fix its restart record by fix ID (and style) only: a fix fem/body whose ID
// the file does not hold starts from its mesh. When the file holds a body under another ID, that
// is most often a renamed fix, which would silently start the body afresh. The host drops the
// records at the next run, so their IDs are noted here and checked at this fix's first run,
// when the input has defined all its fixes.
void FixFemBody::find_restart_records()
{
  const int n = modify->n_restart_data_global_style(style);
  if (n == 0 || modify->have_restart_data(this)) return;
  for (int k = 0; k < n; ++k)
    other_restart_ids_.emplace_back(modify->id_restart_data_global_style(style, k));
}

void FixFemBody::check_restart_records()
{
  for (const std::string& stored : other_restart_ids_) {
    if (dynamic_cast<FixFemBody*>(modify->find_fix_id(stored.c_str()))) continue;
    std::string msg = std::string(kStyle) + " " + id +
                      ": the restart file holds the state of fix fem/body '" + stored +
                      "', which no fix of this input takes up, and this fix (ID '" + id +
                      "') got no state and starts from its mesh; a fix gets its restart state by "
                      "its ID: use 'fix ";
    msg += stored + " ...' to continue that body (to start a new body instead, put 'run 0' "
                    "before this fix command: a run drops the file's fix states)";
    error->all(FLERR, msg.c_str());
  }
  other_restart_ids_.clear();
}

/* ----------------------------------------------------------------------
   per-atom history
------------------------------------------------------------------------- */

void FixFemBody::grow_arrays(int nmax)
{
  memory->grow(history_, nmax, nslots_ * kSlotDoubles, "fem/body:history");
  nmax_atoms_ = nmax;
}

void FixFemBody::copy_arrays(int i, int j, int)
{
  std::memcpy(history_[j], history_[i], sizeof(double) * nslots_ * kSlotDoubles);
}

void FixFemBody::set_arrays(int i)
{
  for (int k = 0; k < nslots_ * kSlotDoubles; ++k)
    history_[i][k] = (k % kSlotDoubles < 2) ? -1 : 0;
}

int FixFemBody::pack_exchange(int i, double* buf)
{
  const int n = nslots_ * kSlotDoubles;
  std::memcpy(buf, history_[i], sizeof(double) * n);
  return n;
}

int FixFemBody::unpack_exchange(int nlocal, double* buf)
{
  const int n = nslots_ * kSlotDoubles;
  std::memcpy(history_[nlocal], buf, sizeof(double) * n);
  return n;
}

int FixFemBody::pack_restart(int i, double* buf)
{
  const int n = nslots_ * kSlotDoubles;
  buf[0] = n + 1;
  std::memcpy(buf + 1, history_[i], sizeof(double) * n);
  return n + 1;
}

void FixFemBody::unpack_restart(int nlocal, int nth)
{
  double** extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; ++k)
    m += static_cast<int>(extra[nlocal][m]);
  const int n = static_cast<int>(extra[nlocal][m]) - 1;
  if (n != nslots_ * kSlotDoubles) {
    set_arrays(nlocal);
    return;
  }
  std::memcpy(history_[nlocal], &extra[nlocal][m + 1], sizeof(double) * n);
}

int FixFemBody::size_restart(int)
{
  return nslots_ * kSlotDoubles + 1;
}
int FixFemBody::maxsize_restart()
{
  return nslots_ * kSlotDoubles + 1;
}

// The body (replicated on every rank), its contact structures and the per-particle history.
double FixFemBody::memory_usage()
{
  double bytes = static_cast<double>(body_.memory_bytes()) + contact_memory_bytes();
  bytes += sizeof(double) * nmax_atoms_ * nslots_ * kSlotDoubles;
  return bytes;
}

template <typename T> static double vector_bytes(const std::vector<T>& v)
{
  return static_cast<double>(v.capacity() * sizeof(T));
}

// Particle-facet contact keeps its arrays private; they are estimated from its facet and node
// counts (particle_facet.cpp, contact_resolution.cpp): per facet the facet, its reference normal
// and about 1.5 edges in the edge map (an unordered_map node with a short vector); per node two
// doubles (surface area, indentation) and a neighbour list. The body-contact surface is public.
double FixFemBody::contact_memory_bytes() const
{
  const double nf = static_cast<double>(contact_.facets().capacity());
  const double nn = body_.num_nodes();
  double bytes = nf * (sizeof(fracdem::Facet) + 3 * sizeof(double) + 1.5 * 96) +
                 nn * (2 * sizeof(double) + sizeof(std::vector<int>)) +
                 6 * sizeof(int) * contact_.facets().size();
  bytes += vector_bytes(surface_.facets) + vector_bytes(surface_.nodes) +
           vector_bytes(surface_.incident_offset) + vector_bytes(surface_.incident) +
           vector_bytes(surface_.reach);
  return bytes;
}

// One line per body and run, beside the host's "Memory usage per processor": every rank holds
// the whole body, so a large body is most of a rank's memory. The per-particle contact history
// scales with the particles, not the body: counted in memory_usage() only.
void FixFemBody::log_memory()
{
  double bytes = static_cast<double>(body_.memory_bytes()) + contact_memory_bytes();
  MPI_Allreduce(MPI_IN_PLACE, &bytes, 1, MPI_DOUBLE, MPI_MAX, world);
  if (comm->me != 0) return;
  char line[256];
  snprintf(line, sizeof(line), "fix fem/body %s: %d nodes, %d elements, %.4g MB per rank\n", id,
           body_.num_nodes(), body_.mesh().num_active_elems(), bytes / (1024.0 * 1024.0));
  if (screen) fputs(line, screen);
  if (logfile) fputs(line, logfile);
}
