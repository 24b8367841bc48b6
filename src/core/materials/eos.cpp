// Linear and Mie-Grueneisen pressure, and the energy-consistent pressure step.
#include "materials/eos.h"

#include <algorithm>
#include <cmath>

namespace fracdem
{

double eos_compression(const EosParams& e, double theta)
{
  const double J = std::max(1.0 + theta, 0.1);
  double mu = 1.0 / J - 1.0;
  if (e.s > 1) mu = std::min(mu, 0.9 / (e.s - 1));
  return mu;
}

double eos_reference_pressure(const EosParams& e, double K, double rho0, double theta)
{
  if (e.model == EosModel::Linear) return -K * theta;
  const double mu = eos_compression(e, theta);
  const double rc2 = rho0 * e.c0 * e.c0;
  if (!(mu > 0)) return rc2 * mu;
  const double den = 1 - (e.s - 1) * mu;
  return rc2 * mu * (1 + (1 - 0.5 * e.gamma0) * mu) / (den * den);
}

double eos_pressure(const EosParams& e, double K, double rho0, double theta, double E)
{
  const double g = e.model == EosModel::MieGruneisen ? e.gamma0 : 0.0;
  return eos_reference_pressure(e, K, rho0, theta) + g * E;
}

double eos_step(const EosParams& e, double K, double rho0, double theta_old, double theta_new,
                double p_old, double dissipated, double& E, double* volumetric_work)
{
  const double g = e.model == EosModel::MieGruneisen ? e.gamma0 : 0.0;
  const double dth = theta_new - theta_old;
  // p = p_ref + g (E_old + D + dW), dW = -(p_old + p) dth / 2: linear in p, solved exactly.
  // 1 + g dth / 2 > 0 for any step that keeps J > 0 with Gamma0 < 4 (all metals); guarded anyway.
  const double den = std::max(1 + 0.5 * g * dth, 1e-3);
  const double p = (eos_reference_pressure(e, K, rho0, theta_new) + g * (E + dissipated) -
                    0.5 * g * p_old * dth) /
                   den;
  const double dW = -0.5 * (p_old + p) * dth;
  E += dissipated + dW;
  if (volumetric_work) *volumetric_work = dW;
  return p;
}

const char* eos_check(const EosParams& e)
{
  if (e.model == EosModel::Linear) return "";
  if (!(e.c0 > 0) || !std::isfinite(e.c0)) return "C0 (bulk sound speed) must be > 0";
  if (!(e.s >= 0) || !std::isfinite(e.s)) return "S (Hugoniot slope) must be >= 0";
  if (!(e.gamma0 >= 0) || !std::isfinite(e.gamma0)) return "GAMMA0 must be >= 0";
  return "";
}

} // namespace fracdem
