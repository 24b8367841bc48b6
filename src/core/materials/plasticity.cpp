// J2 radial return with Johnson-Cook / Zerilli-Armstrong / power-law flow stresses, heating, EOS.
#include "materials/plasticity.h"

#include <algorithm>
#include <cmath>

namespace fracdem
{

namespace
{

// State slots (see plasticity.h).
constexpr int kEpsP = 0;
constexpr int kEpsBar = 6;
constexpr int kTempRise = 7;
constexpr int kWork = 8;
constexpr int kEnergy = 9;
constexpr int kRate = 10;
constexpr int kRateP = 11;
constexpr int kEpsPrev = 12;
constexpr int kSigPrev = 18;
constexpr double kZaRateFloor = 1e-6;

// s:s of a symmetric Voigt tensor stored with TENSOR shear (shear terms count twice).
inline double dev_dot(const double s[6])
{
  return s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
}

// Stored deviatoric energy s:s / (4 mu) plus the volumetric work kept in the state.
inline double stored_energy(const double sigma[6], double mu, const double* st)
{
  const double p = -(sigma[0] + sigma[1] + sigma[2]) / 3.0;
  const double s[6] = {sigma[0] + p, sigma[1] + p, sigma[2] + p, sigma[3], sigma[4], sigma[5]};
  return dev_dot(s) / (4 * mu) + (st[kEnergy] - st[kWork]);
}

// Equivalent deviatoric strain rate of the step from the strain increment (engineering shear).
double strain_rate(const double e[6], const double* prev, double dt)
{
  double d[6];
  for (int k = 0; k < 6; ++k)
    d[k] = e[k] - prev[k];
  const double tr = (d[0] + d[1] + d[2]) / 3.0;
  const double n =
      (d[0] - tr) * (d[0] - tr) + (d[1] - tr) * (d[1] - tr) + (d[2] - tr) * (d[2] - tr);
  const double sh = 0.5 * (d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
  return std::sqrt(2.0 / 3.0 * (n + sh)) / dt;
}

// Multiplier and additive thermally activated term of the flow stress at (rate, T):
// sigma_y = scale (a + b eps^n) + act g(eps), g = 1 or sqrt(eps) (fcc).
void rate_temperature_terms(const PlasticParams& p, double rate, double T, double& scale,
                            double& act)
{
  scale = 1;
  act = 0;
  if (p.model == YieldModel::JohnsonCook) {
    scale = 1 + p.c * std::log(std::max(rate / p.eps0, 1.0));
    if (p.tmelt > p.troom) {
      const double ts = std::min(1.0, std::max(0.0, (T - p.troom) / (p.tmelt - p.troom)));
      scale *= 1 - std::pow(ts, p.m);
    }
  } else if (p.model == YieldModel::ZerilliArmstrong) {
    const double lr = std::log(std::max(rate / p.eps0, kZaRateFloor));
    act = p.c1 * std::exp(-p.c3 * T + p.c4 * T * lr);
  }
}

// Solves q_tr - 3 mu x - sigma_y(eps_bar + x) = 0 for x in [0, q_tr / (3 mu)] (g decreasing).
double return_increment(const PlasticParams& p, double mu3, double q_tr, double eps_bar,
                        double rate, double T)
{
  double lo = 0, hi = q_tr / mu3, x = 0;
  for (int it = 0; it < 200; ++it) {
    const double g = q_tr - mu3 * x - flow_stress(p, eps_bar + x, rate, T);
    if (g > 0)
      lo = x;
    else
      hi = x;
    if (std::fabs(g) <= 1e-14 * q_tr || hi - lo <= 1e-15 * hi) break;
    const double dg = -mu3 - flow_stress_slope(p, eps_bar + x, rate, T);
    double xn = x - g / dg;
    if (!(xn > lo && xn < hi)) xn = 0.5 * (lo + hi); // Newton left the bracket (or slope = inf)
    x = xn;
  }
  return x;
}

// Pressure and stress of the step; the deviator s (tensor shear) is known.
void finish_stress(const J2Params& p, const double e[6], const double s[6], double dwp, double* st,
                   double sigma[6])
{
  const double K = p.E / (3 * (1 - 2 * p.nu));
  const double th_old = st[kEpsPrev] + st[kEpsPrev + 1] + st[kEpsPrev + 2];
  const double p_old = -(st[kSigPrev] + st[kSigPrev + 1] + st[kSigPrev + 2]) / 3.0;
  const double th = e[0] + e[1] + e[2];
  double pr;
  if (p.log_strain) { // theta = ln J, stored stress Kirchhoff: the EOS works in J - 1 and Cauchy p
    const double J_old = std::exp(th_old), J = std::exp(th);
    pr = J * eos_step(p.eos, K, p.rho, J_old - 1, J - 1, p_old / J_old, dwp, st[kEnergy]);
  } else {
    pr = eos_step(p.eos, K, p.rho, th_old, th, p_old, dwp, st[kEnergy]);
  }
  for (int k = 0; k < 3; ++k)
    sigma[k] = s[k] - pr;
  for (int k = 3; k < 6; ++k)
    sigma[k] = s[k];
}

} // namespace

double flow_stress(const PlasticParams& p, double eps_bar, double rate, double T)
{
  double scale, act;
  rate_temperature_terms(p, rate, T, scale, act);
  double y = scale * (p.a + p.b * std::pow(eps_bar, p.n));
  if (p.model == YieldModel::ZerilliArmstrong) y += act * (p.fcc ? std::sqrt(eps_bar) : 1.0);
  return std::max(y, 0.0);
}

double flow_stress_slope(const PlasticParams& p, double eps_bar, double rate, double T)
{
  double scale, act;
  rate_temperature_terms(p, rate, T, scale, act);
  double d = scale * p.b * p.n * std::pow(eps_bar, p.n - 1); // n = 1: pow(0, 0) = 1
  if (p.model == YieldModel::ZerilliArmstrong && p.fcc)
    d += act > 0 ? 0.5 * act / std::sqrt(eps_bar) : 0.0;
  return d;
}

double plastic_stress(const J2Params& p, StressMode mode, const double eps_in[6], double dt,
                      double* st, double sigma[6])
{
  const double mu = p.E / (2 * (1 + p.nu));
  double e[6];
  std::copy(eps_in, eps_in + 6, e);
  if (mode != StressMode::Solid) e[4] = e[5] = 0;
  if (std::equal(e, e + 6, st + kEpsPrev)) { // nothing moved: the stored answer, no history
    std::copy(st + kSigPrev, st + kSigPrev + 6, sigma);
    return stored_energy(sigma, mu, st);
  }
  // Trial deviator (tensor shear) from the elastic strain e - eps_p.
  const double th = (e[0] + e[1] + e[2]) / 3.0;
  double s[6];
  for (int k = 0; k < 3; ++k)
    s[k] = 2 * mu * (e[k] - st[kEpsP + k] - th);
  for (int k = 3; k < 6; ++k)
    s[k] = mu * (e[k] - st[kEpsP + k]);
  const double rate = dt > 0 ? strain_rate(e, st + kEpsPrev, dt) : st[kRate];
  const double T = p.plastic.troom + st[kTempRise];
  const double q_tr = std::sqrt(1.5 * dev_dot(s));
  double dwp = 0, dgamma = 0;
  if (q_tr > flow_stress(p.plastic, st[kEpsBar], rate, T)) {
    dgamma = return_increment(p.plastic, 3 * mu, q_tr, st[kEpsBar], rate, T);
    const double f = 1.5 * dgamma / q_tr; // d eps_p = f s_tr (tensor components)
    for (int k = 0; k < 3; ++k)
      st[kEpsP + k] += f * s[k];
    for (int k = 3; k < 6; ++k)
      st[kEpsP + k] += 2 * f * s[k]; // engineering shear
    const double shrink = 1 - 3 * mu * dgamma / q_tr;
    for (int k = 0; k < 6; ++k)
      s[k] *= shrink;
    st[kEpsBar] += dgamma;
    dwp = flow_stress(p.plastic, st[kEpsBar], rate, T) * dgamma;
    st[kWork] += dwp;
    if (p.plastic.cp > 0 && p.rho > 0)
      st[kTempRise] += kTaylorQuinney * dwp / (p.rho * p.plastic.cp);
  }
  finish_stress(p, e, s, dwp, st, sigma);
  st[kRate] = rate;
  if (dt > 0) st[kRateP] = dgamma / dt;
  std::copy(e, e + 6, st + kEpsPrev);
  std::copy(sigma, sigma + 6, st + kSigPrev);
  return stored_energy(sigma, mu, st);
}

double plastic_equivalent_strain(const double* state)
{
  return state[kEpsBar];
}
double plastic_temperature(const PlasticParams& p, const double* state)
{
  return p.troom + state[kTempRise];
}
double plastic_dissipated(const double* state)
{
  return state[kWork];
}
double plastic_internal_energy(const double* state)
{
  return state[kEnergy];
}
const double* plastic_strain(const double* state)
{
  return state + kEpsP;
}

const char* plastic_params_check(const PlasticParams& f)
{
  auto bad = [](double v) { return !std::isfinite(v); };
  if (bad(f.a) || bad(f.b) || bad(f.n) || bad(f.c) || bad(f.m) || bad(f.c1) || bad(f.c3) ||
      bad(f.c4) || bad(f.eps0) || bad(f.tmelt) || bad(f.troom) || bad(f.cp))
    return "constants must be finite numbers";
  if (f.model == YieldModel::J2) {
    if (!(f.a > 0)) return "yield SY must be > 0";
    if (!(f.b >= 0)) return "hardening H must be >= 0";
    if (!(f.n > 0)) return "exponent N must be > 0";
    return "";
  }
  if (!(f.n > 0)) return "hardening exponent N must be > 0";
  if (!(f.eps0 > 0)) return "eps0 (reference strain rate) must be > 0";
  if (!(f.troom > 0)) return "troom must be > 0 (absolute temperature)";
  if (!(f.cp >= 0)) return "cp (specific heat) must not be negative";
  if (f.model == YieldModel::JohnsonCook) {
    if (!(f.a > 0)) return "A (initial yield stress) must be > 0";
    if (!(f.b >= 0)) return "B must be >= 0";
    if (!(f.c >= 0)) return "C (rate constant) must be >= 0";
    if (!(f.m > 0)) return "M (thermal-softening exponent) must be > 0";
    if (f.tmelt != 0 && !(f.tmelt > f.troom)) return "tmelt must exceed troom";
    if (f.tmelt != 0 && !(f.cp > 0)) return "tmelt needs cp > 0 (the heating that softens)";
    return "";
  }
  if (!(f.a >= 0)) return "C0 must be >= 0";
  if (!(f.c1 >= 0)) return "C1 must be >= 0";
  if (!(f.c3 >= 0)) return "C3 must be >= 0";
  if (!(f.c4 >= 0)) return "C4 must be >= 0";
  if (!(f.b >= 0)) return "C5 must be >= 0";
  if (!(f.a > 0 || (!f.fcc && f.c1 > 0)))
    return f.fcc ? "C0 (initial yield stress of the fcc form) must be > 0"
                 : "C0 + C1 (initial yield stress) must be > 0";
  return "";
}

const char* plastic_check(const J2Params& p, StressMode mode)
{
  if (!(p.E > 0)) return "E (young) must be > 0";
  if (!(p.nu > -1 && p.nu < 0.5)) return "nu (poisson) must lie in (-1, 0.5)";
  if (!(p.rho > 0)) return "rho (density) must be > 0";
  if (mode == StressMode::PlaneStress)
    return "plasticity and equations of state need plane strain, axisymmetric or 3D (not plane "
           "stress)";
  const char* f = plastic_params_check(p.plastic);
  if (*f) return f;
  return eos_check(p.eos);
}

} // namespace fracdem
