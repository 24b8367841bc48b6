// Equations of state for the pressure of plastic materials: linear (elastic bulk) and
// Mie-Grueneisen with a linear-Hugoniot reference; host-free, one integration point at a time.
#pragma once

#include <cstdint>

namespace fracdem
{

// Sign convention: pressure p > 0 in compression; sigma = s - p I. Volumetric strain theta =
// tr(eps) of the small-strain kernels (theta < 0 in compression), relative volume J = 1 + theta.
//
//  * Linear       : p = -K theta, K = E / (3 (1 - 2 nu)) (the elastic bulk modulus).
//  * MieGruneisen : mu = rho / rho0 - 1 = 1 / J - 1, and with E the internal energy per unit
//    REFERENCE volume (so "Gamma0 rho0 e" with e per unit mass is Gamma0 E):
//      compression (mu > 0): p = rho0 C0^2 mu (1 + (1 - Gamma0 / 2) mu) / (1 - (S - 1) mu)^2
//                                + Gamma0 E
//      tension     (mu <= 0): p = rho0 C0^2 mu + Gamma0 E
//    This is the form of LS-DYNA *EOS_GRUNEISEN and Radioss /EOS/GRUNEISEN with S2 = S3 = a = 0
//    (Hugoniot U_s = C0 + S u_p); the energy term is kept in tension as those codes do.
//    Guards (not physics; a run that reaches them has inverted or crushed elements): J is held at
//    >= 0.1 and, for S > 1, mu at <= 0.9 / (S - 1) where the Hugoniot denominator would vanish.
//
// Energy: the volumetric work per unit reference volume, dW = -p dtheta, is integrated by the
// trapezoidal rule. With the energy term the new pressure depends on the new energy; eos_step
// solves that linear relation exactly, so W and p stay consistent step by step. For Linear the
// trapezoidal sum telescopes to 0.5 K theta^2 (exact stored energy).

enum class EosModel : std::uint8_t { Linear, MieGruneisen };

struct EosParams {
  EosModel model = EosModel::Linear;
  double c0 = 0, s = 0, gamma0 = 0; // Mie-Grueneisen: bulk sound speed, Hugoniot slope, Gamma0
};

// Pressure at volumetric strain theta with no internal energy: -K theta (Linear) or the
// Hugoniot-reference part above (MieGruneisen). K: elastic bulk modulus; rho0: reference density.
double eos_reference_pressure(const EosParams& e, double K, double rho0, double theta);
// Full pressure at theta and internal energy E (per unit reference volume).
double eos_pressure(const EosParams& e, double K, double rho0, double theta, double E);
// mu = rho / rho0 - 1 after the guards above.
double eos_compression(const EosParams& e, double theta);

// One step theta_old -> theta_new. p_old: pressure at the step's start; E (in/out): internal
// energy per unit reference volume; dissipated: other energy deposited in this step (plastic
// work), added to E before the pressure is taken. Returns the new pressure; *volumetric_work
// (if given) gets -0.5 (p_old + p_new) (theta_new - theta_old).
double eos_step(const EosParams& e, double K, double rho0, double theta_old, double theta_new,
                double p_old, double dissipated, double& E, double* volumetric_work = nullptr);

// Empty when valid, else the reason naming the constant (C0 > 0, S >= 0, GAMMA0 >= 0, finite).
const char* eos_check(const EosParams& e);

} // namespace fracdem
