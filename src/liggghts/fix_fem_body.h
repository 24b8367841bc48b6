// fix fem/body: a deformable (or rigid, prescribed-motion) finite-element body that DEM particles
// hit.
#pragma once

#include <string>
#include <vector>

#include "fix.h"

#include "fe_only_scene.h"

#include "body/body_driver.h"

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
  const fracdem::Body& body() const { return driver_.body(); }
  // parallel distributed: this rank holds part() of the body only.
  bool distributed() const { return driver_.distributed(); }
  const fracdem::MeshPart& part() const { return driver_.part(); }
  const fracdem::PartTopology& topology() const { return driver_.topology(); }
  const fracdem::Mesh& mesh() const { return body().mesh(); }
  const fracdem::FeSpace& fe_space() const { return body().space(); }
  const std::vector<double>& positions() const { return body().positions(); }
  const std::vector<double>& velocities() const { return body().velocities(); }
  bool is_rigid() const { return body().rigid(); }
  double body_time() const { return body().time(); }
  // Facet checks and resolved facet contacts per local particle in the last force evaluation
  // (empty when the body has no contact surface); the load balancer's cost input.
  const std::vector<int>& facet_checks() const { return driver_.contact().checks(); }
  const std::vector<int>& facet_contacts() const { return driver_.contact().contacts(); }

  // Number of doubles per history slot: feature key (two exact 32-bit halves) + shear[3].
  static constexpr int kSlotDoubles = fracdem::kHistorySlotDoubles;

private:
  // ---- set-up helpers ----
  fracdem::BodyHost host() const;
  void parse_arguments(int narg, char** arg);
  void load_mesh();
  // Where the body leaves the part of the box that particles can reach ("" if nowhere).
  std::string box_violation() const;
  void check_in_box(const char* when);
  void find_restart_records();
  void check_restart_records();
  void read_contact_properties();
  void find_contact_partners();
  void read_gravity();

  // ---- per-step work: the core's fracdem::BodyDriver; this adapter moves data ----
  fracdem::ParticleArrays particle_arrays() const;
  void compute_forces();

  // ---- arguments (fracdem::parse_body_spec, check_body_spec) ----
  fracdem::BodySpec spec_;

  // ---- the body (replicated on every rank), its step and its contact surfaces ----
  fracdem::BodyDriver driver_;
  FeOnlyScene fe_only_{lmp};
  // fem/body records of a restart file read before this fix, when none has this fix's ID; the
  // first run checks that other fixes take them up (a renamed fix would silently start afresh).
  std::vector<std::string> other_restart_ids_;
  bool warned_outside_ = false; // a deformable body's nodes left the box: warned once

  // ---- per-atom tangential history (rows of nslots_ records) ----
  int nslots_ = 8;
  double** history_ = nullptr; // [nmax][nslots_*kSlotDoubles]
  int nmax_atoms_ = 0;
};

} // namespace LAMMPS_NS
