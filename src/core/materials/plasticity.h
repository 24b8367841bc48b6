// J2 (von Mises) plasticity with isotropic hardening by radial return: linear / power-law,
// Johnson-Cook and Zerilli-Armstrong flow stresses, adiabatic heating, pressure from an EOS.
#pragma once

#include <cstdint>

#include "materials/eos.h"
#include "materials/rankine.h" // StressMode

namespace fracdem
{

// Model (small strain, isotropic, one integration point at a time; no host types involved):
//
//  * Split: sigma = s - p I. The deviator s = 2 mu dev(eps - eps_p) is J2-plastic; the pressure p
//    comes from the EOS (materials/eos.h) of the volumetric strain theta = tr(eps) (plastic flow
//    is isochoric, tr eps_p = 0). mu = E / (2 (1 + nu)), K = E / (3 (1 - 2 nu)).
//  * Yield: q = sqrt(3/2 s:s) <= sigma_y(eps_p, rate, T). Radial return (backward Euler, exact
//    for the flow direction): trial s_tr with q_tr; if q_tr > sigma_y, solve
//      q_tr - 3 mu dgamma - sigma_y(eps_p + dgamma) = 0        (strictly decreasing in dgamma)
//    by safeguarded Newton (bisection inside the bracket [0, q_tr / (3 mu)]), then
//      s = s_tr (1 - 3 mu dgamma / q_tr),  eps_p += dgamma (3/2) s_tr / q_tr,  eps_bar += dgamma.
//    Linear hardening converges in one Newton step: dgamma = (q_tr - sigma_y) / (3 mu + H).
//  * Flow stress (eps = eps_bar, equivalent plastic strain; rate* = max(rate / eps0, floor)):
//      J2              : sigma_y = a + b eps^n                 (yield SY -> a, hardening H -> b,
//                                                               exponent N -> n, default 1)
//      JohnsonCook     : sigma_y = (a + b eps^n) (1 + c ln(max(rate / eps0, 1))) (1 - T*^m),
//                        T* = (T - troom) / (tmelt - troom) clamped to [0, 1]; no tmelt: the last
//                        factor is 1 (A B N C M -> a b n c m)
//      ZerilliArmstrong: sigma_y = a + b eps^n + c1 f(eps) exp(-c3 T + c4 T ln(rate*)),
//                        f = 1 (bcc) or sqrt(eps) (fcc), rate* floored at 1e-6 (the rate
//                        sensitivity stops there: ln 0 would remove the thermal term entirely)
//                        (C0 C1 C3 C4 C5 N -> a c1 c3 c4 b n)
//    Zerilli & Armstrong (1987, J. Appl. Phys. 61, 1816): bcc  sigma = dsigma_G' + C1 exp(-C3 T +
//    C4 T ln epsdot) + C5 eps^n + k l^-1/2, fcc  sigma = dsigma_G' + C2 eps^1/2 exp(...) + k
//    l^-1/2; C0 = dsigma_G' + k l^-1/2. The fcc form here takes C2 in the C1 slot and keeps
//    C5 eps^N as an optional athermal term (0 0 gives the 1987 fcc form), as in the general form
//    of IMPETUS *MAT_ZA; the bcc form is Radioss /MAT/PLAS_ZERIL.
//  * Rate: the equivalent deviatoric TOTAL strain rate of the step, sqrt(2/3 de:de) / dt with de
//    the deviatoric strain increment since the previous call (explicit codes' usual choice: in
//    sustained plastic flow it equals the plastic rate). dt <= 0 (no time information: output,
//    set-up) reuses the rate stored by the last call. The rate and the temperature are frozen
//    over the step (evaluated at its start), so the return solves for dgamma alone.
//  * Temperature T = troom + rise; adiabatic heating rise += beta dW_p / (rho cp) with the
//    Taylor-Quinney coefficient beta = 0.9 (the usual fraction of plastic work that becomes heat;
//    Taylor & Quinney 1934) and dW_p = sigma_y dgamma the plastic work of the step. cp <= 0: no
//    heating (isothermal at troom). T >= tmelt (JC): sigma_y = 0, the point flows like a fluid.
//  * Dissipation: W_p += s : d eps_p = sigma_y(new) dgamma per step (backward Euler, consistent
//    with the return). Internal energy E (EOS) += W_p increment + volumetric work (eos_step).
//  * A call whose strain equals the stored previous strain bit for bit (re-evaluation in the same
//    step, output on a copy of the state) returns the stored stress and changes nothing.
//  * Returned energy: recoverable energy density s:s / (4 mu) + W_vol, W_vol = E - W_p the stored
//    volumetric work (0.5 K theta^2 for the linear EOS).
//
//  * Logarithmic strain (log_strain, set by the corotational kernels, fem/fe_space.cpp): eps =
//    ln U of the corotated stretch, theta = ln J, and the same update gives the Kirchhoff stress
//    tau (work-conjugate to ln U per unit reference volume; Cauchy = tau / J, J = det F). Plastic
//    flow that is isochoric in ln U keeps the volume exactly at any strain. The EOS is a law of
//    the true relative volume: it is stepped from J_old - 1 to J - 1 (J = exp(theta)) with the
//    Cauchy pressure p_old = tau_p,old / J_old, and returns tau_p = J p (Linear: tau_p =
//    -K J (J - 1)); its energy sum -p dJ is then the volumetric work per unit reference volume.
//    Without the flag (small-strain kernels) theta is the small-strain dilatation J - 1.
//
// Stress modes (Voigt order xx, yy, zz, xy, yz, zx, ENGINEERING shear in eps):
//   Solid        : full 3D.
//   PlaneStrain  : yz = zx = 0 enforced; eps_zz is taken as given (0 from tri3, the B-bar
//                  correction from quad4); sigma_zz and eps_p,zz follow from the 3D update.
//   Axisymmetric : the zz slot is the hoop component; yz = zx = 0 enforced.
//   PlaneStress  : not supported (sigma_zz = 0 would need a local iteration): plastic_check
//                  refuses it; the kernel treats it as PlaneStrain if called anyway.
//
// State layout (kPlasticStateSize doubles; all zeros = virgin material at troom):
//   [0..5]   eps_p    plastic strain, Voigt with engineering shear (trace 0)
//   [6]      eps_bar  equivalent plastic strain (accumulated dgamma)
//   [7]      dT       temperature rise above troom (T = troom + dT)
//   [8]      W_p      plastic work (dissipated energy) per unit volume
//   [9]      E        internal energy per unit reference volume (volumetric work + W_p; EOS)
//   [10]     rate     equivalent total deviatoric strain rate used by the last call
//   [11]     rate_p   equivalent plastic strain rate dgamma / dt of the last call (0 if dt <= 0)
//   [12..17] eps_prev strain of the previous call, as used (after the mode's constraints)
//   [18..23] sig_prev stress of the previous call

enum class YieldModel : std::uint8_t { J2, JohnsonCook, ZerilliArmstrong };

// Flow-stress constants; see the model notes for which keyword fills which field.
struct PlasticParams {
  YieldModel model = YieldModel::J2;
  double a = 0, b = 0, n = 1;    // athermal part a + b eps^n (JC: times the rate and T factors)
  double c = 0, m = 1;           // Johnson-Cook rate and thermal-softening constants
  bool fcc = false;              // Zerilli-Armstrong crystal form
  double c1 = 0, c3 = 0, c4 = 0; // Zerilli-Armstrong thermally activated part
  double eps0 = 1;               // reference strain rate (1/s in the run's time unit)
  double tmelt = 0;              // JC melting temperature (0: no thermal softening)
  double troom = 293;            // room / initial temperature (K)
  double cp = 0;                 // specific heat (0: no adiabatic heating)
};

// Everything one point needs: elastic constants, density (heating, EOS), flow stress, EOS.
struct J2Params {
  double E = 0, nu = 0, rho = 0;
  PlasticParams plastic;
  EosParams eos;
  // eps is the logarithmic strain ln U of the corotational kernels and sigma the (rotated)
  // Kirchhoff stress conjugate to it (see the notes): the EOS then sees the true relative volume.
  bool log_strain = false;
};

constexpr int kPlasticStateSize = 24;
constexpr double kTaylorQuinney = 0.9;

// Stress update. eps: small strain (ln U with log_strain), Voigt, engineering shear. dt: time
// since the previous call (<= 0: none, see the notes). state: kPlasticStateSize doubles, updated
// in place. sigma: Cauchy stress (Kirchhoff with log_strain), Voigt (out). Returns the
// recoverable energy density per unit reference volume (see the notes).
double plastic_stress(const J2Params& p, StressMode mode, const double eps[6], double dt,
                      double* state, double sigma[6]);

// Flow stress sigma_y at equivalent plastic strain eps_bar, rate and absolute temperature T, and
// its slope d sigma_y / d eps_bar (infinite at eps_bar = 0 for exponents below 1).
double flow_stress(const PlasticParams& p, double eps_bar, double rate, double T);
double flow_stress_slope(const PlasticParams& p, double eps_bar, double rate, double T);

double plastic_equivalent_strain(const double* state);
double plastic_temperature(const PlasticParams& p, const double* state); // absolute T
double plastic_dissipated(const double* state); // plastic work per unit volume
double plastic_internal_energy(const double* state);
const double* plastic_strain(const double* state); // Voigt, engineering shear

// Empty when valid, else the reason naming the constant: signs of the flow-stress constants,
// positive initial yield, tmelt > troom with cp > 0.
const char* plastic_params_check(const PlasticParams& p);
// Empty when valid, else the reason naming the parameter: E > 0, nu in (-1, 0.5), rho > 0, the
// flow-stress constants (signs, positive initial yield, tmelt > troom with cp), the EOS, and no
// PlaneStress mode.
const char* plastic_check(const J2Params& p, StressMode mode);

} // namespace fracdem
