// fix fem/body: a deformable (or rigid, prescribed-motion) finite-element body that DEM particles
// hit.
#pragma once

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "fix.h"

#include "contact/contact_resolution.h"
#include "contact/contact_spread.h"
#include "contact/contact_search.h"
#include "contact/granular_law.h"
#include "fem/fe_space.h"
#include "fem/material.h"
#include "fem/mesh.h"

namespace LAMMPS_NS
{

class FixFemBody : public Fix
{
public:
  FixFemBody(class LAMMPS*, int, char**);
  ~FixFemBody() override;

  int setmask() override;
  void init() override;
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
  const fracdem::Mesh& mesh() const { return mesh_; }
  const fracdem::FeSpace& fe_space() const { return space_; }
  const std::vector<double>& positions() const { return x_; }
  const std::vector<double>& velocities() const { return v_; }
  bool is_rigid() const { return rigid_; }
  double body_time() const { return time_; }
  // Facet checks and resolved facet contacts per local particle in the last force evaluation
  // (empty when the body has no contact surface); the load balancer's cost input.
  const std::vector<int>& facet_checks() const { return facet_checks_; }
  const std::vector<int>& facet_contacts() const { return facet_contacts_; }

  // Number of doubles per history slot: feature key (two exact 32-bit halves) + shear[3].
  static constexpr int kSlotDoubles = 5;

private:
  struct NodeVelocitySpec {
    std::string set;
    double v[3];
  };
  enum class MotionKind { None, Linear, Rotate };

  // ---- set-up helpers ----
  void parse_arguments(int narg, char** arg);
  void load_mesh();
  void apply_initial_transforms();
  std::vector<int> node_set(const std::string& name, const char* keyword) const;
  void read_contact_properties();
  void check_time_step();
  void prescribed_motion(double t, double* x, double* v) const;

  // ---- per-step work ----
  void compute_forces();
  void contact_forces(double* f_contact, int& ncontacts);
  void rebuild_search();
  bool search_is_stale();
  double* history_slot_find(int i, std::uint64_t key, bool create);
  double kinetic_energy() const;
  void write_energy_row();

  // ---- arguments ----
  std::string mesh_file_;
  int surface_type_ = -1;
  fracdem::Material material_;
  bool have_density_ = false, have_youngs_ = false, have_poisson_ = false;
  bool rigid_ = false;
  MotionKind motion_ = MotionKind::None;
  double motion_vel_[3] = {0, 0, 0};
  double motion_origin_[3] = {0, 0, 0}, motion_axis_[3] = {0, 0, 1}, motion_period_ = 0;
  std::vector<std::string> fixed_sets_;
  std::vector<NodeVelocitySpec> initial_velocity_, prescribed_velocity_;
  struct Transform {
    enum Kind { Scale, Move, Rotate } kind;
    double a[4];
  };
  std::vector<Transform> transforms_;
  fracdem::NormalModel normal_model_ = fracdem::NormalModel::Hertz;
  bool tangential_history_ = true;
  int compliance_combined_ = -1; // -1: default (combined for rigid, particle-only for deformable)
  double buffer_ = -1;           // search buffer; -1: host neighbour skin
  bool dt_check_error_ = true;
  bool apply_gravity_ = true;
  std::string energy_file_;
  int energy_every_ = 0;
  FILE* energy_fp_ = nullptr;
  bigint last_energy_step_ = -1;

  // ---- body state (replicated on every rank) ----
  fracdem::Mesh mesh_;
  fracdem::FeSpace space_;
  std::vector<double> x_, v_, f_, mass_, inv_mass_;
  std::vector<double> f_contact_, f_contact_prev_;
  std::vector<std::uint8_t> node_fixed_; // 0 free, 1 fixed, 2 prescribed velocity
  std::vector<double> v_prescribed_;
  int elem_begin_ = 0, elem_end_ = 0; // this rank's share of the element work
  double time_ = 0;                   // body time since creation (prescribed motion)
  double strain_energy_ = 0, external_work_ = 0, contact_work_ = 0;
  double gravity_[3] = {0, 0, 0};
  double contact_force_total_[3] = {0, 0, 0};
  int ncontacts_ = 0;
  double dt_stable_ = 0;
  bool initial_velocity_applied_ = false;
  bool restarted_state_ = false;

  // ---- contact ----
  fracdem::ContactMaterial contact_material_;
  std::vector<double> particle_E_, particle_nu_, particle_e_, particle_mu_; // per atom type
  double surface_E_ = 0, surface_nu_ = 0, char_vel_ = 1.0;
  std::vector<fracdem::Facet> facets_;
  fracdem::SurfaceTopology topology_;
  std::unique_ptr<fracdem::BufferedSearch> search_;
  std::vector<int> search_atoms_;     // search sphere index -> local atom index
  std::vector<double> search_sphere_; // x,y,z,r per search sphere at build time
  bool search_stale_ = true;
  std::vector<double> normals_, overlaps_; // per-hit scratch
  std::vector<int> facet_checks_, facet_contacts_;
  // Hertz contact on the resolved deformable surface (see hertz_contact_patch).
  std::vector<double> node_area_, indentation_disp_, patch_weights_;
  fracdem::SurfacePatch patch_;
  void rebuild_surface();
  bool hertz_contact_patch(const fracdem::FacetHit& lead, fracdem::ContactInput& in, double radius);
  int nrebuilds_ = 0;

  // ---- per-atom history ----
  int nslots_ = 8;
  double** history_ = nullptr; // [nmax][nslots_*kSlotDoubles]
  int nmax_atoms_ = 0;
  bool warned_slots_ = false;
};

} // namespace LAMMPS_NS
