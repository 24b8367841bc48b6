// fix fem/body: a deformable (or rigid, prescribed-motion) finite-element body that DEM particles
// hit.
#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "fix.h"

#include "fe_only_scene.h"

#include "contact/particle_facet.h"
#include "contact/surface_contact.h"
#include "fem/body.h"
#include "fem/body_spec.h"
#include "fem/erosion.h"
#include "fracture/nodal_fracture.h"

namespace LAMMPS_NS
{

class FixFemBody : public Fix
{
public:
  FixFemBody(class LAMMPS*, int, char**);
  ~FixFemBody() override;

  int setmask() override;
  void init() override;
  // Properties::max_type() stops a granular run unless something in it uses type 1: the body
  // meets particles of every type from 1 on. No max_type(): pair gran would then apply its
  // particle-material checks (youngsModulus <= 1e9 in SI) to the body's own type.
  int min_type() override { return 1; }
  void setup(int) override;
  void initial_integrate(int) override;
  void post_force(int) override;
  void final_integrate() override;
  void pre_neighbor() override;
  void reset_dt() override;

  double compute_scalar() override;
  double compute_vector(int) override;

  void write_restart(FILE*) override;
  void restart(char*) override;

  // Per-particle tangential contact history travels with its particle.
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double*) override;
  int unpack_exchange(int, double*) override;
  int pack_restart(int, double*) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;
  double memory_usage() override;

  // Read access for output fixes (fix fem/vtk) and diagnostics.
  const fracdem::Body& body() const { return body_; }
  const fracdem::Mesh& mesh() const { return body_.mesh(); }
  const fracdem::FeSpace& fe_space() const { return body_.space(); }
  const std::vector<double>& positions() const { return body_.positions(); }
  const std::vector<double>& velocities() const { return body_.velocities(); }
  bool is_rigid() const { return body_.rigid(); }
  double body_time() const { return body_.time(); }
  // Facet checks and resolved facet contacts per local particle in the last force evaluation
  // (empty when the body has no contact surface); the load balancer's cost input.
  const std::vector<int>& facet_checks() const { return contact_.checks(); }
  const std::vector<int>& facet_contacts() const { return contact_.contacts(); }

  // Number of doubles per history slot: feature key (two exact 32-bit halves) + shear[3].
  static constexpr int kSlotDoubles = fracdem::kHistorySlotDoubles;

private:
  // ---- set-up helpers ----
  void parse_arguments(int narg, char** arg);
  void load_mesh();
  void log_body();
  void log_memory();
  double contact_memory_bytes() const;
  // Where the body leaves the part of the box that particles can reach ("" if nowhere).
  std::string box_violation() const;
  void check_in_box(const char* when);
  void find_restart_records();
  void check_restart_records();
  void check_stored_placement(const double* head, int n);
  void check_crack_band();
  void read_contact_properties();
  void check_time_step();

  // ---- per-step work ----
  void warn_unresolved_contact(const fracdem::ParticleFacetResult& res);
  void compute_forces();
  fracdem::ParticleArrays particle_arrays() const;
  void write_energy_row();
  void fracture();
  void log_splits(const std::vector<fracdem::SplitEvent>& events);
  void log_fragments();
  int last_fragments_ = 1;
  void erode_inverted(int e);
  double internal_forces(int& first_inverted);
  double forces_after_erosion(double energy, int& first_inverted);
  void after_erosion(const int* counts, const std::vector<int>& batch);
  void log_erosion(const int* counts, const std::vector<int>& batch);
  bool warned_dt_after_erosion_ = false;
  // The body can lose elements (energy-file columns eroded_*): erosion or nodal fracture.
  bool can_erode() const { return spec_.erosion.on() || spec_.fracture_every > 0; }
  int erode_collapsed(const std::vector<double>& failure);
  fracdem::FailureMap failure_map_;

  // ---- arguments (fracdem::parse_body_spec, check_body_spec) ----
  fracdem::BodySpec spec_;
  bool split_element_work_ = false; // element work shared among ranks (else replicated)
  FILE* energy_fp_ = nullptr;
  bigint last_energy_step_ = -1;

  // ---- the body (replicated on every rank) and its contact surface ----
  fracdem::Body body_;
  fracdem::ParticleFacetContact contact_;
  FeOnlyScene fe_only_{lmp};
  // Contact of the body's surface with its own pieces and with later bodies (partners).
  struct Partner {
    FixFemBody* other = nullptr;
    fracdem::SurfaceContact mine_on_theirs, theirs_on_mine;
  };
  fracdem::ContactSurface surface_;
  fracdem::SurfaceContact self_contact_;
  std::vector<Partner> partners_;
  std::vector<FixFemBody*> contact_partner_of_; // earlier bodies that handle contact with this one
  fracdem::SurfaceContactOptions surface_options(int other_type, double other_E) const;
  void find_contact_partners();
  void partner_changed(FixFemBody* other);
  int body_contacts();
  void rebuild_surfaces();
  double gravity_[3] = {0, 0, 0};
  int ncontacts_ = 0;
  double dt_stable_ = 0;
  bool initial_velocity_applied_ = false;
  bool restarted_state_ = false;
  // fem/body records of a restart file read before this fix, when none has this fix's ID; the
  // first run checks that other fixes take them up (a renamed fix would silently start afresh).
  std::vector<std::string> other_restart_ids_;
  bool warned_slots_ = false;
  bool warned_unresolved_ = false; // the time-resolution warning is given once per run
  bool warned_outside_ = false;    // a deformable body's nodes left the box: warned once

  // ---- per-atom tangential history (rows of nslots_ records) ----
  int nslots_ = 8;
  double** history_ = nullptr; // [nmax][nslots_*kSlotDoubles]
  int nmax_atoms_ = 0;
};

} // namespace LAMMPS_NS
