// Particle-surface contact law in LIGGGHTS' conventions (wall/gran hertz|hooke, tangential
// history).
#pragma once

#include <cstdint>

namespace fracdem
{

enum class NormalModel : std::uint8_t { Hertz, Hooke };

struct ContactMaterial {
  double Yeff = 0, Geff = 0; // effective Young's and shear moduli
  double coeffRest = 1, coeffFric = 0, charVel = 1;
  double betaeff = 0; // log(e) / sqrt(log(e)^2 + pi^2)
  NormalModel model = NormalModel::Hertz;
  bool tangential_history = true;
};

// LIGGGHTS mixing: Yeff = 1/((1-nu1^2)/E1 + (1-nu2^2)/E2), Geff = 1/(2(2-nu1)(1+nu1)/E1 + ...).
// E2 <= 0 means "rigid surface": only the particle's compliance enters.
ContactMaterial mix_materials(double E1, double nu1, double E2, double nu2, double e, double mu,
                              double char_vel, NormalModel m, bool history);

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
