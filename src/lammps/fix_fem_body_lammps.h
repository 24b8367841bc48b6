// fix fem/body under LAMMPS (preview): a deformable finite-element body integrated in step with
// LAMMPS and hit by atom_style sphere particles; the physics is the core's fracdem::Body and
// fracdem::ParticleFacetContact, as in the LIGGGHTS adapter.
#pragma once

#include <string>
#include <vector>

#include "fix.h"

#include "contact/particle_facet.h"
#include "fem/body.h"
#include "fem/body_setup.h"
#include "fem/body_spec.h"

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
  // The contact law as written after keyword 'contact' (LAMMPS's granular syntax, the supported
  // subset): hertz/material E COR NU, damping coeff_restitution|tsuji, tangential mindlin NULL XT
  // MU | linear_nohistory XT 0.
  struct ContactLaw {
    bool on = false;
    double E = 0, cor = 0, nu = 0;
    bool tsuji = false;    // damping tsuji (else coeff_restitution)
    bool history = true;   // tangential mindlin (else linear_nohistory, frictionless)
    double xt = 0, mu = 0; // tangential damping ratio and friction coefficient
  };
  // compliance combined: the body's youngs/poisson enter E*, G*.
  bool combined() const { return spec_.compliance_combined > 0; }

  // The core's keyword table (fracdem::parse_body_spec), restricted to this host, and its checks.
  void parse_arguments(int narg, char** arg);
  void load_mesh();
  void log_line(const std::string& line) const;
  void check_time_step();
  void read_gravity();
  void compute_forces();
  // keyword 'contact' and its parts (each returns the index of the word after it)
  void parse_contact(fracdem::SpecReader& r);
  void parse_contact_normal(const fracdem::SpecReader& r);
  std::size_t parse_contact_damping(const fracdem::SpecReader& r, std::size_t j);
  std::size_t parse_contact_tangential(const fracdem::SpecReader& r, std::size_t j);
  std::size_t parse_contact_none(const fracdem::SpecReader& r, std::size_t j);
  std::size_t parse_contact_unsupported(const fracdem::SpecReader& r, std::size_t j);
  void contact_setup();
  fracdem::ParticleArrays particle_arrays() const;
  void warn_unresolved_contact(const fracdem::ParticleFacetResult& res);
  std::string box_violation() const;
  void check_in_box(const char* when);

  // ---- arguments ----
  fracdem::BodySpec spec_;
  ContactLaw law_;
  fracdem::ContactMaterial contact_material_;

  // ---- the body, replicated on every rank ----
  fracdem::Body body_;
  bool split_element_work_ = false; // element work shared among ranks (else replicated)
  double gravity_[3] = {0, 0, 0};
  double dt_stable_ = 0;
  bool initial_velocity_applied_ = false;

  // ---- particle contact ----
  fracdem::ParticleFacetContact contact_;
  double** history_ = nullptr; // per atom: history_slots records of fracdem::kHistorySlotDoubles
  int ncontacts_ = 0;
  bool warned_slots_ = false, warned_unresolved_ = false, warned_outside_ = false;
  bool warned_no_contact_ = false;
};

} // namespace LAMMPS_NS
