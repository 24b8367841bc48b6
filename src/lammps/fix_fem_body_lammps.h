// fix fem/body under LAMMPS (preview): a deformable finite-element body integrated in step with
// LAMMPS and hit by atom_style sphere particles; the physics is the core's fracdem::Body and
// fracdem::ParticleFacetContact, as in the LIGGGHTS adapter.
#pragma once

#include <string>
#include <vector>

#include "fix.h"

#include "contact/particle_facet.h"
#include "fem/body.h"

namespace LAMMPS_NS
{

class FixFemBodyLammps : public Fix
{
public:
  FixFemBodyLammps(class LAMMPS*, int, char**);
  ~FixFemBodyLammps() override;

  int setmask() override;
  void init() override;
  void setup(int) override;
  void initial_integrate(int) override;
  void post_force(int) override;
  void final_integrate() override;
  void pre_neighbor() override;
  void reset_dt() override;

  // per-particle tangential history, migrating with the atoms
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double*) override;
  int unpack_exchange(int, double*) override;
  double memory_usage() override;

  double compute_scalar() override;
  double compute_vector(int) override;

  const fracdem::Body& body() const { return body_; }
  // Particle contact: per local particle, its facet checks and contacts in the last evaluation
  // (empty without `contact`); read by compute fracdem/cost.
  const fracdem::ParticleFacetContact& contact() const { return contact_; }

private:
  struct NodeVelocitySpec {
    std::string set;
    double v[3];
    double ramp = 0; // prescribed_velocity: linear ramp time
    int group = -1;  // reaction account
  };
  // The contact law as written after keyword 'contact' (LAMMPS's granular syntax, the supported
  // subset): hertz/material E COR NU, damping coeff_restitution|tsuji, tangential mindlin NULL XT
  // MU | linear_nohistory XT 0.
  struct ContactLaw {
    bool on = false;
    double E = 0, cor = 0, nu = 0;
    bool tsuji = false;    // damping tsuji (else coeff_restitution)
    bool history = true;   // tangential mindlin (else linear_nohistory, frictionless)
    double xt = 0, mu = 0; // tangential damping ratio and friction coefficient
    bool combined = false; // compliance combined: the body's youngs/poisson enter E*, G*
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
  int parse_contact(int iarg, int narg, char** arg);
  void contact_setup();
  fracdem::ParticleArrays particle_arrays() const;
  void warn_unresolved_contact(const fracdem::ParticleFacetResult& res);
  std::string box_violation() const;
  void check_in_box(const char* when);

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
  ContactLaw law_;
  fracdem::ContactMaterial contact_material_;
  double buffer_ = -1; // search buffer; < 0: the neighbour skin
  int nslots_ = 8;     // history_slots

  // ---- the body, replicated on every rank ----
  fracdem::Body body_;
  bool split_element_work_ = false; // element work shared among ranks (else replicated)
  double gravity_[3] = {0, 0, 0};
  double dt_stable_ = 0;
  bool initial_velocity_applied_ = false;

  // ---- particle contact ----
  fracdem::ParticleFacetContact contact_;
  double** history_ = nullptr; // per atom: nslots_ records of fracdem::kHistorySlotDoubles
  int ncontacts_ = 0;
  bool warned_slots_ = false, warned_unresolved_ = false, warned_outside_ = false;
  bool warned_no_contact_ = false;
};

} // namespace LAMMPS_NS
