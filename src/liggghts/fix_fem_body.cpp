// fix fem/body: host adapter that owns a replicated FE body, integrates it and couples it to
// particles.
#include "fix_fem_body.h"

#include <algorithm>
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

using namespace LAMMPS_NS;
using namespace FixConst;

namespace
{

const char* const kStyle = "fix fem/body";

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
  kVectorSize
};

void rotate_about_axis(const double axis_in[3], double angle, const double p[3], double out[3])
{
  double n = std::sqrt(axis_in[0] * axis_in[0] + axis_in[1] * axis_in[1] + axis_in[2] * axis_in[2]);
  double k[3] = {axis_in[0] / n, axis_in[1] / n, axis_in[2] / n};
  double c = std::cos(angle), s = std::sin(angle);
  double kdotp = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
  double kxp[3] = {k[1] * p[2] - k[2] * p[1], k[2] * p[0] - k[0] * p[2], k[0] * p[1] - k[1] * p[0]};
  for (int d = 0; d < 3; ++d)
    out[d] = p[d] * c + kxp[d] * s + k[d] * kdotp * (1 - c);
}

} // namespace

/* ---------------------------------------------------------------------- */

FixFemBody::FixFemBody(LAMMPS* lmp, int narg, char** arg) : Fix(lmp, narg, arg)
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag)
    error->all(FLERR, "fix fem/body requires atom_style granular (radius, rmass, omega)");

  parse_arguments(narg, arg);
  load_mesh();

  scalar_flag = 1;
  extscalar = 1;
  vector_flag = 1;
  size_vector = kVectorSize;
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
      surface_type_ = force->inumeric(FLERR, arg[iarg + 1]);
      iarg += 2;
    } else if (!strcmp(kw, "density")) {
      need(iarg, 1, kw, "a value");
      material_.rho = force->numeric(FLERR, arg[iarg + 1]);
      have_density_ = true;
      iarg += 2;
    } else if (!strcmp(kw, "youngs")) {
      need(iarg, 1, kw, "a value");
      material_.E = force->numeric(FLERR, arg[iarg + 1]);
      have_youngs_ = true;
      iarg += 2;
    } else if (!strcmp(kw, "poisson")) {
      need(iarg, 1, kw, "a value");
      material_.nu = force->numeric(FLERR, arg[iarg + 1]);
      have_poisson_ = true;
      iarg += 2;
    } else if (!strcmp(kw, "model")) {
      need(iarg, 1, kw, "elastic or corotational");
      material_.kinematics = lookup(error, kKinematicsTable, kw, arg[iarg + 1]);
      iarg += 2;
    } else if (!strcmp(kw, "plane")) {
      need(iarg, 1, kw, "strain or axisymmetric");
      material_.plane = lookup(error, kPlaneModeTable, kw, arg[iarg + 1]);
      iarg += 2;
    } else if (!strcmp(kw, "thickness")) {
      need(iarg, 1, kw, "a value");
      material_.thickness = force->numeric(FLERR, arg[iarg + 1]);
      if (material_.thickness <= 0)
        error->all(FLERR, "fix fem/body: keyword 'thickness' must be > 0");
      iarg += 2;
    } else if (!strcmp(kw, "fixed")) {
      need(iarg, 1, kw, "a mesh physical group name");
      fixed_sets_.push_back(arg[iarg + 1]);
      iarg += 2;
    } else if (!strcmp(kw, "velocity") || !strcmp(kw, "prescribed_velocity")) {
      need(iarg, 4, kw, "GROUP vx vy vz");
      NodeVelocitySpec s;
      s.set = arg[iarg + 1];
      for (int d = 0; d < 3; ++d)
        s.v[d] = force->numeric(FLERR, arg[iarg + 2 + d]);
      (kw[0] == 'v' ? initial_velocity_ : prescribed_velocity_).push_back(s);
      iarg += 5;
    } else if (!strcmp(kw, "scale")) {
      need(iarg, 1, kw, "a factor");
      Transform t{Transform::Scale, {force->numeric(FLERR, arg[iarg + 1]), 0, 0, 0}};
      if (t.a[0] <= 0) error->all(FLERR, "fix fem/body: keyword 'scale' must be > 0");
      transforms_.push_back(t);
      iarg += 2;
    } else if (!strcmp(kw, "move")) {
      need(iarg, 3, kw, "dx dy dz");
      Transform t{Transform::Move, {0, 0, 0, 0}};
      for (int d = 0; d < 3; ++d)
        t.a[d] = force->numeric(FLERR, arg[iarg + 1 + d]);
      transforms_.push_back(t);
      iarg += 4;
    } else if (!strcmp(kw, "rotate")) {
      need(iarg, 6, kw, "axis ax ay az angle DEGREES");
      if (strcmp(arg[iarg + 1], "axis") || strcmp(arg[iarg + 5], "angle"))
        error->all(FLERR, "fix fem/body: keyword 'rotate' expects 'axis ax ay az angle DEGREES'");
      Transform t{Transform::Rotate, {0, 0, 0, 0}};
      for (int d = 0; d < 3; ++d)
        t.a[d] = force->numeric(FLERR, arg[iarg + 2 + d]);
      t.a[3] = force->numeric(FLERR, arg[iarg + 6]) * M_PI / 180.0;
      transforms_.push_back(t);
      iarg += 7;
    } else if (!strcmp(kw, "rigid")) {
      rigid_ = either(iarg, kw, "yes", "no");
      iarg += 2;
    } else if (!strcmp(kw, "motion")) {
      need(iarg, 1, kw, "linear vx vy vz | rotate origin ox oy oz axis ax ay az period T");
      if (!strcmp(arg[iarg + 1], "linear")) {
        need(iarg, 4, kw, "linear vx vy vz");
        motion_ = MotionKind::Linear;
        for (int d = 0; d < 3; ++d)
          motion_vel_[d] = force->numeric(FLERR, arg[iarg + 2 + d]);
        iarg += 5;
      } else if (!strcmp(arg[iarg + 1], "rotate")) {
        need(iarg, 10, kw, "rotate origin ox oy oz axis ax ay az period T");
        if (strcmp(arg[iarg + 2], "origin") || strcmp(arg[iarg + 6], "axis") ||
            strcmp(arg[iarg + 10], "period"))
          error->all(FLERR,
                     "fix fem/body: keyword 'motion rotate' expects 'origin ox oy oz axis ax "
                     "ay az period T'");
        motion_ = MotionKind::Rotate;
        for (int d = 0; d < 3; ++d) {
          motion_origin_[d] = force->numeric(FLERR, arg[iarg + 3 + d]);
          motion_axis_[d] = force->numeric(FLERR, arg[iarg + 7 + d]);
        }
        motion_period_ = force->numeric(FLERR, arg[iarg + 11]);
        double n = std::sqrt(motion_axis_[0] * motion_axis_[0] + motion_axis_[1] * motion_axis_[1] +
                             motion_axis_[2] * motion_axis_[2]);
        if (n == 0 || motion_period_ == 0)
          error->all(FLERR, "fix fem/body: 'motion rotate' needs a non-zero axis and period");
        for (double& a : motion_axis_)
          a /= n;
        iarg += 12;
      } else {
        error->all(FLERR, "fix fem/body: keyword 'motion' expects 'linear' or 'rotate'");
      }
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
      buffer_ = force->numeric(FLERR, arg[iarg + 1]);
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
      energy_every_ = force->inumeric(FLERR, arg[iarg + 2]);
      if (energy_every_ <= 0) error->all(FLERR, "fix fem/body: keyword 'energy_file' needs N > 0");
      iarg += 3;
    } else if (!strcmp(kw, "history_slots")) {
      need(iarg, 1, kw, "a count");
      nslots_ = force->inumeric(FLERR, arg[iarg + 1]);
      if (nslots_ < 1) error->all(FLERR, "fix fem/body: keyword 'history_slots' must be >= 1");
      iarg += 2;
    } else {
      std::string msg = std::string(kStyle) + ": unknown keyword '" + kw + "'";
      error->all(FLERR, msg.c_str());
    }
  }

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
    if (motion_ != MotionKind::None)
      error->all(FLERR, "fix fem/body: keyword 'motion' needs 'rigid yes' (deformable bodies move "
                        "by forces and 'prescribed_velocity')");
  } else {
    if (!fixed_sets_.empty() || !prescribed_velocity_.empty() || !initial_velocity_.empty())
      error->all(FLERR, "fix fem/body: 'fixed', 'velocity' and 'prescribed_velocity' apply to "
                        "deformable bodies; a rigid body moves by 'motion'");
    if (!have_density_) material_.rho = 1.0; // only used for the (unused) mass of a rigid body
  }
  if (compliance_combined_ < 0) compliance_combined_ = rigid_ ? 1 : 0;
}

/* ---------------------------------------------------------------------- */

void FixFemBody::load_mesh()
{
  try {
    mesh_ = fracdem::read_gmsh(mesh_file_, domain->dimension);
  } catch (const std::exception& e) {
    std::string msg = std::string(kStyle) + " " + id + ": cannot use mesh: " + e.what();
    error->all(FLERR, msg.c_str());
  }
  if (mesh_.dim != domain->dimension) {
    std::string msg = std::string(kStyle) + ": mesh '" + mesh_file_ + "' is " +
                      std::to_string(mesh_.dim) + "D but the simulation is " +
                      std::to_string(domain->dimension) + "D";
    error->all(FLERR, msg.c_str());
  }
  apply_initial_transforms();

  try {
    space_.build(mesh_, material_);
  } catch (const std::exception& e) {
    std::string msg =
        std::string(kStyle) + " " + id + ": bad mesh '" + mesh_file_ + "': " + e.what();
    error->all(FLERR, msg.c_str());
  }

  const int nn = mesh_.num_nodes();
  x_ = mesh_.X;
  v_.assign(3 * nn, 0.0);
  f_.assign(3 * nn, 0.0);
  f_contact_.assign(3 * nn, 0.0);
  f_contact_prev_.assign(3 * nn, 0.0);
  space_.lumped_masses(mesh_, mass_);
  inv_mass_.resize(nn);
  for (int i = 0; i < nn; ++i)
    inv_mass_[i] = mass_[i] > 0 ? 1.0 / mass_[i] : 0.0;

  node_fixed_.assign(nn, 0);
  v_prescribed_.assign(3 * nn, 0.0);
  for (const auto& s : fixed_sets_)
    for (int n : node_set(s, "fixed"))
      node_fixed_[n] = 1;
  for (const auto& s : prescribed_velocity_)
    for (int n : node_set(s.set, "prescribed_velocity")) {
      node_fixed_[n] = 2;
      for (int d = 0; d < 3; ++d)
        v_prescribed_[3 * n + d] = s.v[d];
    }
  for (const auto& s : initial_velocity_)
    node_set(s.set, "velocity"); // validate names now

  // Split element work evenly; every rank holds the whole body (replicated).
  const int ne = mesh_.num_elems();
  elem_begin_ = static_cast<int>((static_cast<long long>(ne) * comm->me) / comm->nprocs);
  elem_end_ = static_cast<int>((static_cast<long long>(ne) * (comm->me + 1)) / comm->nprocs);

  rebuild_surface();

  if (comm->me == 0) {
    char line[512];
    snprintf(line, sizeof(line),
             "fix fem/body %s: %s, %d nodes, %d elements, %zu boundary facets, %s%s\n", id,
             mesh_file_.c_str(), nn, ne, facets_.size(), rigid_ ? "rigid" : "deformable ",
             rigid_ ? ""
                    : (material_.kinematics == fracdem::Kinematics::Corotational
                           ? "corotational"
                           : "small-strain elastic"));
    if (screen) fputs(line, screen);
    if (logfile) fputs(line, logfile);
  }
}

std::vector<int> FixFemBody::node_set(const std::string& name, const char* keyword) const
{
  if (name == "all") {
    std::vector<int> all(mesh_.num_nodes());
    for (int i = 0; i < mesh_.num_nodes(); ++i)
      all[i] = i;
    return all;
  }
  auto it = mesh_.node_sets.find(name);
  if (it == mesh_.node_sets.end()) {
    std::string msg = std::string(kStyle) + ": keyword '" + keyword + "': mesh '" + mesh_file_ +
                      "' has no physical group '" + name + "'; it has:";
    for (const auto& kv : mesh_.node_sets)
      msg += " " + kv.first;
    msg += " (and 'all')";
    error->all(FLERR, msg.c_str());
  }
  return it->second;
}

void FixFemBody::apply_initial_transforms()
{
  const int nn = mesh_.num_nodes();
  for (const Transform& t : transforms_) {
    for (int i = 0; i < nn; ++i) {
      double* p = &mesh_.X[3 * i];
      if (t.kind == Transform::Scale) {
        for (int d = 0; d < 3; ++d)
          p[d] *= t.a[0];
      } else if (t.kind == Transform::Move) {
        for (int d = 0; d < 3; ++d)
          p[d] += t.a[d];
      } else {
        double q[3];
        rotate_about_axis(t.a, t.a[3], p, q);
        for (int d = 0; d < 3; ++d)
          p[d] = q[d];
      }
    }
  }
  if (mesh_.dim == 2)
    for (int i = 0; i < nn; ++i)
      if (std::fabs(mesh_.X[3 * i + 2]) > 0)
        error->all(FLERR,
                   "fix fem/body: 2D mesh must stay in the z = 0 plane after 'move'/'rotate'");
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
  particle_E_.assign(ntypes + 1, 0);
  particle_nu_.assign(ntypes + 1, 0);
  particle_e_.assign(ntypes + 1, 0);
  particle_mu_.assign(ntypes + 1, 0);
  for (int t = 1; t <= ntypes; ++t) {
    particle_E_[t] = E->compute_vector(t - 1);
    particle_nu_[t] = nu->compute_vector(t - 1);
    particle_e_[t] = e->compute_array(t - 1, surface_type_ - 1);
    particle_mu_[t] = mu->compute_array(t - 1, surface_type_ - 1);
  }
  surface_E_ = particle_E_[surface_type_];
  surface_nu_ = particle_nu_[surface_type_];
  if (normal_model_ == fracdem::NormalModel::Hooke) {
    Fix* cv = modify->find_fix_property("characteristicVelocity", "property/global", "scalar", 0, 0,
                                        style);
    char_vel_ = static_cast<FixPropertyGlobal*>(cv)->compute_scalar();
  }
}

void FixFemBody::init()
{
  read_contact_properties();
  buffer_ = buffer_ >= 0 ? buffer_ : neighbor->skin;
  search_ = std::make_unique<fracdem::BufferedSearch>(buffer_);
  search_stale_ = true;

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
    fprintf(energy_fp_,
            "step,time,kinetic,strain,external_work,contact_work,total,nodes,elements\n");
  }
  check_time_step();
}

void FixFemBody::reset_dt()
{
  check_time_step();
}

void FixFemBody::check_time_step()
{
  if (rigid_) return;
  dt_stable_ = space_.stable_time_step(mesh_, x_.data());
  const double dt = update->dt;
  if (comm->me == 0) {
    char line[256];
    snprintf(line, sizeof(line),
             "fix fem/body %s: stable FE time step %.6g, host time step %.6g (%.1f%%)\n", id,
             dt_stable_, dt, 100.0 * dt / dt_stable_);
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
      for (int n : node_set(s.set, "velocity"))
        for (int d = 0; d < 3; ++d)
          v_[3 * n + d] = s.v[d];
    for (int n = 0; n < mesh_.num_nodes(); ++n)
      if (node_fixed_[n] == 1)
        for (int d = 0; d < 3; ++d)
          v_[3 * n + d] = 0;
      else if (node_fixed_[n] == 2)
        for (int d = 0; d < 3; ++d)
          v_[3 * n + d] = v_prescribed_[3 * n + d];
  }
  initial_velocity_applied_ = true;
  if (rigid_) prescribed_motion(time_, x_.data(), v_.data());
  search_stale_ = true;
  compute_forces();
  if (energy_fp_ && update->ntimestep % energy_every_ == 0) write_energy_row();
}

void FixFemBody::pre_neighbor()
{
  search_stale_ = true;
}

/* ----------------------------------------------------------------------
   velocity Verlet, in step with the host: half kick + drift here,
   forces in post_force, second half kick in final_integrate.
------------------------------------------------------------------------- */

void FixFemBody::initial_integrate(int /*vflag*/)
{
  const double dt = update->dt;
  time_ += dt;
  if (rigid_) {
    prescribed_motion(time_, x_.data(), v_.data());
    return;
  }
  const int nn = mesh_.num_nodes();
  const double half = 0.5 * dt;
  for (int n = 0; n < nn; ++n) {
    double* v = &v_[3 * n];
    double* x = &x_[3 * n];
    if (node_fixed_[n] == 0) {
      const double s = half * inv_mass_[n];
      const double* f = &f_[3 * n];
      v[0] += s * f[0];
      v[1] += s * f[1];
      v[2] += s * f[2];
    } else if (node_fixed_[n] == 1) {
      continue;
    }
    x[0] += dt * v[0];
    x[1] += dt * v[1];
    x[2] += dt * v[2];
  }
}

void FixFemBody::post_force(int /*vflag*/)
{
  compute_forces();
}

void FixFemBody::final_integrate()
{
  if (rigid_) return;
  const double half = 0.5 * update->dt;
  const int nn = mesh_.num_nodes();
  for (int n = 0; n < nn; ++n) {
    if (node_fixed_[n]) continue;
    const double s = half * inv_mass_[n];
    const double* f = &f_[3 * n];
    double* v = &v_[3 * n];
    v[0] += s * f[0];
    v[1] += s * f[1];
    v[2] += s * f[2];
  }
  if (energy_fp_ && update->ntimestep % energy_every_ == 0) write_energy_row();
}

void FixFemBody::compute_forces()
{
  const int nn = mesh_.num_nodes();
  std::fill(f_.begin(), f_.end(), 0.0);
  std::fill(f_contact_.begin(), f_contact_.end(), 0.0);

  // Local shares: internal forces of this rank's elements, contact forces of
  // this rank's particles; one reduction makes every replica identical.
  double local_energy = 0;
  int first_inverted = -1;
  if (!rigid_)
    local_energy = space_.add_internal_forces(mesh_, x_.data(), elem_begin_, elem_end_, f_.data(),
                                              nullptr, &first_inverted);
  int local_contacts = 0;
  contact_forces(f_contact_.data(), local_contacts);

  double scalars[3] = {local_energy, static_cast<double>(local_contacts),
                       static_cast<double>(first_inverted >= 0 ? first_inverted + 1 : 0)};
  if (comm->nprocs > 1) {
    MPI_Allreduce(MPI_IN_PLACE, f_.data(), 3 * nn, MPI_DOUBLE, MPI_SUM, world);
    MPI_Allreduce(MPI_IN_PLACE, f_contact_.data(), 3 * nn, MPI_DOUBLE, MPI_SUM, world);
    MPI_Allreduce(MPI_IN_PLACE, scalars, 2, MPI_DOUBLE, MPI_SUM, world);
    MPI_Allreduce(MPI_IN_PLACE, &scalars[2], 1, MPI_DOUBLE, MPI_MAX, world);
  }
  strain_energy_ = scalars[0];
  ncontacts_ = static_cast<int>(scalars[1]);
  if (scalars[2] > 0) {
    char msg[256];
    snprintf(msg, sizeof(msg),
             "fix fem/body %s: element %d inverted (det F <= 0) at step " BIGINT_FORMAT
             "; the time step is too large or the load too severe for this mesh",
             id, static_cast<int>(scalars[2]) - 1, update->ntimestep);
    error->all(FLERR, msg);
  }
  if (!std::isfinite(strain_energy_)) {
    char msg[256];
    snprintf(msg, sizeof(msg),
             "fix fem/body %s: non-finite strain energy at step " BIGINT_FORMAT
             " (NaN/Inf in the body state)",
             id, update->ntimestep);
    error->all(FLERR, msg);
  }

  // Work of contact forces on the body over the last step (trapezoidal rule,
  // v holds the mid-step velocity here).
  const double dt = update->dt;
  double dw_contact = 0, dw_gravity = 0;
  contact_force_total_[0] = contact_force_total_[1] = contact_force_total_[2] = 0;
  for (int n = 0; n < nn; ++n) {
    for (int d = 0; d < 3; ++d) {
      const int k = 3 * n + d;
      dw_contact += 0.5 * (f_contact_[k] + f_contact_prev_[k]) * v_[k];
      contact_force_total_[d] += f_contact_[k];
      f_[k] += f_contact_[k];
    }
  }
  if (!rigid_) {
    const double g2 =
        gravity_[0] * gravity_[0] + gravity_[1] * gravity_[1] + gravity_[2] * gravity_[2];
    if (g2 > 0)
      for (int n = 0; n < nn; ++n)
        for (int d = 0; d < 3; ++d) {
          f_[3 * n + d] += mass_[n] * gravity_[d];
          dw_gravity += mass_[n] * gravity_[d] * v_[3 * n + d];
        }
  }
  if (update->setupflag == 0) {
    contact_work_ += dt * dw_contact;
    external_work_ += dt * dw_gravity;
  }
  std::swap(f_contact_prev_, f_contact_);
  // f_contact_prev_ now holds this step's contact forces; f_contact_ is scratch.
  for (int n = 0; n < nn; ++n)
    if (node_fixed_[n])
      for (int d = 0; d < 3; ++d)
        f_[3 * n + d] = 0;
}

/* ----------------------------------------------------------------------
   particle-facet contact for the particles this rank owns
------------------------------------------------------------------------- */

void FixFemBody::rebuild_search()
{
  const int nlocal = atom->nlocal;
  search_atoms_.clear();
  search_sphere_.clear();
  for (int i = 0; i < nlocal; ++i) {
    if (!(atom->mask[i] & groupbit)) continue;
    search_atoms_.push_back(i);
    search_sphere_.insert(search_sphere_.end(),
                          {atom->x[i][0], atom->x[i][1], atom->x[i][2], atom->radius[i]});
  }
  std::vector<fracdem::Aabb> boxes(facets_.size());
  for (size_t k = 0; k < facets_.size(); ++k) {
    fracdem::Aabb& b = boxes[k];
    for (int d = 0; d < 3; ++d) {
      b.lo[d] = std::numeric_limits<double>::max();
      b.hi[d] = -std::numeric_limits<double>::max();
    }
    for (int j = 0; j < facets_[k].nn; ++j) {
      const double* p = &x_[3 * facets_[k].n[j]];
      for (int d = 0; d < 3; ++d) {
        b.lo[d] = std::min(b.lo[d], p[d]);
        b.hi[d] = std::max(b.hi[d], p[d]);
      }
    }
  }
  search_->build(boxes, search_sphere_.data(), static_cast<int>(search_atoms_.size()));
  std::vector<double> sx(3 * search_atoms_.size());
  for (size_t s = 0; s < search_atoms_.size(); ++s)
    for (int d = 0; d < 3; ++d)
      sx[3 * s + d] = search_sphere_[4 * s + d];
  search_->remember_positions(x_.data(), mesh_.num_nodes(), sx.data(),
                              static_cast<int>(search_atoms_.size()));
  search_stale_ = false;
  ++nrebuilds_;
}

bool FixFemBody::search_is_stale()
{
  if (search_stale_) return true;
  std::vector<double> sx(3 * search_atoms_.size());
  for (size_t s = 0; s < search_atoms_.size(); ++s)
    for (int d = 0; d < 3; ++d)
      sx[3 * s + d] = atom->x[search_atoms_[s]][d];
  return search_->needs_rebuild(x_.data(), mesh_.num_nodes(), sx.data(),
                                static_cast<int>(search_atoms_.size()));
}

void FixFemBody::contact_forces(double* f_contact, int& ncontacts)
{
  ncontacts = 0;
  if (facets_.empty()) return;
  // The search covers only this rank's particles against the replicated body,
  // so each rank decides on its own when to rebuild (no collective needed).
  if (search_is_stale()) rebuild_search();

  double** x = atom->x;
  double** v = atom->v;
  double** omega = atom->omega;
  double** f = atom->f;
  double** torque = atom->torque;
  const double* radius = atom->radius;
  const double* rmass = atom->rmass;
  const int* type = atom->type;
  const double dt = update->dt;

  const auto& cand = search_->candidates();
  // Per-particle work of this step, read by the load balancer (fix balance/graph).
  facet_checks_.assign(atom->nlocal, 0);
  facet_contacts_.assign(atom->nlocal, 0);
  std::vector<fracdem::FacetHit> hits;
  size_t c = 0;
  std::vector<char> touched(nslots_);
  while (c < cand.size()) {
    const int s = cand[c].first;
    const int i = search_atoms_[s];
    hits.clear();
    const double r = radius[i];
    for (; c < cand.size() && cand[c].first == s; ++c) {
      const fracdem::Facet& fc = facets_[cand[c].second];
      fracdem::FacetHit h;
      h.facet = cand[c].second;
      h.nn = fc.nn;
      for (int j = 0; j < 3; ++j)
        h.nodes[j] = fc.n[j];
      if (fc.nn == 3)
        h.cp = fracdem::closest_point_triangle(x[i], &x_[3 * fc.n[0]], &x_[3 * fc.n[1]],
                                               &x_[3 * fc.n[2]]);
      else
        h.cp = fracdem::closest_point_segment(x[i], &x_[3 * fc.n[0]], &x_[3 * fc.n[1]]);
      if (h.cp.dist2 < r * r) hits.push_back(h);
      ++facet_checks_[i];
    }

    // Forget history of contacts that ended.
    double* hist = history_ ? history_[i] : nullptr;
    if (hits.empty()) {
      if (hist)
        for (int k = 0; k < nslots_; ++k)
          hist[k * kSlotDoubles] = hist[k * kSlotDoubles + 1] = -1;
      continue;
    }
    hits = fracdem::resolve_sphere_hits(std::move(hits), x[i], x_.data(), topology_);
    facet_contacts_[i] += static_cast<int>(hits.size());

    const int ti = type[i];
    fracdem::ContactMaterial mat = fracdem::mix_materials(
        particle_E_[ti], particle_nu_[ti], compliance_combined_ ? surface_E_ : 0.0,
        compliance_combined_ ? surface_nu_ : 0.0, particle_e_[ti], particle_mu_[ti], char_vel_,
        normal_model_, tangential_history_);

    // Normal and overlap of every kept hit.
    const int nh = static_cast<int>(hits.size());
    normals_.resize(3 * nh);
    overlaps_.resize(nh);
    for (int k = 0; k < nh; ++k) {
      const fracdem::FacetHit& h = hits[k];
      const double dist = std::sqrt(h.cp.dist2);
      double* nk = &normals_[3 * k];
      if (dist > 1e-12 * r) {
        for (int d = 0; d < 3; ++d)
          nk[d] = (x[i][d] - h.cp.p[d]) / dist;
      } else {
        // Centre on the surface: fall back to the facet normal.
        const double* a = &x_[3 * h.nodes[0]];
        const double* b = &x_[3 * h.nodes[1]];
        double nrm[3];
        if (h.nn == 3) {
          const double* cc = &x_[3 * h.nodes[2]];
          double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
          double e2[3] = {cc[0] - a[0], cc[1] - a[1], cc[2] - a[2]};
          nrm[0] = e1[1] * e2[2] - e1[2] * e2[1];
          nrm[1] = e1[2] * e2[0] - e1[0] * e2[2];
          nrm[2] = e1[0] * e2[1] - e1[1] * e2[0];
        } else {
          nrm[0] = b[1] - a[1];
          nrm[1] = a[0] - b[0];
          nrm[2] = 0;
        }
        const double l = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
        for (int d = 0; d < 3; ++d)
          nk[d] = nrm[d] / l;
      }
      overlaps_[k] = r - dist;
    }

    std::fill(touched.begin(), touched.end(), 0);
    for (const std::vector<int>& cluster :
         fracdem::cluster_hits(normals_.data(), overlaps_.data(), nh)) {
      // One contact per cluster, evaluated at the deepest hit; its reaction is shared among the
      // cluster's facets in proportion to overlap^1.5 (their Hertz weights).
      const fracdem::FacetHit& lead = hits[cluster[0]];
      double wsum = 0;
      for (int k : cluster)
        wsum += std::pow(overlaps_[k], 1.5);
      fracdem::ContactInput in;
      for (int d = 0; d < 3; ++d)
        in.n[d] = normals_[3 * cluster[0] + d];
      in.delta = overlaps_[cluster[0]];
      in.radius = r;
      in.mass = rmass[i];
      in.dt = dt;
      double vsurf[3] = {0, 0, 0};
      for (int k : cluster) {
        const double share = std::pow(overlaps_[k], 1.5) / wsum;
        const fracdem::FacetHit& h = hits[k];
        for (int j = 0; j < h.nn; ++j)
          for (int d = 0; d < 3; ++d)
            vsurf[d] += share * h.cp.w[j] * v_[3 * h.nodes[j] + d];
      }
      for (int d = 0; d < 3; ++d) {
        in.v_rel[d] = v[i][d] - vsurf[d];
        in.omega[d] = omega[i][d];
      }
      double scratch[3] = {0, 0, 0};
      double* shear = scratch;
      if (tangential_history_ && hist) {
        double* slot = history_slot_find(i, fracdem::feature_key(lead), true);
        if (slot) {
          shear = slot + 2;
          touched[(slot - hist) / kSlotDoubles] = 1;
        }
      }
      // On a deformable body carrying its own compliance, a resolved contact gets Hertz's contact
      // radius from the total approach and spreads its reaction as Hertz pressure over the
      // contact disc; an unresolved one (disc smaller than the mesh) stays a point contact.
      bool spread = false;
      if (!rigid_ && !compliance_combined_ && normal_model_ == fracdem::NormalModel::Hertz)
        spread = hertz_contact_patch(lead, in, r);
      fracdem::ContactOutput out = fracdem::particle_surface_force(mat, in, shear);
      for (int d = 0; d < 3; ++d) {
        f[i][d] += out.force[d];
        torque[i][d] += out.torque[d];
      }
      if (spread) {
        for (size_t k = 0; k < patch_.nodes.size(); ++k)
          for (int d = 0; d < 3; ++d)
            f_contact[3 * patch_.nodes[k] + d] -= patch_weights_[k] * out.force[d];
        ++ncontacts;
        continue;
      }
      // Reaction on the facet nodes by share x barycentric weight: the weights sum to one, so
      // the pair's linear momentum balance holds to round-off.
      for (int k : cluster) {
        const double share = std::pow(overlaps_[k], 1.5) / wsum;
        const fracdem::FacetHit& h = hits[k];
        for (int j = 0; j < h.nn; ++j)
          for (int d = 0; d < 3; ++d)
            f_contact[3 * h.nodes[j] + d] -= share * h.cp.w[j] * out.force[d];
      }
      ++ncontacts;
    }
    if (hist)
      for (int k = 0; k < nslots_; ++k)
        if (!touched[k]) hist[k * kSlotDoubles] = hist[k * kSlotDoubles + 1] = -1;
  }
}

bool FixFemBody::hertz_contact_patch(const fracdem::FacetHit& lead, fracdem::ContactInput& in,
                                     double radius)
{
  // Displacement into the body (along -n) at the contact point and around it.
  const double* X = mesh_.X.data();
  auto into_body = [&](int v) {
    double u = 0;
    for (int d = 0; d < 3; ++d)
      u -= (x_[3 * v + d] - X[3 * v + d]) * in.n[d];
    return u;
  };
  double u_c = 0;
  for (int j = 0; j < lead.nn; ++j)
    u_c += lead.cp.w[j] * into_body(lead.nodes[j]);
  // The patch must reach the ring [1.5 a, 3.5 a] of the largest plausible contact radius; two
  // passes: the ring of the point-law radius first, then of the radius that gives.
  double a = std::sqrt(radius * in.delta);
  double delta_b = 0;
  for (int pass = 0; pass < 2; ++pass) {
    fracdem::gather_surface_patch(topology_, x_.data(), lead.nodes, lead.nn, lead.cp.p, in.n,
                                  3.6 * std::sqrt(2 * radius * (in.delta + delta_b)), patch_);
    for (int v : patch_.nodes)
      indentation_disp_[v] = into_body(v);
    delta_b = fracdem::local_indentation(radius, in.delta, u_c, indentation_disp_, patch_);
    a = std::sqrt(radius * (in.delta + delta_b));
  }
  if (!fracdem::hertz_pressure_weights(patch_, node_area_, a, patch_weights_)) return false;
  in.contact_radius = a;
  return true;
}

void FixFemBody::rebuild_surface()
{
  facets_ = fracdem::boundary_facets(mesh_);
  topology_.build(facets_, mesh_.num_nodes());
  // Surface area per node in the reference configuration (a third of each triangle, half of
  // each 2D edge): the weights of a pressure spread over the nodes.
  node_area_.assign(mesh_.num_nodes(), 0.0);
  const double* X = mesh_.X.data();
  for (const fracdem::Facet& fc : facets_) {
    const double* a = &X[3 * fc.n[0]];
    const double* b = &X[3 * fc.n[1]];
    double size;
    if (fc.nn == 3) {
      const double* c = &X[3 * fc.n[2]];
      const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
      const double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      const double cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                            e1[0] * e2[1] - e1[1] * e2[0]};
      size = 0.5 * std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
    } else {
      size = std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]));
    }
    for (int j = 0; j < fc.nn; ++j)
      node_area_[fc.n[j]] += size / fc.nn;
  }
  indentation_disp_.assign(mesh_.num_nodes(), 0.0);
}

double* FixFemBody::history_slot_find(int i, std::uint64_t key, bool create)
{
  double* hist = history_[i];
  const double hi = static_cast<double>(key >> 32), lo = static_cast<double>(key & 0xffffffffu);
  int free_slot = -1;
  for (int k = 0; k < nslots_; ++k) {
    double* s = hist + k * kSlotDoubles;
    if (s[0] == hi && s[1] == lo) return s;
    if (free_slot < 0 && s[0] < 0) free_slot = k;
  }
  if (!create) return nullptr;
  if (free_slot < 0) {
    if (!warned_slots_) {
      error->warning(FLERR, "fix fem/body: a particle has more simultaneous facet contacts than "
                            "'history_slots'; extra contacts run without tangential history");
      warned_slots_ = true;
    }
    return nullptr;
  }
  double* s = hist + free_slot * kSlotDoubles;
  s[0] = hi;
  s[1] = lo;
  s[2] = s[3] = s[4] = 0;
  return s;
}

/* ---------------------------------------------------------------------- */

void FixFemBody::prescribed_motion(double t, double* x, double* v) const
{
  const int nn = mesh_.num_nodes();
  const double* X = mesh_.X.data();
  if (motion_ == MotionKind::None) {
    std::copy(X, X + 3 * nn, x);
    std::fill(v, v + 3 * nn, 0.0);
  } else if (motion_ == MotionKind::Linear) {
    for (int n = 0; n < nn; ++n)
      for (int d = 0; d < 3; ++d) {
        x[3 * n + d] = X[3 * n + d] + motion_vel_[d] * t;
        v[3 * n + d] = motion_vel_[d];
      }
  } else {
    const double w = 2 * M_PI / motion_period_;
    const double* k = motion_axis_;
    for (int n = 0; n < nn; ++n) {
      double p[3], q[3];
      for (int d = 0; d < 3; ++d)
        p[d] = X[3 * n + d] - motion_origin_[d];
      rotate_about_axis(k, w * t, p, q);
      for (int d = 0; d < 3; ++d)
        x[3 * n + d] = motion_origin_[d] + q[d];
      v[3 * n + 0] = w * (k[1] * q[2] - k[2] * q[1]);
      v[3 * n + 1] = w * (k[2] * q[0] - k[0] * q[2]);
      v[3 * n + 2] = w * (k[0] * q[1] - k[1] * q[0]);
    }
  }
}

double FixFemBody::kinetic_energy() const
{
  if (rigid_) return 0.0;
  double ke = 0;
  const int nn = mesh_.num_nodes();
  for (int n = 0; n < nn; ++n) {
    const double* v = &v_[3 * n];
    ke += 0.5 * mass_[n] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  return ke;
}

double FixFemBody::compute_scalar()
{
  return kinetic_energy() + strain_energy_;
}

double FixFemBody::compute_vector(int i)
{
  switch (i) {
  case kKinetic:
    return kinetic_energy();
  case kStrain:
    return strain_energy_;
  case kExternalWork:
    return external_work_;
  case kContactWork:
    return contact_work_;
  case kNodes:
    return mesh_.num_nodes();
  case kElements:
    return mesh_.num_active_elems();
  case kContacts:
    return ncontacts_;
  case kForceX:
    return contact_force_total_[0];
  case kForceY:
    return contact_force_total_[1];
  case kForceZ:
    return contact_force_total_[2];
  case kStableDt:
    return dt_stable_;
  case kSearchRebuilds: {
    double local = nrebuilds_, total = 0;
    MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_MAX, world);
    return total;
  }
  case kMomentumX:
  case kMomentumY:
  case kMomentumZ: {
    if (rigid_) return 0.0;
    const int d = i - kMomentumX;
    double p = 0;
    for (int n = 0; n < mesh_.num_nodes(); ++n)
      p += mass_[n] * v_[3 * n + d];
    return p;
  }
  }
  return 0.0;
}

void FixFemBody::write_energy_row()
{
  if (update->ntimestep == last_energy_step_) return; // a new run starts where the last ended
  last_energy_step_ = update->ntimestep;
  const double ke = kinetic_energy();
  fprintf(energy_fp_, BIGINT_FORMAT ",%.10g,%.12g,%.12g,%.12g,%.12g,%.12g,%d,%d\n",
          update->ntimestep, time_, ke, strain_energy_, external_work_, contact_work_,
          ke + strain_energy_, mesh_.num_nodes(), mesh_.num_active_elems());
  fflush(energy_fp_);
}

/* ----------------------------------------------------------------------
   restart: the mesh is re-read from the same file when the input script
   re-creates the fix; the global state (positions, velocities, activity,
   time, energy accounts) is restored from the restart file.
------------------------------------------------------------------------- */

void FixFemBody::write_restart(FILE* fp)
{
  if (comm->me != 0) return;
  const int nn = mesh_.num_nodes(), ne = mesh_.num_elems();
  std::vector<double> buf;
  buf.reserve(8 + 6 * nn + ne);
  buf.push_back(1.0); // format version
  buf.push_back(nn);
  buf.push_back(ne);
  buf.push_back(time_);
  buf.push_back(external_work_);
  buf.push_back(contact_work_);
  buf.insert(buf.end(), x_.begin(), x_.end());
  buf.insert(buf.end(), v_.begin(), v_.end());
  for (int e = 0; e < ne; ++e)
    buf.push_back(mesh_.active[e]);
  // The host reads the size in bytes, then that many bytes.
  const int nbytes = static_cast<int>(buf.size() * sizeof(double));
  fwrite(&nbytes, sizeof(int), 1, fp);
  fwrite(buf.data(), sizeof(double), buf.size(), fp);
}

void FixFemBody::restart(char* raw)
{
  const double* buf = reinterpret_cast<const double*>(raw);
  const int nn = mesh_.num_nodes(), ne = mesh_.num_elems();
  if (static_cast<int>(buf[1]) != nn || static_cast<int>(buf[2]) != ne) {
    char msg[256];
    snprintf(msg, sizeof(msg),
             "fix fem/body %s: restart file holds a body with %d nodes / %d elements but mesh '%s' "
             "has %d / %d; use the same mesh file and transforms as the run that wrote it",
             id, static_cast<int>(buf[1]), static_cast<int>(buf[2]), mesh_file_.c_str(), nn, ne);
    error->all(FLERR, msg);
  }
  time_ = buf[3];
  external_work_ = buf[4];
  contact_work_ = buf[5];
  const double* p = buf + 6;
  std::copy(p, p + 3 * nn, x_.begin());
  std::copy(p + 3 * nn, p + 6 * nn, v_.begin());
  p += 6 * nn;
  for (int e = 0; e < ne; ++e)
    mesh_.active[e] = p[e] != 0.0;
  rebuild_surface();
  restarted_state_ = true;
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

double FixFemBody::memory_usage()
{
  double bytes = sizeof(double) * (x_.size() + v_.size() + f_.size() + mass_.size() +
                                   f_contact_.size() + f_contact_prev_.size());
  bytes += sizeof(double) * nmax_atoms_ * nslots_ * kSlotDoubles;
  return bytes;
}
