// Particle-surface contact law in LIGGGHTS' conventions (wall/gran hertz|hooke, tangential
// history) and LAMMPS's pair granular laws with a given stiffness (hooke|hertz k_n damp).
#pragma once

#include <cstdint>

namespace fracdem
{

enum class NormalModel : std::uint8_t { Hertz, Hooke };

// LAMMPS's pair granular damping models (gran_sub_mod_damping.cpp, LAMMPS 22 Jul 2025): the
// normal damping force is -eta v_n with eta = c (Velocity), c m (MassVelocity), c m a
// (Viscoelastic), c sqrt(m F_ne / delta) (Tsuji, CoeffRestitution; c from the restitution).
enum class DampingModel : std::uint8_t {
  None,
  Velocity,
  MassVelocity,
  Viscoelastic,
  Tsuji,
  CoeffRestitution
};

// A law with a given stiffness, as LAMMPS's pair granular writes it: normal 'hooke k_n damp'
// (F_ne = k_n delta) or 'hertz k_n damp' (F_ne = k_n a delta, a the contact radius), a damping
// model, and a tangential spring k_t (linear_history) or k_t a (mindlin) with damping x_t eta,
// history and slip as LAMMPS's; the contact point lies at r from the centre (LAMMPS's walls).
struct GivenStiffness {
  bool on = false;
  double kn = 0;
  double c = 0; // eta's coefficient (for Tsuji / CoeffRestitution: converted from COR)
  DampingModel damping = DampingModel::Velocity;
  double kt = 0;
  bool kt_times_a = false; // mindlin: the tangential stiffness scales with the contact radius
  double xt = 0;           // tangential damping eta_t = xt eta
};

struct ContactMaterial {
  double Yeff = 0, Geff = 0; // effective Young's and shear moduli
  double coeffRest = 1, coeffFric = 0, charVel = 1;
  double betaeff = 0; // log(e) / sqrt(log(e)^2 + pi^2)
  NormalModel model = NormalModel::Hertz;
  bool tangential_history = true;
  GivenStiffness given; // on: this law replaces the moduli-based one above
};

// LIGGGHTS mixing: Yeff = 1/((1-nu1^2)/E1 + (1-nu2^2)/E2), Geff = 1/(2(2-nu1)(1+nu1)/E1 + ...).
// E2 <= 0 means "rigid surface": only the particle's compliance enters.
ContactMaterial mix_materials(double E1, double nu1, double E2, double nu2, double e, double mu,
                              double char_vel, NormalModel m, bool history);

// LAMMPS's pair granular law with a given stiffness: model Hooke or Hertz with k_n and the
// normal model's second value `damp` (a coefficient of restitution for Tsuji and
// CoeffRestitution, converted here as LAMMPS's damping init does); tangential spring kt (times a
// when kt_times_a), damping ratio xt, friction mu; history off: linear_nohistory (viscous,
// Coulomb-capped).
ContactMaterial given_stiffness_law(NormalModel m, double kn, double damp, DampingModel d,
                                    double kt, bool kt_times_a, double xt, double mu, bool history);

// LAMMPS's tsuji damping coefficient for a coefficient of restitution: Marshall 2009, eq. 53
// (LAMMPS 22 Jul 2025; later versions multiply it by sqrt(2)).
double tsuji_damping(double cor);

// One particle-surface contact. n: unit normal from the surface to the sphere centre; delta:
// overlap > 0; v_rel: particle centre velocity minus the surface velocity at the contact point;
// omega: particle spin. The particle's contact point sits at radius cr = r - delta/2 from its
// centre, as in LIGGGHTS' wall surface model.
struct ContactInput {
  double n[3];
  double delta;
  double radius;
  double mass;
  double v_rel[3];
  double omega[3];
  double dt;
  // Hertz contact radius, where the caller knows it better than sqrt(radius * delta) (a sphere on
  // a deformable surface: a^2 = R (delta + body indentation)); 0 = sqrt(radius * delta).
  double contact_radius = 0;
};
struct ContactOutput {
  double force[3];  // on the particle
  double torque[3]; // on the particle
  double fn;        // signed normal force magnitude (repulsive > 0)
};

// shear: tangential spring history (in/out), ignored when !tangential_history.
ContactOutput particle_surface_force(const ContactMaterial& mat, const ContactInput& in,
                                     double shear[3]);

// Classical elastic Hertz impact of a sphere (effective mass m, radius R) at speed v on a
// surface with effective modulus Estar.
struct HertzImpact {
  double peak_force, duration, max_overlap;
};
HertzImpact hertz_impact(double Estar, double R, double m, double v);

} // namespace fracdem
