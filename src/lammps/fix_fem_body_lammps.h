// fix fem/body under LAMMPS: a finite-element body integrated in step with LAMMPS and hit by
// atom_style sphere particles; its step is the core's fracdem::BodyDriver, as in the LIGGGHTS
// adapter.
#pragma once

#include <string>
#include <vector>

#include "fix.h"

#include "body/body_driver.h"
#include "body/body_setup.h"
#include "body/body_spec.h"

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
  int pack_restart(int, double*) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;
  double memory_usage() override;

  double compute_scalar() override;
  double compute_vector(int) override;

  // The body's state and topology (the core's record, as the LIGGGHTS adapter writes it).
  void write_restart(FILE*) override;
  void restart(char*) override;

  const fracdem::Body& body() const { return driver_.body(); }
  // parallel distributed: this rank holds part() of the body only.
  bool distributed() const { return driver_.distributed(); }
  const fracdem::MeshPart& part() const { return driver_.part(); }
  const fracdem::PartTopology& topology() const { return driver_.topology(); }
  // Particle contact: per local particle, its facet checks and contacts in the last evaluation
  // (empty without `contact`); read by compute fracdem/cost.
  const fracdem::ParticleFacetContact& contact() const { return driver_.contact(); }

private:
  // The contact law as written after keyword 'contact' (LAMMPS's granular syntax, the supported
  // subset): hertz/material E COR NU, damping coeff_restitution|tsuji, tangential mindlin NULL XT
  // MU | linear_nohistory XT 0; or a given stiffness, hooke|hertz K_N DAMP, damping none|velocity|
  // mass_velocity|viscoelastic|coeff_restitution|tsuji, tangential linear_history|mindlin K_T XT
  // MU | linear_nohistory XT MU.
  struct ContactLaw {
    bool on = false;
    double E = 0, cor = 0, nu = 0; // cor: the normal model's second value (DAMP for hooke|hertz)
    bool tsuji = false;            // damping tsuji (else coeff_restitution)
    bool history = true;           // tangential mindlin (else linear_nohistory, frictionless)
    double xt = 0, mu = 0;         // tangential damping ratio and friction coefficient
    // given stiffness (normal hooke|hertz): k_n, the damping model, k_t (mindlin: times a)
    bool given_k = false, hooke = false, kt_times_a = false;
    double kn = 0, kt = 0;
    std::string damping = "viscoelastic"; // LAMMPS's default damping model
  };
  // compliance combined: the body's youngs/poisson enter E*, G*.
  bool combined() const { return spec_.compliance_combined > 0; }

  // The core's keyword table (fracdem::parse_body_spec), restricted to this host, and its checks.
  fracdem::BodyHost host() const;
  void parse_arguments(int narg, char** arg);
  void load_mesh();
  void log_line(const std::string& line) const;
  void read_gravity();
  void find_contact_partners();
  void compute_forces();
  // keyword 'contact' and its parts (each returns the index of the word after it)
  void parse_contact(fracdem::SpecReader& r);
  std::size_t parse_contact_normal(const fracdem::SpecReader& r);
  std::size_t parse_contact_damping(const fracdem::SpecReader& r, std::size_t j);
  std::size_t parse_contact_tangential(const fracdem::SpecReader& r, std::size_t j);
  std::size_t parse_given_stiffness(const fracdem::SpecReader& r, const std::string& normal);
  std::size_t parse_contact_none(const fracdem::SpecReader& r, std::size_t j);
  std::size_t parse_contact_unsupported(const fracdem::SpecReader& r, std::size_t j);
  void contact_setup();
  void contact_setup_given_k();
  fracdem::ParticleArrays particle_arrays() const;
  std::string box_violation() const;
  void check_in_box(const char* when);

  // ---- arguments ----
  fracdem::BodySpec spec_;
  ContactLaw law_;
  fracdem::ContactMaterial contact_material_;

  // ---- the body (replicated on every rank), its step and its contact surfaces ----
  fracdem::BodyDriver driver_;

  // ---- particle contact ----
  double** history_ = nullptr; // per atom: history_slots records of fracdem::kHistorySlotDoubles
  bool warned_outside_ = false, warned_no_contact_ = false;
};

} // namespace LAMMPS_NS
