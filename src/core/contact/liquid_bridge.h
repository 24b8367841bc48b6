// Pendular liquid bridge between two spheres or a sphere and a plane: capillary and viscous force,
// bridge potential and rupture distance.
//
// Capillary force: the closed-form approximation of Willett, Adams, Johnson & Seville,
// "Capillary bridges between two spherical bodies", Langmuir 16 (2000) 9396-9405, for unequal
// spheres through the Derjaguin radius R* = 2 R1 R2 / (R1 + R2) (R* = R for equal spheres,
// R* = 2 R1 against a plane, R2 -> infinity):
//
//   F_c(S) = 2 pi R* gamma cos(theta) / (1 + 1.05 S^ + 2.5 S^^2),   S^ = S sqrt(R*/V),
//
// S the gap between the surfaces (>= 0), gamma the surface tension, theta the contact angle, V the
// bridge volume. F_c(0) = 2 pi R* gamma cos(theta), the Derjaguin limit at contact; while the
// spheres overlap (S < 0) the force stays at that value.
//
// Viscous normal force: Pitois, Moucheront & Chateau, "Liquid bridge between two moving spheres:
// an experimental study of viscosity effects", J. Colloid Interface Sci. 231 (2000) 26-31, their
// closed form with R* in place of the sphere radius:
//
//   F_v = 6 pi mu R*^2 (dS/dt) / S * (1 - 1/sqrt(1 + 2 V / (pi R* S^2)))^2,
//
// mu the liquid viscosity; it resists the change of the gap (attractive while the gap opens). It
// grows as 1/S at small gaps, so S is floored at kViscousGapFloor * R* (overlap included).
//
// Rupture: Lian, Thornton & Adams, "A theoretical study of the liquid bridge forces between two
// rigid spherical bodies", J. Colloid Interface Sci. 161 (1993) 138-147:
//
//   S_c = (1 + theta/2) V^(1/3).
//
// A bridge forms when the surfaces touch and breaks once S >= S_c.
#pragma once

#include <string>
#include <vector>

namespace fracdem
{

struct LiquidBridge {
  double surface_tension = 0; // gamma, force per length
  double contact_angle = 0;   // theta, radians, in [0, pi/2)
  double volume = 0;          // V of one bridge
  double viscosity = 0;       // mu, dynamic viscosity; 0: no viscous force
};

// Gap floor of the viscous force as a fraction of R* (a roughness scale; keeps it finite).
constexpr double kViscousGapFloor = 1e-3;

// Empty when the parameters are valid, else what is wrong and what to write (keyword named).
std::string check_liquid_bridge(const LiquidBridge& b);

// R* = 2 r1 r2 / (r1 + r2); r2 <= 0 stands for a plane (R* = 2 r1).
double derjaguin_radius(double r1, double r2);

// S_c = (1 + theta/2) V^(1/3).
double rupture_distance(const LiquidBridge& b);

// Willett's F_c(S) >= 0 (attractive), F_c(0) for S < 0; 0 at and beyond S_c.
double capillary_force(const LiquidBridge& b, double r_star, double gap);

// Potential energy of the capillary force, zero at rupture: U(S) = -int_S^{S_c} F_c(s) ds for
// 0 <= S < S_c (closed form), U(0) + F_c(0) S for S < 0, 0 beyond S_c. dU/dS = F_c.
double capillary_potential(const LiquidBridge& b, double r_star, double gap);

// Pitois's F_v, positive when attractive (gap opening, gap_rate = dS/dt > 0); 0 beyond S_c.
double viscous_force(const LiquidBridge& b, double r_star, double gap, double gap_rate);

// A law with its constants evaluated once, for callers that evaluate it for every pair and step;
// the functions above are these with the law prepared on each call.
struct BridgeLaw {
  LiquidBridge params;
  double rupture = 0;            // S_c
  double two_pi_tension_cos = 0; // 2 pi gamma cos(theta): F_c(0) = this R*
};
BridgeLaw prepare_bridge(const LiquidBridge& b);
double capillary_force(const BridgeLaw& law, double r_star, double gap);
double capillary_potential(const BridgeLaw& law, double r_star, double gap);
double viscous_force(const BridgeLaw& law, double r_star, double gap, double gap_rate);

// Whether a bridge exists after this step: one forms at contact (gap <= 0) and persists while the
// gap stays below the rupture distance.
inline bool bridge_persists(bool bridged, double gap, double rupture)
{
  if (gap <= 0) return true;
  return bridged && gap < rupture;
}

// The words after 'bridge' in a pair style: "willett surface_tension G contact_angle THETA volume V
// [viscosity MU] [wet yes|no]", keywords in any order after the model name.
struct BridgeSettings {
  bool on = false;
  LiquidBridge law;
  bool wet = true; // pairs closer than the rupture distance at set-up start bridged
};

// Fills out from words; empty on success, else what is wrong and what to write.
std::string parse_bridge_settings(const std::vector<std::string>& words, BridgeSettings& out);

} // namespace fracdem
