// fix fem/body: host adapter that owns a replicated FE body, integrates it and couples it to
// particles.
#include "fix_fem_body.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
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
#include "fem/body_setup.h"
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

// The global vector: fracdem::BodyVectorIndex (docs/fix_fem_body.md), the reaction forces (3 per
// group), then these, so that the indices before them stay.
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
  size_vector = fracdem::kVecSize + 3 * static_cast<int>(spec_.reaction_groups.size()) + kTailSize;
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
   The core's keyword table (fracdem::parse_body_spec), all of it.
------------------------------------------------------------------------- */

void FixFemBody::parse_arguments(int narg, char** arg)
{
  try {
    spec_ = fracdem::parse_body_spec(std::vector<std::string>(arg + 3, arg + narg));
    fracdem::check_body_spec(spec_, {}, atom->ntypes, domain->dimension);
  } catch (const fracdem::SpecError& e) {
    error->all(FLERR, fracdem::fix_message(e, id).c_str());
  }
  nslots_ = spec_.history_slots;
}

/* ---------------------------------------------------------------------- */

void FixFemBody::load_mesh()
{
  try {
    fracdem::build_body(spec_, domain->dimension, body_);
  } catch (const fracdem::SpecError& e) {
    error->all(FLERR, fracdem::fix_message(e, id).c_str());
  }
  // Every rank holds the whole body (replicated). The element work of a material without
  // history is split evenly; one with history (softening, cracks, the viscous work of the bulk
  // viscosity) is advanced on every rank, so that every replica holds the whole material state
  // (fracture decisions, restart, energy accounts). So is an eroding body's, so that every
  // replica sees every inverted element and erodes the same elements.
  split_element_work_ =
      fracdem::split_element_work(body_, comm->me, comm->nprocs, spec_.erosion.on());
  rebuild_surfaces();
  check_crack_band();
  check_in_box("as placed");
  log_body();
}

// The softening law snaps back in elements wider than 2 E G_f / f_t^2: refuse them by name.
void FixFemBody::check_crack_band()
{
  if (spec_.material.model != fracdem::MaterialModel::Rankine) return;
  const double limit = fracdem::rankine_snapback_length(spec_.material.rankine());
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
             id, worst, spec_.mesh_file.c_str(), hmax, limit, limit);
    error->all(FLERR, msg);
  }
}

/* ----------------------------------------------------------------------
   the body in the simulation box
------------------------------------------------------------------------- */

// The body must stay where particles can reach it (fracdem::body_box_violation says why).
std::string FixFemBody::box_violation() const
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
  return fracdem::body_box_violation(contact_.facets(), body_.positions().data(), box);
}

// A body placed outside, or a rigid body outside (carried there by its prescribed motion, or
// left there by 'change_box'), is an input mistake: refused. A deformable body gets out by its
// own dynamics (fragments thrown off, a body pushed out): only the part outside is out of the
// particles' reach, so the run goes on with one warning.
// when: "as placed" (fix command), "at the start of the run", or nullptr: at this step.
void FixFemBody::check_in_box(const char* when)
{
  const bool placed = when && !strcmp(when, "as placed");
  if (!placed && !spec_.rigid && warned_outside_) return;
  const std::string where = box_violation();
  if (where.empty()) return;
  char step[64];
  snprintf(step, sizeof step, "at step " BIGINT_FORMAT, update->ntimestep);
  std::string msg = std::string(kStyle) + " " + id + ": mesh '" + spec_.mesh_file + "' " +
                    (when ? when : step) + ": ";
  if (placed) {
    error->all(FLERR, (msg + where + " (keywords 'move', 'scale', 'rotate' place it)").c_str());
  } else if (spec_.rigid) {
    if (spec_.motion.kind != fracdem::RigidMotion::None)
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
  if (spec_.viscosity.on)
    snprintf(viscosity, sizeof(viscosity), ", bulk viscosity %g %g", spec_.viscosity.q1,
             spec_.viscosity.q2);
  snprintf(line, sizeof(line),
           "fix fem/body %s: %s, %d nodes, %d elements, %zu boundary facets, %s%s%s\n", id,
           spec_.mesh_file.c_str(), body_.num_nodes(), body_.mesh().num_elems(),
           contact_.facets().size(), spec_.rigid ? "rigid" : "deformable ",
           spec_.rigid ? ""
                       : (spec_.material.kinematics == fracdem::Kinematics::Corotational
                              ? "corotational"
                              : "small-strain elastic"),
           viscosity);
  if (screen) fputs(line, screen);
  if (logfile) fputs(line, logfile);
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
  if (spec_.normal_model == fracdem::NormalModel::Hooke) {
    Fix* cv = modify->find_fix_property("characteristicVelocity", "property/global", "scalar", 0, 0,
                                        style);
    char_vel = static_cast<FixPropertyGlobal*>(cv)->compute_scalar();
  }
  // The surface's own compliance enters only where the law carries it (rigid bodies by default).
  const double surface_E =
      spec_.compliance_combined ? E->compute_vector(spec_.surface_type - 1) : 0.0;
  const double surface_nu =
      spec_.compliance_combined ? nu->compute_vector(spec_.surface_type - 1) : 0.0;
  std::vector<fracdem::ContactMaterial> per_type(ntypes + 1);
  for (int t = 1; t <= ntypes; ++t)
    per_type[t] =
        fracdem::mix_materials(E->compute_vector(t - 1), nu->compute_vector(t - 1), surface_E,
                               surface_nu, e->compute_array(t - 1, spec_.surface_type - 1),
                               mu->compute_array(t - 1, spec_.surface_type - 1), char_vel,
                               spec_.normal_model, spec_.tangential_history);
  contact_.set_materials(std::move(per_type));
}

void FixFemBody::init()
{
  check_restart_records();
  fe_only_.init(this);
  fracdem::ParticleFacetOptions opt;
  opt.model = spec_.normal_model;
  opt.tangential_history = spec_.tangential_history;
  opt.hertz_patch = !spec_.rigid && !spec_.compliance_combined &&
                    spec_.normal_model == fracdem::NormalModel::Hertz;
  spec_.buffer = spec_.buffer >= 0 ? spec_.buffer : neighbor->skin;
  opt.buffer = spec_.buffer;
  contact_.configure(opt);
  read_contact_properties();
  if (spec_.contact_bodies) find_contact_partners();

  gravity_[0] = gravity_[1] = gravity_[2] = 0;
  if (spec_.apply_gravity && !spec_.rigid) {
    for (int i = 0; i < modify->nfix; ++i)
      if (!strcmp(modify->fix[i]->style, "gravity"))
        static_cast<FixGravity*>(modify->fix[i])->get_gravity(gravity_);
  }
  if (!spec_.energy_file.empty() && comm->me == 0 && !energy_fp_) {
    energy_fp_ = fopen(spec_.energy_file.c_str(), "w");
    if (!energy_fp_) {
      std::string msg = std::string(kStyle) + ": keyword 'energy_file': cannot open '" +
                        spec_.energy_file + "' for writing";
      error->one(FLERR, msg.c_str());
    }
    // The material's dissipation: cracking, or the plastic work of a plastic material (which
    // does not crack); the bulk viscosity's work has a column of its own.
    fprintf(energy_fp_,
            "step,time,kinetic,strain,external_work,contact_work,total,nodes,elements,"
            "%s,split_nodes,fragments,boundary_work%s%s%s",
            spec_.material.plastic_model() ? "plastic_work" : "fracture_energy",
            spec_.viscosity.on ? ",viscous_work" : "",
            can_erode() ? ",eroded_elements,eroded_mass,eroded_energy" : "",
            body_.space().axisymmetric() ? ",shield_work" : "");
    for (const std::string& g : spec_.reaction_groups)
      fprintf(energy_fp_, ",reaction_%s_x,reaction_%s_y,reaction_%s_z", g.c_str(), g.c_str(),
              g.c_str());
    for (const std::string& g : spec_.reaction_groups)
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
  if (spec_.rigid) return;
  dt_stable_ = fracdem::stable_time_step_after_erosion(body_, spec_.erosion);
  const double dt = update->dt;
  if (comm->me == 0) {
    const std::string line = "fix fem/body " + std::string(id) + ": " +
                             fracdem::time_step_line(dt_stable_, dt) +
                             (spec_.erosion.min_dt > 0 ? " without the elements below erosion "
                                                         "min_dt\n"
                                                       : "\n");
    if (screen) fputs(line.c_str(), screen);
    if (logfile) fputs(line.c_str(), logfile);
  }
  const std::string violation = fracdem::time_step_violation(dt_stable_, dt, spec_.mesh_file);
  if (violation.empty()) return;
  const std::string msg = "fix fem/body " + std::string(id) + ": " + violation;
  if (spec_.dt_check_error)
    error->all(FLERR, msg.c_str());
  else if (comm->me == 0)
    error->warning(FLERR, msg.c_str());
}

/* ---------------------------------------------------------------------- */

void FixFemBody::setup(int /*vflag*/)
{
  if (!initial_velocity_applied_ && !restarted_state_) {
    for (const auto& s : spec_.initial_velocity)
      body_.set_velocity(fracdem::body_node_set(body_, spec_, s.set, "velocity"), s.v);
    body_.impose_velocity_conditions();
  }
  initial_velocity_applied_ = true;
  if (spec_.rigid) body_.move_rigid();
  check_in_box("at the start of the run"); // restart, change_box and earlier runs move it
  contact_.invalidate_search();
  compute_forces();
  log_memory();
  if (energy_fp_ && update->ntimestep % spec_.energy_every == 0) write_energy_row();
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
  if (spec_.rigid)
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
  if (spec_.rigid) return;
  body_.half_kick(update->dt);
  if (spec_.fracture_every > 0 && update->ntimestep % spec_.fracture_every == 0) fracture();
  if (energy_fp_ && update->ntimestep % spec_.energy_every == 0) write_energy_row();
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
  if (spec_.contact_bodies && comm->me == 0) body_contacts();
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
  if (spec_.erosion.on()) return forces_after_erosion(energy, first_inverted);
  while (first_inverted >= 0 && spec_.fracture_every > 0 && !split_element_work_) {
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
  fracdem::select_eroding(body_, spec_.erosion, elems, causes);
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
    body_.erode(elems, spec_.erosion.remove_mass);
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
  case fracdem::kVecContacts:
    return ncontacts_;
  case fracdem::kVecStableDt:
    return dt_stable_;
  case fracdem::kVecSearchRebuilds: {
    double local = contact_.search_rebuilds(), total = 0;
    MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_MAX, world);
    return total;
  }
  }
  const int ngroups = static_cast<int>(spec_.reaction_groups.size());
  double value = 0.0;
  if (fracdem::body_vector_entry(body_, i, ngroups, value)) return value;
  switch (i - (fracdem::kVecSize + 3 * ngroups)) {
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
  if (!spec_.contact_bodies) return;
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
  so.youngs = std::min(spec_.material.E, other_E);
  so.penalty_scale = spec_.contact_penalty;
  so.thickness = domain->dimension == 2 ? spec_.material.thickness : 1.0;
  so.axisymmetric = body_.space().axisymmetric();
  auto* mu = static_cast<FixPropertyGlobal*>(
      modify->find_fix_property("coefficientFriction", "property/global", "peratomtypepair",
                                atom->ntypes, atom->ntypes, style));
  so.friction = mu->compute_array(spec_.surface_type - 1, other_type - 1);
  return so;
}

// This body handles its own pieces and every later fix fem/body with contact_bodies yes.
void FixFemBody::find_contact_partners()
{
  self_contact_.configure(surface_options(spec_.surface_type, spec_.material.E));
  partners_.clear();
  contact_partner_of_.clear();
  bool after = false;
  for (int i = 0; i < modify->nfix; ++i) {
    auto* other = dynamic_cast<FixFemBody*>(modify->fix[i]);
    if (other == this) {
      after = true;
    } else if (other && other->spec_.contact_bodies > 0) {
      if (after) {
        partners_.emplace_back();
        partners_.back().other = other;
        const auto so = surface_options(other->spec_.surface_type, other->spec_.material.E);
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
  body_.erode({e}, spec_.erosion.remove_mass);
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
    if (spec_.dt_check_error)
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
    if (!spec_.erode_cracked && body_.element_time_step(e) >= update->dt) continue;
    eroded.push_back(e);
    if (comm->me != 0) continue;
    char line[256];
    snprintf(line, sizeof(line),
             "fix fem/body %s: step " BIGINT_FORMAT ": failed element %d %s, eroded\n", id,
             update->ntimestep, e,
             spec_.erode_cracked ? "carries no more tension" : "squeezed below the host time step");
    if (logfile) fputs(line, logfile);
    if (screen) fputs(line, screen);
  }
  body_.erode(eroded, spec_.erosion.remove_mass);
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
          fracdem::split_node_count(body_), fracdem::fragment_count(body_), body_.boundary_work());
  if (spec_.viscosity.on) fprintf(energy_fp_, ",%.12g", body_.viscous_work());
  if (can_erode())
    fprintf(energy_fp_, ",%d,%.12g,%.12g", body_.eroded().elements, body_.eroded().mass,
            body_.eroded().energy);
  if (body_.space().axisymmetric()) fprintf(energy_fp_, ",%.12g", body_.shield_work());
  const auto& r = body_.reactions();
  for (size_t k = 0; k < 3 * spec_.reaction_groups.size(); ++k)
    fprintf(energy_fp_, ",%.12g", k < r.size() ? r[k] : 0.0);
  // Mean displacement of each group's nodes (load-displacement curves).
  for (const std::string& g : spec_.reaction_groups) {
    const std::vector<int> nodes = fracdem::body_node_set(body_, spec_, g, "energy_file");
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
// After the transforms the head may hold sections (tag, number of doubles, doubles); a reader
// skips the head by its length, so one that knows no sections reads the placement as before.
// kSelfContactSection: the contact state of the body's pieces (SurfaceContact::pack_state),
// written only where there is some, so a body without piece contact writes the same bytes.
constexpr double kRecordHead = -1.0;
constexpr double kSelfContactSection = 1.0;

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
  std::vector<double> buf = {kRecordHead, 0.0, spec_.rigid ? 1.0 : 0.0,
                             static_cast<double>(spec_.transforms.size())};
  for (const fracdem::MeshTransform& t : spec_.transforms) {
    buf.push_back(static_cast<double>(t.kind));
    buf.insert(buf.end(), t.a, t.a + 4);
  }
  std::vector<double> self_state;
  if (spec_.contact_bodies) self_contact_.pack_state(self_state);
  if (!self_state.empty()) {
    buf.push_back(kSelfContactSection);
    buf.push_back(static_cast<double>(self_state.size()));
    buf.insert(buf.end(), self_state.begin(), self_state.end());
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
  if (rigid == spec_.rigid && same_placement(stored, spec_.transforms)) return;
  const std::string msg = std::string(kStyle) + " " + id +
                          ": the restart file holds this body with '" +
                          placement_text(rigid, stored) + "' but this command gives '" +
                          placement_text(spec_.rigid, spec_.transforms) +
                          "'; the body continues from the stored state and placement, so give "
                          "the stored keywords (to start the body afresh from its mesh instead, "
                          "put 'run 0' before this fix command: a run drops the file's fix "
                          "states)";
  error->all(FLERR, msg.c_str());
}

void FixFemBody::restart(char* raw)
{
  const double* record = reinterpret_cast<const double*>(raw);
  const double* self_state = nullptr;
  size_t self_state_size = 0;
  if (record[0] == kRecordHead) {
    const int n = static_cast<int>(record[1]);
    check_stored_placement(record + 2, n);
    for (int k = 2 + 5 * static_cast<int>(record[3]); k < n;) {
      const double tag = record[2 + k];
      const int size = k + 1 < n ? static_cast<int>(record[3 + k]) : -1;
      if (size < 0 || k + 2 + size > n) error->all(FLERR, "fix fem/body: corrupt restart record");
      if (tag == kSelfContactSection) {
        self_state = record + 4 + k;
        self_state_size = static_cast<size_t>(size);
      }
      k += 2 + size;
    }
    record += 2 + n;
  }
  try {
    body_.unpack_state(record);
  } catch (const std::exception& e) {
    std::string msg = std::string(kStyle) + " " + id + ": " + e.what() + " (mesh '" +
                      spec_.mesh_file +
                      "'); use the same mesh file and transforms as the run that wrote it";
    error->all(FLERR, msg.c_str());
  }
  rebuild_surfaces();
  // The pieces' contacts continue where they were (without: a resting contact would restart
  // as an unexplained penetration and lose its force).
  if (spec_.contact_bodies && self_state) {
    try {
      self_contact_.unpack_state(self_state, self_state_size);
    } catch (const std::exception& e) {
      error->all(FLERR, (std::string(kStyle) + " " + id + ": " + e.what()).c_str());
    }
  }
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
