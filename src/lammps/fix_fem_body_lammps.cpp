// fix fem/body under LAMMPS: parses the LIGGGHTS adapter's keyword syntax (the supported part),
// builds a fracdem::Body from a Gmsh mesh and drives its explicit update from LAMMPS's Verlet.
#include "fix_fem_body_lammps.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "modify.h"
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
    "rigid",      "motion", "eos",         "fracture",       "contact_model",   "tangential",
    "compliance", "buffer", "energy_file", "contact_bodies", "contact_penalty", "history_slots"};

const char* const kSupported = "type density youngs poisson model material(elastic) plane "
                               "thickness fixed velocity prescribed_velocity scale move rotate "
                               "dt_check gravity";

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

} // namespace

/* ---------------------------------------------------------------------- */

FixFemBodyLammps::FixFemBodyLammps(LAMMPS* lmp, int narg, char** arg) : Fix(lmp, narg, arg)
{
  // Particles meet the body through their radius, mass and spin once contact comes: the input
  // needs the sphere style already, so that scripts stay valid then.
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag)
    error->all(FLERR, "fix fem/body requires atom_style sphere (radius, rmass, omega)");

  parse_arguments(narg, arg);
  load_mesh();

  scalar_flag = 1;
  extscalar = 1;
  vector_flag = 1;
  size_vector = kVectorSize + 3 * static_cast<int>(reaction_groups_.size());
  extvector = 0;
  global_freq = 1;
  // time_integrate stays 0: this fix integrates FE nodes, never the host's atoms.
  time_depend = 1;
}

int FixFemBodyLammps::setmask()
{
  return INITIAL_INTEGRATE | POST_FORCE | FINAL_INTEGRATE;
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
  log_line(fmt::format("fix fem/body {}: {}, {} nodes, {} elements, deformable {} (LAMMPS host, "
                       "FE only)\n",
                       id, mesh_file_, body_.num_nodes(), body_.mesh().num_elems(),
                       material_.kinematics == fracdem::Kinematics::Corotational
                           ? "corotational"
                           : "small-strain elastic"));
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
  compute_forces();
}

/* ----------------------------------------------------------------------
   velocity Verlet, in step with the host: half kick + drift here,
   forces in post_force, second half kick in final_integrate.
------------------------------------------------------------------------- */

void FixFemBodyLammps::initial_integrate(int /*vflag*/)
{
  body_.advance_time(update->dt);
  body_.half_kick_drift(update->dt);
}

void FixFemBodyLammps::post_force(int /*vflag*/)
{
  compute_forces();
}

void FixFemBodyLammps::final_integrate()
{
  body_.half_kick(update->dt);
}

// The force evaluation of the LIGGGHTS adapter without particle contact: internal forces of
// this rank's elements, one reduction, then the body finishes (gravity, reactions, work).
void FixFemBodyLammps::compute_forces()
{
  const int nn = body_.num_nodes();
  body_.begin_forces();
  int first_inverted = -1;
  double scalars[2] = {body_.add_internal_forces(&first_inverted),
                       static_cast<double>(first_inverted >= 0 ? first_inverted + 1 : 0)};
  if (split_element_work_) {
    MPI_Allreduce(MPI_IN_PLACE, body_.forces_data(), 3 * nn, MPI_DOUBLE, MPI_SUM, world);
    MPI_Allreduce(MPI_IN_PLACE, &scalars[0], 1, MPI_DOUBLE, MPI_SUM, world);
    MPI_Allreduce(MPI_IN_PLACE, &scalars[1], 1, MPI_DOUBLE, MPI_MAX, world);
  }
  if (scalars[1] > 0)
    error->all(FLERR,
               "fix fem/body {}: element {} inverted (det F <= 0) at step {}; the time step "
               "is too large or the load too severe for this mesh",
               id, static_cast<int>(scalars[1]) - 1, update->ntimestep);
  if (!std::isfinite(scalars[0]))
    error->all(FLERR,
               "fix fem/body {}: non-finite strain energy at step {} (NaN/Inf in the body "
               "state)",
               id, update->ntimestep);
  body_.finish_forces(scalars[0], gravity_, update->dt, update->setupflag == 0);
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
    return 0;
  case kForceX:
  case kForceY:
  case kForceZ:
    return body_.contact_force_total()[i - kForceX];
  case kStableDt:
    return dt_stable_;
  case kSearchRebuilds:
    return 0;
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
