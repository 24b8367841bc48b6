// fix fem/body under LAMMPS (preview): a deformable finite-element body integrated in step with
// LAMMPS; the physics is the core's fracdem::Body, as in the LIGGGHTS adapter.
#pragma once

#include <string>
#include <vector>

#include "fix.h"

#include "fem/body.h"

namespace LAMMPS_NS
{

class FixFemBodyLammps : public Fix
{
public:
  FixFemBodyLammps(class LAMMPS*, int, char**);

  int setmask() override;
  void init() override;
  void setup(int) override;
  void initial_integrate(int) override;
  void post_force(int) override;
  void final_integrate() override;
  void reset_dt() override;

  double compute_scalar() override;
  double compute_vector(int) override;

  const fracdem::Body& body() const { return body_; }

private:
  struct NodeVelocitySpec {
    std::string set;
    double v[3];
    double ramp = 0; // prescribed_velocity: linear ramp time
    int group = -1;  // reaction account
  };
  struct FixedSpec {
    std::string set;
    int mask; // held components, bit d = component d
    int group;
  };

  void parse_arguments(int narg, char** arg);
  double number(const char* keyword, const char* word);
  int whole_number(const char* keyword, const char* word);
  int reaction_group(const std::string& set);
  void check_arguments();
  void load_mesh();
  void log_line(const std::string& line) const;
  std::vector<int> node_set(const std::string& name, const char* keyword) const;
  void check_time_step();
  void read_gravity();
  void compute_forces();

  // ---- arguments ----
  std::string mesh_file_;
  int surface_type_ = -1;
  fracdem::Material material_;
  bool have_density_ = false, have_youngs_ = false, have_poisson_ = false;
  bool have_plane_ = false;
  std::vector<FixedSpec> fixed_sets_;
  std::vector<std::string> reaction_groups_; // fixed / prescribed_velocity groups, in order
  std::vector<NodeVelocitySpec> initial_velocity_, prescribed_velocity_;
  std::vector<fracdem::MeshTransform> transforms_;
  bool dt_check_error_ = true;
  bool apply_gravity_ = true;

  // ---- the body, replicated on every rank ----
  fracdem::Body body_;
  bool split_element_work_ = false; // element work shared among ranks (else replicated)
  double gravity_[3] = {0, 0, 0};
  double dt_stable_ = 0;
  bool initial_velocity_applied_ = false;
};

} // namespace LAMMPS_NS
