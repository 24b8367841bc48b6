// Artificial bulk viscosity: viscous pressure, damping ratio, stable-step factor, checks.
#include "materials/bulk_viscosity.h"

#include <cmath>

namespace fracdem
{

double bulk_viscosity_pressure(const BulkViscosity& bv, double rho, double c, double l, double rate)
{
  if (!(rate < 0)) return 0.0; // expansion (and NaN): no viscosity
  const double d = -rate;
  return rho * l * (bv.q1 * c * d + bv.q2 * bv.q2 * l * d * d);
}

double bulk_viscosity_damping_ratio(const BulkViscosity& bv, double c, double l, double rate)
{
  const double d = rate < 0 ? -rate : 0.0;
  return bv.q1 + bv.q2 * bv.q2 * (l / c) * d;
}

double damped_time_step_factor(double xi)
{
  // sqrt(1 + xi^2) - xi written as 1 / (sqrt(1 + xi^2) + xi): no cancellation for large xi.
  return 1.0 / (std::sqrt(1.0 + xi * xi) + xi);
}

const char* bulk_viscosity_check(const BulkViscosity& bv)
{
  if (!std::isfinite(bv.q1) || bv.q1 < 0) return "Q1 (linear coefficient) must be >= 0";
  if (!std::isfinite(bv.q2) || bv.q2 < 0) return "Q2 (quadratic coefficient) must be >= 0";
  return "";
}

} // namespace fracdem
