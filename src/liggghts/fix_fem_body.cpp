// fix fem/body under LIGGGHTS: moves data between the host and the core's fracdem::BodyDriver (a
// replicated FE body, its step and its contact with particles and other bodies).
#include "fix_fem_body.h"

#include <cstring>
#include <functional>
#include <memory>

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

#include "contact/granular_law.h"
#include "body/body_setup.h"
#include "io/input_help.h"
#include "mpi_body_host.h"

using namespace LAMMPS_NS;
using namespace FixConst;

namespace
{

const char* const kStyle = "fix fem/body";
// Steps between checks that the body is still inside the box (besides every re-neighbouring):
// a pass over its surface nodes, cheap beside the element work of as many steps.
constexpr int kBoxCheckEvery = 100;

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
  // fracdem::BodyVectorIndex (docs/fix_fem_body.md), 3 reactions per group, BodyVectorTail.
  size_vector = driver_.vector_size();
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
}

int FixFemBody::setmask()
{
  return INITIAL_INTEGRATE | POST_FORCE | FINAL_INTEGRATE | PRE_NEIGHBOR;
}

// The core's BodyDriver gets the MPI services over world and this host's output and errors.
fracdem::BodyHost FixFemBody::host() const
{
  fracdem::BodyHost h;
  fracdem::add_mpi_services(h, world);
  LAMMPS* host = lmp;
  h.print = [host](const std::string& line, bool to_screen, bool to_log) {
    if (to_screen && host->screen) fputs(line.c_str(), host->screen);
    if (to_log && host->logfile) fputs(line.c_str(), host->logfile);
  };
  Error* err = error;
  h.warning = [err](const std::string& text) { err->warning(FLERR, text.c_str()); };
  h.error_all = [err](const std::string& text) { err->all(FLERR, text.c_str()); };
  h.error_one = [err](const std::string& text) { err->one(FLERR, text.c_str()); };
  return h;
}

/* ----------------------------------------------------------------------
   argument parsing: fix ID group fem/body file FILE keyword value ...
   The core's keyword table (fracdem::parse_body_spec), all of it.
------------------------------------------------------------------------- */

void FixFemBody::parse_arguments(int narg, char** arg)
{
  const std::string units = fracdem::body_units_error(update->unit_style);
  if (!units.empty()) error->all(FLERR, (std::string(kStyle) + ": " + units).c_str());
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
  driver_.attach(spec_, id, host());
  try {
    driver_.build(domain->dimension);
  } catch (const fracdem::SpecError& e) {
    error->all(FLERR, fracdem::fix_message(e, id).c_str());
  }
  check_in_box("as placed");
  if (comm->me == 0) {
    const std::string line = driver_.describe() + "\n";
    if (screen) fputs(line.c_str(), screen);
    if (logfile) fputs(line.c_str(), logfile);
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
  return fracdem::body_box_violation(driver_.contact().facets(), body().positions().data(), box);
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
  // A distributed body's rank sees its own part only: it stops the run by itself.
  auto stop = [this](const std::string& text) {
    if (driver_.distributed())
      error->one(FLERR, text.c_str());
    else
      error->all(FLERR, text.c_str());
  };
  if (placed) {
    stop(msg + where + " (keywords 'move', 'scale', 'rotate' place it)");
  } else if (spec_.rigid) {
    if (spec_.motion.kind != fracdem::RigidMotion::None)
      msg += "its prescribed 'motion' has carried it out of the box: ";
    error->all(FLERR, (msg + where).c_str());
  }
  warned_outside_ = true;
  msg += "its nodes have moved out of the box: " + where + " (warned once; the run goes on)";
  if (comm->me == 0 || driver_.distributed()) error->warning(FLERR, msg.c_str());
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
  fracdem::ParticleFacetOptions opt;
  opt.model = spec_.normal_model;
  opt.tangential_history = spec_.tangential_history;
  opt.hertz_patch = !spec_.rigid && !spec_.compliance_combined &&
                    spec_.normal_model == fracdem::NormalModel::Hertz;
  spec_.buffer = spec_.buffer >= 0 ? spec_.buffer : neighbor->skin;
  opt.buffer = spec_.buffer;
  driver_.configure_contact(opt, std::move(per_type));
}

// This body computes the contact with its own pieces and every later fix fem/body with
// contact_bodies yes; friction: coefficientFriction of the surface types.
void FixFemBody::find_contact_partners()
{
  std::vector<fracdem::BodyDriver*> later, earlier;
  bool after = false;
  for (int i = 0; i < modify->nfix; ++i) {
    auto* other = dynamic_cast<FixFemBody*>(modify->fix[i]);
    if (other == this)
      after = true;
    else if (other && other->spec_.contact_bodies > 0)
      (after ? later : earlier).push_back(&other->driver_);
  }
  auto* mu = static_cast<FixPropertyGlobal*>(
      modify->find_fix_property("coefficientFriction", "property/global", "peratomtypepair",
                                atom->ntypes, atom->ntypes, style));
  driver_.set_partners(later, earlier,
                       [mu](int ti, int tj) { return mu->compute_array(ti - 1, tj - 1); });
}

void FixFemBody::read_gravity()
{
  double g[3] = {0, 0, 0};
  for (int i = 0; i < modify->nfix; ++i)
    if (!strcmp(modify->fix[i]->style, "gravity"))
      static_cast<FixGravity*>(modify->fix[i])->get_gravity(g);
  driver_.set_gravity(g);
}

void FixFemBody::init()
{
  check_restart_records();
  fe_only_.init(this);
  read_contact_properties();
  if (spec_.contact_bodies) find_contact_partners();
  read_gravity();
  const std::string failed = driver_.open_energy_file();
  if (!failed.empty()) error->one(FLERR, failed.c_str());
  driver_.check_time_step(update->dt);
}

void FixFemBody::reset_dt()
{
  driver_.check_time_step(update->dt);
}

/* ---------------------------------------------------------------------- */

void FixFemBody::setup(int /*vflag*/)
{
  driver_.start_run();
  driver_.particles_regrouped();
  check_in_box("at the start of the run"); // restart, change_box and earlier runs move it
  driver_.contact().invalidate_search();
  compute_forces();
  driver_.log_memory();
  driver_.write_energy_row_if_due(update->ntimestep);
}

// The host drops particles outside the box when it re-neighbours: the body is checked then too,
// and every kBoxCheckEvery steps (a scene without moving particles never re-neighbours).
void FixFemBody::pre_neighbor()
{
  driver_.particles_regrouped(); // a distributed body exchanges its particle boxes
  driver_.contact().invalidate_search();
  check_in_box(nullptr);
}

/* ----------------------------------------------------------------------
   velocity Verlet, in step with the host: half kick + drift here,
   forces in post_force, second half kick (fracture, energy row) in
   final_integrate
------------------------------------------------------------------------- */

void FixFemBody::initial_integrate(int /*vflag*/)
{
  driver_.begin_step(update->dt);
  if (update->ntimestep % kBoxCheckEvery == 0) check_in_box(nullptr);
}

void FixFemBody::post_force(int /*vflag*/)
{
  compute_forces();
}

void FixFemBody::final_integrate()
{
  driver_.end_step(update->ntimestep, update->dt);
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
  // A distributed body in a run without particles exchanges nothing for contact.
  const fracdem::ParticleArrays particles = particle_arrays();
  const bool none = driver_.distributed() && atom->natoms == 0;
  driver_.compute_forces(none ? nullptr : &particles, update->ntimestep, update->dt,
                         update->setupflag == 0);
}

/* ---------------------------------------------------------------------- */

double FixFemBody::compute_scalar()
{
  return driver_.scalar();
}

double FixFemBody::compute_vector(int i)
{
  return driver_.vector_entry(i);
}

/* ----------------------------------------------------------------------
   restart: the core's record (fracdem::BodyDriver::restart_record); the
   mesh is re-read from the same file when the input re-creates the fix
------------------------------------------------------------------------- */

void FixFemBody::write_restart(FILE* fp)
{
  driver_.write_restart(fp); // every rank: a distributed body gathers its parts
}

void FixFemBody::restart(char* raw)
{
  driver_.read_restart(reinterpret_cast<const double*>(raw));
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
  double bytes = static_cast<double>(driver_.memory_bytes());
  bytes += sizeof(double) * nmax_atoms_ * nslots_ * kSlotDoubles;
  return bytes;
}
