// Artificial bulk viscosity of shock problems: the viscous pressure, its damping ratio and the
// reduction of the stable time step it causes.
#pragma once

namespace fracdem
{

// Model (one element at a time; docs/materials.md "Bulk viscosity"):
//
//  * D = tr(rate of deformation) = div v, the element's volumetric strain rate (< 0: compression).
//  * In compression the element carries the extra pressure (Abaqus/Explicit's linear + quadratic
//    bulk viscosity, both terms applied only in compression as in LS-DYNA)
//      q = rho l (Q1 c |D| + Q2^2 l D^2)          (D < 0),      q = 0  (D >= 0),
//    rho the current density, c the dilatational wave speed, l the element's characteristic
//    length. The stress becomes sigma - q I, so the viscous power per unit volume q |D| >= 0.
//  * Damping ratio of the element's highest (dilatational) mode and the stable step it allows
//    (Abaqus Theory Manual, explicit dynamic analysis; the same as LS-DYNA's
//    dt = l / (Q + sqrt(Q^2 + c^2)) with Q = xi c):
//      xi = Q1 + Q2^2 (l / c) max(0, -D),     dt = dt_0 (sqrt(1 + xi^2) - xi).
//    The linear part is counted in expansion too, which is conservative.
// Defaults Q1 = 0.06, Q2 = 1.2 are Abaqus/Explicit's (b1, b2). LS-DYNA names them the other way
// round (its Q1 = 1.5 is the quadratic coefficient, Q2 = 0.06 the linear one).
struct BulkViscosity {
  bool on = false;
  double q1 = 0.06; // linear coefficient
  double q2 = 1.2;  // quadratic coefficient
};

constexpr double kBulkViscosityLinear = 0.06;
constexpr double kBulkViscosityQuadratic = 1.2;

// Viscous pressure q >= 0 (0 in expansion). rho: current density, c: dilatational wave speed,
// l: characteristic length, rate: D = tr(rate of deformation).
double bulk_viscosity_pressure(const BulkViscosity& bv, double rho, double c, double l,
                               double rate);
// Fraction of critical damping of the element's highest mode.
double bulk_viscosity_damping_ratio(const BulkViscosity& bv, double c, double l, double rate);
// Factor sqrt(1 + xi^2) - xi (<= 1) on the undamped stable step for damping ratio xi >= 0.
double damped_time_step_factor(double xi);
// "" when valid, else the reason naming the coefficient (Q1, Q2 finite and >= 0).
const char* bulk_viscosity_check(const BulkViscosity& bv);

} // namespace fracdem
