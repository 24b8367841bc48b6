// Unit tests of the J2 plasticity point (radial return, hardening families, rate and temperature
// factors), the equations of state, the material argument parser and the element-kernel hook.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "fem/body.h"
#include "fem/fe_space.h"
#include "io/mesh_generators.h"
#include "materials/eos.h"
#include "materials/material_table.h"
#include "materials/plasticity.h"

using namespace fracdem;

namespace
{

// Steel-like elasticity with linear hardening: E = 200 GPa, nu = 0.3, SY = 300 MPa, H = 2 GPa.
J2Params steel(double H = 2e9, double n = 1.0)
{
  J2Params p;
  p.E = 200e9;
  p.nu = 0.3;
  p.rho = 7800;
  p.plastic.model = YieldModel::J2;
  p.plastic.a = 300e6;
  p.plastic.b = H;
  p.plastic.n = n;
  return p;
}

double shear_modulus(const J2Params& p)
{
  return p.E / (2 * (1 + p.nu));
}
double bulk_modulus(const J2Params& p)
{
  return p.E / (3 * (1 - 2 * p.nu));
}

// Von Mises equivalent stress of a Voigt stress.
double mises(const double s[6])
{
  const double a = s[0] - s[1], b = s[1] - s[2], c = s[2] - s[0];
  return std::sqrt(0.5 * (a * a + b * b + c * c) + 3 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
}

struct Point {
  std::vector<double> state = std::vector<double>(kPlasticStateSize, 0.0);
  double sigma[6] = {0, 0, 0, 0, 0, 0};
  double psi = 0;
  void step(const J2Params& p, const double eps[6], double dt = 0, StressMode m = StressMode::Solid)
  {
    psi = plastic_stress(p, m, eps, dt, state.data(), sigma);
  }
  double eps_bar() const { return plastic_equivalent_strain(state.data()); }
};

// Uniaxial stress: eps_xx prescribed, eps_yy = eps_zz found (secant, on copies of the state) so
// that sigma_yy = sigma_zz = 0, then committed.
void uniaxial_stress_step(const J2Params& p, Point& pt, double exx, double& lat)
{
  auto syy = [&](double e) {
    Point trial = pt;
    const double eps[6] = {exx, e, e, 0, 0, 0};
    trial.step(p, eps);
    return trial.sigma[1];
  };
  const double lam = p.E * p.nu / ((1 + p.nu) * (1 - 2 * p.nu));
  double e0 = lat, f0 = syy(e0);
  double e1 = e0 - f0 / (2 * (lam + shear_modulus(p))), f1 = syy(e1);
  for (int it = 0; it < 60 && std::fabs(f1) > 1e-6 && f1 != f0; ++it) {
    const double e2 = e1 - f1 * (e1 - e0) / (f1 - f0);
    e0 = e1;
    f0 = f1;
    e1 = e2;
    f1 = syy(e1);
  }
  lat = e1;
  const double eps[6] = {exx, lat, lat, 0, 0, 0};
  pt.step(p, eps);
}

} // namespace

// Uniaxial stress, linear hardening: sigma = SY + H eps_p, tangent E_t = E H / (E + H), and the
// lateral strain -nu sigma / E - eps_p / 2 (plastic incompressibility).
TEST(Plasticity, UniaxialStressLinearHardening)
{
  const J2Params p = steel();
  const double E = p.E, H = p.plastic.b, SY = p.plastic.a, Et = E * H / (E + H);
  Point pt;
  double lat = 0;
  for (int k = 1; k <= 40; ++k) {
    const double exx = 0.0002 * k; // up to 0.8 %, yield at 0.15 %
    uniaxial_stress_step(p, pt, exx, lat);
    const double sig = exx <= SY / E ? E * exx : SY + Et * (exx - SY / E);
    const double ep = exx <= SY / E ? 0.0 : (E * exx - SY) / (E + H);
    EXPECT_NEAR(pt.sigma[0], sig, 1e-9 * sig) << "step " << k;
    EXPECT_NEAR(pt.eps_bar(), ep, 1e-12) << "step " << k;
    EXPECT_NEAR(lat, -p.nu * sig / E - 0.5 * ep, 1e-12) << "step " << k;
    if (ep > 0) EXPECT_NEAR(pt.sigma[0], SY + H * ep, 1e-9 * SY);
  }
}

// Uniaxial strain (eps = diag(e, 0, 0)): q = 2 mu (e - 3/2 eps_p) = SY + H eps_p, p = -K e.
TEST(Plasticity, UniaxialStrainLinearHardening)
{
  const J2Params p = steel();
  const double mu = shear_modulus(p), K = bulk_modulus(p), SY = p.plastic.a, H = p.plastic.b;
  Point pt;
  for (int k = 1; k <= 30; ++k) {
    const double e = 0.0003 * k;
    const double eps[6] = {e, 0, 0, 0, 0, 0};
    pt.step(p, eps);
    const double ep = std::max(0.0, (2 * mu * e - SY) / (3 * mu + H));
    const double q = 2 * mu * (e - 1.5 * ep);
    EXPECT_NEAR(pt.eps_bar(), ep, 1e-13);
    EXPECT_NEAR(pt.sigma[0], K * e + 2.0 / 3.0 * q, 1e-9 * std::fabs(pt.sigma[0]));
    EXPECT_NEAR(pt.sigma[1], K * e - q / 3.0, 1e-9 * std::fabs(pt.sigma[0]));
    EXPECT_DOUBLE_EQ(pt.sigma[1], pt.sigma[2]);
  }
}

// Pure shear gamma_xy: tau = mu (gamma - gamma_p), eps_bar = gamma_p / sqrt 3,
// sqrt 3 tau = SY + H eps_bar.
TEST(Plasticity, PureShear)
{
  const J2Params p = steel();
  const double mu = shear_modulus(p), SY = p.plastic.a, H = p.plastic.b, r3 = std::sqrt(3.0);
  Point pt;
  for (int k = 1; k <= 25; ++k) {
    const double g = 0.0004 * k;
    const double eps[6] = {0, 0, 0, g, 0, 0};
    pt.step(p, eps);
    const double ep = std::max(0.0, (r3 * mu * g - SY) / (3 * mu + H));
    const double tau = mu * (g - r3 * ep);
    EXPECT_NEAR(pt.eps_bar(), ep, 1e-13);
    EXPECT_NEAR(pt.sigma[3], tau, 1e-9 * tau);
    EXPECT_NEAR(plastic_strain(pt.state.data())[3], r3 * ep, 1e-13); // engineering shear
    EXPECT_NEAR(pt.sigma[0], 0.0, 1e-6);
  }
}

// After a return the stress lies on the yield surface, the plastic strain increment is normal to
// it (parallel to the deviator) and traceless.
TEST(Plasticity, RadialReturnConsistency)
{
  const J2Params p = steel(5e9);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.004, 0.004);
  Point pt;
  double eps[6] = {0, 0, 0, 0, 0, 0};
  int plastic_steps = 0;
  for (int k = 0; k < 200; ++k) {
    const double ep_old[6] = {pt.state[0], pt.state[1], pt.state[2],
                              pt.state[3], pt.state[4], pt.state[5]};
    const double bar_old = pt.eps_bar();
    for (double& e : eps)
      e += 0.25 * u(rng);
    pt.step(p, eps);
    const double q = mises(pt.sigma);
    const double sy = flow_stress(p.plastic, pt.eps_bar(), 0, 293);
    const double dgamma = pt.eps_bar() - bar_old;
    EXPECT_LE(q, sy * (1 + 1e-12));
    if (!(dgamma > 0)) continue;
    ++plastic_steps;
    EXPECT_NEAR(q, sy, 1e-11 * sy);
    const double pr = -(pt.sigma[0] + pt.sigma[1] + pt.sigma[2]) / 3;
    const double s[6] = {pt.sigma[0] + pr, pt.sigma[1] + pr, pt.sigma[2] + pr,
                         pt.sigma[3],      pt.sigma[4],      pt.sigma[5]};
    double d[6];
    for (int i = 0; i < 6; ++i)
      d[i] = pt.state[i] - ep_old[i];
    EXPECT_NEAR(d[0] + d[1] + d[2], 0.0, 1e-15);
    for (int i = 0; i < 3; ++i) // d eps_p = 3/2 dgamma s / q (tensor; shear doubled)
      EXPECT_NEAR(d[i], 1.5 * dgamma * s[i] / q, 1e-12 * dgamma);
    for (int i = 3; i < 6; ++i)
      EXPECT_NEAR(d[i], 3.0 * dgamma * s[i] / q, 1e-12 * dgamma);
  }
  EXPECT_GT(plastic_steps, 20);
}

// Unloading from a plastic state is elastic: the plastic strain stays, the stress change is
// (K + 4/3 mu) de in uniaxial strain; reloading yields again at the stress reached before.
TEST(Plasticity, ElasticUnloading)
{
  const J2Params p = steel();
  const double mu = shear_modulus(p), K = bulk_modulus(p);
  Point pt;
  const double e_max = 0.006;
  for (int k = 1; k <= 20; ++k) {
    const double eps[6] = {e_max * k / 20, 0, 0, 0, 0, 0};
    pt.step(p, eps);
  }
  const double s_max = pt.sigma[0], ep = pt.eps_bar();
  const std::vector<double> plastic(pt.state.begin(), pt.state.begin() + 6);
  for (int k = 1; k <= 10; ++k) {
    const double de = -0.0001 * k;
    const double eps[6] = {e_max + de, 0, 0, 0, 0, 0};
    pt.step(p, eps);
    EXPECT_NEAR(pt.sigma[0] - s_max, (K + 4.0 / 3.0 * mu) * de, 1e-9 * s_max);
    EXPECT_EQ(pt.eps_bar(), ep);
    for (int i = 0; i < 6; ++i)
      EXPECT_EQ(pt.state[i], plastic[i]);
  }
  const double eps[6] = {e_max, 0, 0, 0, 0, 0};
  pt.step(p, eps);
  EXPECT_NEAR(pt.sigma[0], s_max, 1e-9 * s_max);
  EXPECT_NEAR(pt.eps_bar(), ep, 1e-15); // back on the surface where it left it
}

// Power-law hardening sigma_y = SY + H eps^N (N = 0.4, infinite slope at 0): the flow stress
// formula and uniaxial strain, whose closed form 2 mu (e - 3/2 eps_p) = SY + H eps_p^N is solved
// here by bisection.
TEST(Plasticity, PowerLawHardening)
{
  const J2Params p = steel(800e6, 0.4);
  const double mu = shear_modulus(p), SY = p.plastic.a, H = p.plastic.b;
  EXPECT_DOUBLE_EQ(flow_stress(p.plastic, 0.0, 0, 293), SY);
  EXPECT_NEAR(flow_stress(p.plastic, 0.05, 0, 293), SY + H * std::pow(0.05, 0.4), 1e-3);
  Point pt;
  for (int k = 1; k <= 20; ++k) {
    const double e = 0.0005 * k;
    const double eps[6] = {e, 0, 0, 0, 0, 0};
    pt.step(p, eps);
    double lo = 0, hi = e / 1.5;
    if (2 * mu * e <= SY) hi = 0;
    for (int it = 0; it < 200 && hi > 0; ++it) {
      const double mid = 0.5 * (lo + hi);
      (2 * mu * (e - 1.5 * mid) > SY + H * std::pow(mid, 0.4) ? lo : hi) = mid;
    }
    EXPECT_NEAR(pt.eps_bar(), hi, 1e-14 + 1e-10 * hi) << "step " << k;
    if (pt.eps_bar() > 0)
      EXPECT_NEAR(mises(pt.sigma), flow_stress(p.plastic, pt.eps_bar(), 0, 293), 1e-3);
  }
}

// Johnson-Cook: (A + B eps^N)(1 + C ln(max(rate / eps0, 1)))(1 - T*^M); constants of 4340 steel
// (Johnson & Cook 1985). Hand values from the formula.
J2Params johnson_cook(bool thermal)
{
  J2Params p;
  p.E = 200e9;
  p.nu = 0.29;
  p.rho = 7830;
  p.plastic.model = YieldModel::JohnsonCook;
  p.plastic.a = 792e6;
  p.plastic.b = 510e6;
  p.plastic.n = 0.26;
  p.plastic.c = 0.014;
  p.plastic.m = 1.03;
  if (thermal) {
    p.plastic.tmelt = 1793;
    p.plastic.troom = 293;
    p.plastic.cp = 477;
  }
  return p;
}

TEST(Plasticity, JohnsonCookRateAndTemperature)
{
  const J2Params p = johnson_cook(true);
  const PlasticParams& f = p.plastic;
  const double base = 792e6 + 510e6 * std::pow(0.1, 0.26);
  // Rate: no effect up to eps0, then 1 + C ln(rate); 1.1759631464497244e9 by hand at 1000/s.
  EXPECT_DOUBLE_EQ(flow_stress(f, 0.1, 0.5, 293), base);
  EXPECT_DOUBLE_EQ(flow_stress(f, 0.1, 1.0, 293), base);
  EXPECT_NEAR(flow_stress(f, 0.1, 1000.0, 293), 1175963146.4497244, 1.0);
  EXPECT_NEAR(flow_stress(f, 0.1, 1000.0, 293) / base, 1 + 0.014 * std::log(1000.0), 1e-14);
  // Temperature: halfway to melting, factor 1 - 0.5^1.03 (5.471663788394628e8 by hand); melt: 0;
  // below room temperature: clamped to no softening.
  EXPECT_NEAR(flow_stress(f, 0.1, 1.0, 0.5 * (293 + 1793)), 547166378.8394628, 1.0);
  EXPECT_EQ(flow_stress(f, 0.1, 1.0, 1793), 0.0);
  EXPECT_EQ(flow_stress(f, 0.1, 1.0, 2500), 0.0);
  EXPECT_DOUBLE_EQ(flow_stress(f, 0.1, 1.0, 200), base);
  // Without tmelt no thermal softening.
  EXPECT_DOUBLE_EQ(flow_stress(johnson_cook(false).plastic, 0.1, 1.0, 1500), base);
}

// Driven in shear at a constant rate: the rate the point measures is gamma_dot / sqrt 3, the
// stress sits on the rate-scaled curve, and the temperature rise is 0.9 W_p / (rho cp).
TEST(Plasticity, JohnsonCookPointRateAndHeating)
{
  const J2Params p = johnson_cook(true);
  const double rates[2] = {1e2, 1e4};
  double final_tau[2];
  for (int r = 0; r < 2; ++r) {
    Point pt;
    const double dg = 2e-4, dt = dg / (std::sqrt(3.0) * rates[r]);
    for (int k = 1; k <= 100; ++k) {
      const double eps[6] = {0, 0, 0, dg * k, 0, 0};
      pt.step(p, eps, dt);
    }
    EXPECT_NEAR(pt.state[10], rates[r], 1e-6 * rates[r]); // measured equivalent rate
    const double T = plastic_temperature(p.plastic, pt.state.data());
    EXPECT_NEAR(T - 293, 0.9 * plastic_dissipated(pt.state.data()) / (7830 * 477), 1e-9);
    EXPECT_GT(T, 293.5);
    // On the yield surface of the step's start temperature (frozen over the step).
    const double q = mises(pt.sigma);
    EXPECT_LT(std::fabs(q - flow_stress(p.plastic, pt.eps_bar(), rates[r], T)) / q, 1e-3);
    final_tau[r] = pt.sigma[3];
  }
  // Two decades of rate: ratio (1 + C ln 1e4) / (1 + C ln 1e2) up to the small thermal difference.
  const double expect = (1 + 0.014 * std::log(1e4)) / (1 + 0.014 * std::log(1e2));
  EXPECT_NEAR(final_tau[1] / final_tau[0], expect, 2e-3);
}

// Zerilli-Armstrong with the 1987 constants of Armco iron (bcc) and OFHC copper (fcc), hand values
// from the formulas at (T, rate) = (300 K, 1e3/s) and (600 K, 1/s).
TEST(Plasticity, ZerilliArmstrongBccFcc)
{
  PlasticParams bcc;
  bcc.model = YieldModel::ZerilliArmstrong;
  bcc.a = 70e6;    // C0
  bcc.c1 = 1033e6; // C1
  bcc.c3 = 0.00698;
  bcc.c4 = 0.000415;
  bcc.b = 266e6; // C5
  bcc.n = 0.289;
  EXPECT_NEAR(flow_stress(bcc, 0.1, 1e3, 300), 507473174.5123914, 1.0);
  EXPECT_NEAR(flow_stress(bcc, 0.1, 1.0, 600), 222413047.1324271, 1.0);
  PlasticParams fcc;
  fcc.model = YieldModel::ZerilliArmstrong;
  fcc.fcc = true;
  fcc.a = 65e6;   // C0
  fcc.c1 = 890e6; // C2 of the fcc form
  fcc.c3 = 0.0028;
  fcc.c4 = 0.000115;
  fcc.b = 0; // no athermal power term
  fcc.n = 1;
  EXPECT_NEAR(flow_stress(fcc, 0.2, 1e3, 300), 283070861.698627, 1.0);
  EXPECT_NEAR(flow_stress(fcc, 0.2, 1.0, 600), 139180588.5796647, 1.0);
  EXPECT_DOUBLE_EQ(flow_stress(fcc, 0.0, 1e3, 300), 65e6); // fcc: no thermal term at eps = 0
  // A point of each: the return lands on the surface of its own flow stress (fcc: infinite slope
  // at eps_p = 0, bisection path).
  for (const PlasticParams& f : {bcc, fcc}) {
    J2Params p;
    p.E = 200e9;
    p.nu = 0.3;
    p.rho = 7800;
    p.plastic = f;
    p.plastic.troom = 300;
    Point pt;
    for (int k = 1; k <= 40; ++k) {
      const double eps[6] = {0, 0, 0, 2.5e-4 * k, 0, 0};
      pt.step(p, eps, 2.5e-4 / (std::sqrt(3.0) * 1e3));
    }
    const double sy = flow_stress(p.plastic, pt.eps_bar(), 1e3, 300);
    EXPECT_GT(pt.eps_bar(), 0.0);
    EXPECT_NEAR(mises(pt.sigma), sy, 1e-9 * sy);
  }
}

// Mie-Grueneisen (copper: rho0 8930, C0 3940, S 1.49, Gamma0 2.02) against the formula, by hand
// at three compressions, with and without internal energy, and in tension.
TEST(Plasticity, MieGruneisenPressure)
{
  EosParams e;
  e.model = EosModel::MieGruneisen;
  e.c0 = 3940;
  e.s = 1.49;
  e.gamma0 = 2.02;
  const double rho0 = 8930, K = 140e9;
  const double th[3] = {-0.01, -0.05, -0.1};
  const double p_hand[3] = {1414081982.1801124, 7683445759.662077, 17208557769.45904};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(eos_pressure(e, K, rho0, th[i], 0.0), p_hand[i], 1e-6 * 1e3);
    EXPECT_NEAR(eos_pressure(e, K, rho0, th[i], 1e8), p_hand[i] + 2.02e8, 1e-3);
    const double mu = 1 / (1 + th[i]) - 1;
    EXPECT_NEAR(eos_compression(e, th[i]), mu, 1e-15);
  }
  EXPECT_NEAR(eos_pressure(e, K, rho0, 0.01, 0.0), -1372532158.4158428, 1e-3);
  // Linear: p = -K theta; the trapezoidal energy telescopes to 0.5 K theta^2.
  EosParams lin;
  double E = 0, p_old = 0, th_old = 0;
  for (int k = 1; k <= 50; ++k) {
    const double t = -0.001 * k + 0.0004 * (k % 3);
    p_old = eos_step(lin, K, rho0, th_old, t, p_old, 0.0, E);
    th_old = t;
    EXPECT_DOUBLE_EQ(p_old, -K * t);
  }
  EXPECT_NEAR(E, 0.5 * K * th_old * th_old, 1e-9 * E);
  // Mie-Grueneisen step: the pressure returned is the EOS at the new energy (consistent update).
  double Em = 0;
  const double pm = eos_step(e, K, rho0, 0.0, -0.02, 0.0, 5e6, Em);
  EXPECT_NEAR(pm, eos_pressure(e, K, rho0, -0.02, Em), 1e-6 * pm);
  EXPECT_NEAR(Em, 5e6 + 0.5 * pm * 0.02, 1e-6 * Em);
}

// A plastic point with the Mie-Grueneisen EOS: the mean stress is -p(theta, E) and the deviator
// follows the J2 return as with the linear EOS.
TEST(Plasticity, PlasticPointWithMieGruneisen)
{
  J2Params lin = steel(), mg = steel();
  mg.rho = 8930;
  mg.eos.model = EosModel::MieGruneisen;
  mg.eos.c0 = 3940;
  mg.eos.s = 1.49;
  mg.eos.gamma0 = 2.02;
  Point a, b;
  for (int k = 1; k <= 20; ++k) {
    const double eps[6] = {-0.002 * k, -0.0005 * k, 0, 0.001 * k, 0, 0};
    a.step(lin, eps);
    b.step(mg, eps);
  }
  const double pa = -(a.sigma[0] + a.sigma[1] + a.sigma[2]) / 3;
  const double pb = -(b.sigma[0] + b.sigma[1] + b.sigma[2]) / 3;
  const double theta = -0.05;
  EXPECT_NEAR(pa, -bulk_modulus(lin) * theta, 1e-6 * pa);
  EXPECT_NEAR(pb, eos_pressure(mg.eos, 0, 8930, theta, plastic_internal_energy(b.state.data())),
              1e-9 * pb);
  EXPECT_EQ(a.eps_bar(), b.eps_bar()); // the deviatoric update does not see the pressure
  for (int i = 0; i < 6; ++i)
    EXPECT_NEAR(a.sigma[i] + (i < 3 ? pa : 0), b.sigma[i] + (i < 3 ? pb : 0), 1e-3);
}

// Dissipation: W_p is the sum of s : d eps_p over the steps (checked step by step along a cyclic
// path) and matches SY eps_p + H eps_p^2 / 2 in monotonic uniaxial strain (small steps).
TEST(Plasticity, DissipationIsPlasticWork)
{
  const J2Params p = steel();
  Point pt;
  double sum = 0;
  for (int k = 1; k <= 400; ++k) {
    const double t = 0.05 * k;
    const double eps[6] = {
        0.004 * std::sin(t), -0.001 * std::sin(t), 0.0, 0.003 * std::sin(0.7 * t), 0.0,
        0.001 * std::cos(t)};
    const std::vector<double> before(pt.state.begin(), pt.state.begin() + 6);
    pt.step(p, eps);
    for (int i = 0; i < 6; ++i) // sigma : d eps_p with engineering shear in eps_p
      sum += pt.sigma[i] * (pt.state[i] - before[i]);
    EXPECT_NEAR(plastic_dissipated(pt.state.data()), sum, 1e-9 * sum + 1e-9);
  }
  EXPECT_GT(sum, 0.0);
  Material mat;
  mat.model = MaterialModel::J2;
  EXPECT_EQ(point_dissipation(mat, pt.state.data()), plastic_dissipated(pt.state.data()));

  Point mono;
  const double SY = p.plastic.a, H = p.plastic.b;
  for (int k = 1; k <= 2000; ++k) {
    const double eps[6] = {1e-5 * k, 0, 0, 0, 0, 0};
    mono.step(p, eps);
  }
  const double ep = mono.eps_bar();
  EXPECT_NEAR(plastic_dissipated(mono.state.data()), SY * ep + 0.5 * H * ep * ep, 1e-3 * SY * ep);
}

// Same input, same bits; a repeated call with an unchanged strain changes nothing.
TEST(Plasticity, DeterministicAndIdempotent)
{
  J2Params p = johnson_cook(true);
  p.eos.model = EosModel::MieGruneisen;
  p.eos.c0 = 4570;
  p.eos.s = 1.49;
  p.eos.gamma0 = 1.93;
  auto run = [&](Point& pt, bool repeat) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1e-3, 1e-3);
    double eps[6] = {0, 0, 0, 0, 0, 0};
    for (int k = 0; k < 300; ++k) {
      for (double& e : eps)
        e += u(rng) + (k < 150 ? 2e-4 : -2e-4);
      pt.step(p, eps, 1e-7);
      if (repeat) pt.step(p, eps, 1e-7);
    }
  };
  Point a, b, c;
  run(a, false);
  run(b, false);
  run(c, true);
  EXPECT_GT(a.eps_bar(), 0.01);
  EXPECT_EQ(std::memcmp(a.state.data(), b.state.data(), kPlasticStateSize * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(a.state.data(), c.state.data(), kPlasticStateSize * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(a.sigma, c.sigma, sizeof(a.sigma)), 0);
}

// Parser: every syntax of the table, the errors naming the keyword, open-ended parsing.
TEST(Plasticity, ParseMaterialArguments)
{
  auto parse = [](const std::vector<std::string>& w, Material& m) {
    return parse_material_arguments(w, m);
  };
  Material m;
  EXPECT_EQ(parse({"j2", "yield", "3e8", "hardening", "2e9"}, m), "");
  EXPECT_EQ(m.model, MaterialModel::J2);
  EXPECT_EQ(m.plastic.a, 3e8);
  EXPECT_EQ(m.plastic.b, 2e9);
  EXPECT_EQ(m.plastic.n, 1.0);
  EXPECT_EQ(parse({"j2", "yield", "3e8", "hardening", "8e8", "exponent", "0.4"}, m), "");
  EXPECT_EQ(m.plastic.n, 0.4);
  EXPECT_EQ(parse({"johnson_cook", "792e6", "510e6", "0.26", "0.014", "1.03", "eps0", "1", "tmelt",
                   "1793", "troom", "293", "cp", "477"},
                  m),
            "");
  EXPECT_EQ(m.model, MaterialModel::JohnsonCook);
  EXPECT_EQ(m.plastic.model, YieldModel::JohnsonCook);
  EXPECT_EQ(m.plastic.tmelt, 1793);
  EXPECT_EQ(m.plastic.cp, 477);
  EXPECT_EQ(parse({"zerilli_armstrong", "fcc", "65e6", "890e6", "0.0028", "0.000115", "0", "1",
                   "cp", "383"},
                  m),
            "");
  EXPECT_TRUE(m.plastic.fcc);
  EXPECT_EQ(m.plastic.c1, 890e6);
  EXPECT_EQ(m.plastic.troom, 293);
  EXPECT_EQ(
      parse({"rankine", "strength", "3e6", "fracture_energy", "100", "softening", "exponential"},
            m),
      "");
  EXPECT_EQ(m.model, MaterialModel::Rankine);
  EXPECT_EQ(m.softening, Softening::Exponential);
  EXPECT_EQ(parse({"elastic"}, m), "");

  auto has = [](const std::string& err, const char* what) {
    return err.find(what) != std::string::npos;
  };
  std::string err = parse({"johnson_cook", "792e6", "510e6", "0.26"}, m);
  EXPECT_TRUE(has(err, "material johnson_cook")) << err;
  EXPECT_TRUE(has(err, "missing C")) << err;
  err = parse({"johnson_cook", "792e6", "-5", "0.26", "0.014", "1.03"}, m);
  EXPECT_TRUE(has(err, "B must be >= 0")) << err;
  err = parse({"johnson_cook", "792e6", "5e8", "0.26", "0.014", "1.03", "tmelt", "1793"}, m);
  EXPECT_TRUE(has(err, "tmelt needs cp")) << err;
  err = parse({"j2", "yield", "abc", "hardening", "1"}, m);
  EXPECT_TRUE(has(err, "material j2: yield: 'abc' is not a number")) << err;
  err = parse({"j2", "hardening", "1"}, m);
  EXPECT_TRUE(has(err, "yield and hardening are required")) << err;
  err = parse({"zerilli_armstrong", "hcp", "1", "1", "1", "1", "1", "1"}, m);
  EXPECT_TRUE(has(err, "neither bcc nor fcc")) << err;
  err = parse({"j2", "yield", "3e8", "hardening", "1", "bogus", "2"}, m);
  EXPECT_TRUE(has(err, "unknown word 'bogus'")) << err;
  err = parse({"plasticine"}, m);
  EXPECT_TRUE(has(err, "unknown model 'plasticine'")) << err;

  // Open-ended: stops at the first host keyword and says how many words it used.
  std::size_t used = 0;
  EXPECT_EQ(parse_material_arguments({"j2", "yield", "3e8", "hardening", "1e9", "density", "7800"},
                                     m, &used),
            "");
  EXPECT_EQ(used, 5u);
  EXPECT_EQ(parse_eos_arguments({"mie_gruneisen", "3940", "1.49", "2.02", "young", "1"}, m, &used),
            "");
  EXPECT_EQ(used, 4u);
  EXPECT_EQ(m.eos.model, EosModel::MieGruneisen);
  EXPECT_EQ(m.eos.gamma0, 2.02);
  err = parse_eos_arguments({"mie_gruneisen", "-1", "1.49", "2.02"}, m);
  EXPECT_TRUE(has(err, "eos mie_gruneisen: C0")) << err;
  err = parse_eos_arguments({"mie_gruneisen", "3940", "1.49"}, m);
  EXPECT_TRUE(has(err, "missing GAMMA0")) << err;
  EXPECT_EQ(parse_eos_arguments({"linear"}, m), "");
  EXPECT_EQ(m.eos.model, EosModel::Linear);
}

// Set-up: plane stress is refused for plastic models and Mie-Grueneisen, and Mie-Grueneisen needs
// a plastic model; FeSpace::build throws the same.
TEST(Plasticity, SetupErrors)
{
  Material m;
  m.E = 200e9;
  m.nu = 0.3;
  m.rho = 7800;
  ASSERT_EQ(parse_material_arguments({"j2", "yield", "3e8", "hardening", "1e9"}, m), "");
  EXPECT_EQ(material_setup_error(m, 3), "");
  m.plane = PlaneMode::PlaneStress;
  EXPECT_NE(material_setup_error(m, 2).find("plane stress"), std::string::npos);
  EXPECT_EQ(material_setup_error(m, 3), ""); // 3D ignores the 2D plane mode
  const Mesh mesh = make_rect_mesh(2, 2, 1.0, 1.0);
  FeSpace fs;
  EXPECT_THROW(fs.build(mesh, m), std::invalid_argument);
  Material e;
  e.E = 1e9;
  e.nu = 0.2;
  e.rho = 1000;
  ASSERT_EQ(parse_eos_arguments({"mie_gruneisen", "3940", "1.49", "2.02"}, e), "");
  EXPECT_NE(material_setup_error(e, 3).find("eos mie_gruneisen"), std::string::npos);
  m.rho = 0;
  m.plane = PlaneMode::PlaneStrain;
  EXPECT_NE(material_setup_error(m, 2).find("rho"), std::string::npos);
}

// The element-kernel hook: a tet mesh under homogeneous uniaxial strain gives every element the
// point's stress, state advances once per evaluation, and element_stress does not advance it.
TEST(Plasticity, ElementKernelHook)
{
  Material m;
  m.E = 200e9;
  m.nu = 0.3;
  m.rho = 7800;
  ASSERT_EQ(parse_material_arguments({"j2", "yield", "3e8", "hardening", "2e9"}, m), "");
  for (ElemType t : {ElemType::Tet4, ElemType::Quad4}) {
    const Mesh mesh = t == ElemType::Tet4 ? make_box_tet_mesh(2, 1, 1, 1.0, 1.0, 1.0)
                                          : make_rect_mesh(2, 2, 1.0, 1.0, {0, 0}, t);
    FeSpace fs;
    fs.build(mesh, m);
    ASSERT_EQ(fs.state_size(),
              kPlasticStateSize * mesh.num_elems() * points_per_elem(mesh.etype[0]));
    std::vector<double> state(fs.state_size(), 0.0), f(mesh.X.size());
    Point ref;
    for (int k = 1; k <= 10; ++k) {
      const double e = 0.0006 * k;
      std::vector<double> x(mesh.X);
      for (int n = 0; n < mesh.num_nodes(); ++n)
        x[3 * n] += e * mesh.X[3 * n];
      std::fill(f.begin(), f.end(), 0.0);
      fs.add_internal_forces(mesh, x.data(), 0, mesh.num_elems(), f.data(), nullptr, nullptr,
                             state.data(), nullptr, 1e-6);
      const double eps[6] = {e, 0, 0, 0, 0, 0};
      ref.step(m.plasticity(), eps, 1e-6,
               t == ElemType::Tet4 ? StressMode::Solid : StressMode::PlaneStrain);
      const std::vector<double> before(state);
      for (int el = 0; el < mesh.num_elems(); ++el) {
        double s[6];
        fs.element_stress(mesh, x.data(), el, s, state.data());
        for (int i = 0; i < 4; ++i)
          EXPECT_NEAR(s[i], ref.sigma[i], 1e-6 * std::fabs(ref.sigma[0])) << "elem " << el;
      }
      EXPECT_EQ(state, before);
    }
    EXPECT_GT(ref.eps_bar(), 0.0);
    EXPECT_NEAR(plastic_equivalent_strain(state.data()), ref.eps_bar(), 1e-12);
  }
}

// A Johnson-Cook bar (tet4) pulled at one end through the body's explicit update: it yields, the
// step reaches the material as dt (nonzero strain rates), and the work of the constraints equals
// kinetic + strain + dissipated energy.
TEST(Plasticity, BodyEnergyBalance)
{
  Material m;
  m.E = 200e9;
  m.nu = 0.29;
  m.rho = 7830;
  ASSERT_EQ(parse_material_arguments({"johnson_cook", "792e6", "510e6", "0.26", "0.014", "1.03",
                                      "tmelt", "1793", "cp", "477"},
                                     m),
            "");
  Body b;
  b.build(make_box_tet_mesh(8, 2, 2, 0.04, 0.01, 0.01), m, false);
  const double v[3] = {10.0, 0, 0};
  b.set_fixed(b.mesh().node_sets.at("xmin"), 7, 0);
  b.set_prescribed_velocity(b.mesh().node_sets.at("xmax"), v, 2e-5, 1);
  b.impose_velocity_conditions();
  const double dt = 0.5 * b.stable_time_step(), g[3] = {0, 0, 0};
  int inv = -1;
  b.begin_forces();
  b.finish_forces(b.add_internal_forces(&inv), g, dt, false);
  const int steps = static_cast<int>(1.2e-4 / dt); // about 2.5 % elongation
  for (int s = 0; s < steps; ++s) {
    b.advance_time(dt);
    b.half_kick_drift(dt);
    b.begin_forces();
    b.finish_forces(b.add_internal_forces(&inv), g, dt, true);
    b.half_kick(dt);
  }
  EXPECT_EQ(inv, -1);
  const double work = b.boundary_work();
  const double sum = b.kinetic_energy() + b.strain_energy() + b.dissipated_energy();
  EXPECT_GT(b.dissipated_energy(), 0.5 * work); // mostly plastic by now
  EXPECT_NEAR(sum, work, 0.01 * work);
  double rate = 0;
  for (int e = 0; e < b.mesh().num_elems(); ++e)
    rate = std::max(rate, b.material_state()[b.space().state_offset(e) + 10]);
  EXPECT_GT(rate, 10.0); // the strain rate was measured (dt reached the material)
}
