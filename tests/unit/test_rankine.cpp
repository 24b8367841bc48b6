// Unit tests of the Rankine rotating-crack material point against closed-form values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "materials/rankine.h"

using namespace fracdem;

namespace
{

// Concrete-like constants: kappa0 = 1e-4, snap-back length 2 E gf / ft^2 = 2/3 m.
RankineParams concrete(Softening s = Softening::Linear, double nu = 0.0)
{
  RankineParams p;
  p.E = 30e9;
  p.nu = nu;
  p.ft = 3e6;
  p.gf = 100;
  p.softening = s;
  return p;
}

// 8 nodes of the box [0,lx] x [0,ly] x [0,lz]: extent lx across x, ly across y, lz across z.
std::vector<double> box(double lx, double ly, double lz)
{
  std::vector<double> X;
  for (int k = 0; k < 8; ++k) {
    X.push_back((k & 1) ? lx : 0.0);
    X.push_back((k & 2) ? ly : 0.0);
    X.push_back((k & 4) ? lz : 0.0);
  }
  return X;
}

// The softening laws written out independently of the library (model notes in rankine.h).
double kappa_f(const RankineParams& p, double h)
{
  return 2 * p.gf / (p.ft * h);
}
double kappa_e(const RankineParams& p, double h)
{
  return p.gf / (h * p.ft) - 0.5 * p.ft / p.E;
}
double uniaxial_stress(const RankineParams& p, double h, double e)
{
  const double k0 = p.ft / p.E;
  if (e <= k0) return p.E * e;
  if (p.softening == Softening::Linear) {
    const double kf = kappa_f(p, h);
    return e >= kf ? 0.0 : p.ft * (1 - (e - k0) / (kf - k0));
  }
  return p.ft * std::exp(-(e - k0) / kappa_e(p, h));
}

struct Point {
  std::vector<double> state = std::vector<double>(kRankineStateSize, 0.0);
  double sigma[6] = {0, 0, 0, 0, 0, 0};
  double psi = 0;
  double step(const RankineParams& p, StressMode m, const double eps[6],
              const std::vector<double>& X)
  {
    psi = rankine_stress(p, m, eps, X.data(), int(X.size() / 3), state.data(), sigma);
    return sigma[0];
  }
};

double rel_err(double a, double b)
{
  return std::fabs(a - b) / std::fabs(b);
}

// Strain-driven uniaxial tension eps_xx from 0 to e_max in n steps (nu = 0: uniaxial stress too),
// checking the curve against uniaxial_stress to 1e-9 ft; returns the trapezoidal work.
double drive_uniaxial(const RankineParams& p, double h, double e_max, int n, Point& pt)
{
  const std::vector<double> X = box(h, 2.0, 3.0); // h across x, the crack normal
  double work = 0, e_prev = 0, s_prev = 0;
  for (int i = 1; i <= n; ++i) {
    const double e = e_max * i / n;
    const double eps[6] = {e, 0, 0, 0, 0, 0};
    const double s = pt.step(p, StressMode::Solid, eps, X);
    EXPECT_NEAR(s, uniaxial_stress(p, h, e), 1e-9 * p.ft) << "step " << i << " eps " << e;
    EXPECT_EQ(pt.sigma[1], 0.0); // nu = 0: no lateral stress
    work += 0.5 * (s + s_prev) * (e - e_prev);
    e_prev = e;
    s_prev = s;
  }
  return work;
}

} // namespace

// 1. Uniaxial tension to complete failure: elastic to ft, then the analytic softening curve; the
// trapezoidal work and the kernel's dissipation both equal gf / h (crack band).
TEST(Rankine, UniaxialLinearSofteningFollowsCurveAndDissipatesGfOverH)
{
  const RankineParams p = concrete(Softening::Linear);
  const double h = 0.1, kf = kappa_f(p, h); // kf = 2 gf / (ft h) = 6.67e-4
  Point pt;
  const double work = drive_uniaxial(p, h, 1.2 * kf, 4000, pt);
  EXPECT_LT(rel_err(work, p.gf / h), 0.005);                            // triangle ft kf / 2
  EXPECT_LT(rel_err(rankine_dissipated(pt.state.data()), work), 0.005); // psi = 0 at the end
  EXPECT_EQ(rankine_damage(pt.state.data()), 1.0);                      // f(kappa >= kf) = 0
  EXPECT_TRUE(rankine_cracked(p, pt.state.data()));
  EXPECT_DOUBLE_EQ(rankine_band_width(pt.state.data()), h);
  const double* n = rankine_crack_normal(pt.state.data());
  EXPECT_EQ(n[0], 1.0); // the loading direction, exactly (diagonal trial stress)
  EXPECT_EQ(n[1], 0.0);
  EXPECT_EQ(n[2], 0.0);
}

TEST(Rankine, UniaxialExponentialSofteningFollowsCurveAndDissipatesGfOverH)
{
  const RankineParams p = concrete(Softening::Exponential);
  const double h = 0.1, k0 = p.ft / p.E, ke = kappa_e(p, h);
  // 25 kappa_e past the peak the remaining area ft ke e^-25 is 1e-11 of gf / h.
  Point pt;
  const double work = drive_uniaxial(p, h, k0 + 25 * ke, 5000, pt);
  EXPECT_LT(rel_err(work, p.gf / h), 0.005); // ft k0 / 2 + ft ke = gf / h
  EXPECT_LT(rel_err(rankine_dissipated(pt.state.data()), work), 0.005);
  EXPECT_TRUE(rankine_cracked(p, pt.state.data()));
  EXPECT_GT(rankine_damage(pt.state.data()), 1 - 1e-10); // 1 - f / (E kappa), f = ft e^-25
}

// cracked() switches where the analytic law says: kappa_f (linear), f = 0.01 ft (exponential).
TEST(Rankine, CrackedSwitchesAtTheAnalyticStrain)
{
  const double h = 0.1;
  for (Softening s : {Softening::Linear, Softening::Exponential}) {
    const RankineParams p = concrete(s);
    const double k0 = p.ft / p.E;
    const double kc = s == Softening::Linear ? kappa_f(p, h) : k0 + kappa_e(p, h) * std::log(100.0);
    const std::vector<double> X = box(h, 1, 1);
    for (double f : {0.999, 1.001}) {
      Point pt;
      const double e0[6] = {0.5 * kc, 0, 0, 0, 0, 0}, e1[6] = {f * kc, 0, 0, 0, 0, 0};
      pt.step(p, StressMode::Solid, e0, X);
      pt.step(p, StressMode::Solid, e1, X);
      EXPECT_EQ(rankine_cracked(p, pt.state.data()), f > 1) << int(s) << " " << f;
    }
  }
}

// 2. Crack band: the energy per unit crack AREA, dissipated * h, is gf for any h below snap-back.
TEST(Rankine, DissipationTimesBandWidthIsGfForTwoBandWidths)
{
  for (Softening s : {Softening::Linear, Softening::Exponential}) {
    const RankineParams p = concrete(s);
    for (double h : {0.05, 0.4}) { // snap-back length 2/3
      const double k0 = p.ft / p.E;
      const double e_max = s == Softening::Linear ? 1.1 * kappa_f(p, h) : k0 + 25 * kappa_e(p, h);
      Point pt;
      drive_uniaxial(p, h, e_max, 5000, pt);
      EXPECT_LT(rel_err(rankine_dissipated(pt.state.data()) * h, p.gf), 0.005)
          << "law " << int(s) << " h " << h;
    }
  }
}

// 3. Secant unloading: sigma = (1 - d) E eps with d frozen, zero stress at zero strain, no
// dissipation while unloading or reloading below the previous maximum.
TEST(Rankine, UnloadingIsSecantToTheOrigin)
{
  const RankineParams p = concrete(Softening::Linear);
  const double h = 0.1, k0 = p.ft / p.E, ku = k0 + 0.4 * (kappa_f(p, h) - k0);
  Point pt;
  drive_uniaxial(p, h, ku, 1000, pt);
  const double d = rankine_damage(pt.state.data());
  EXPECT_NEAR(d, 1 - uniaxial_stress(p, h, ku) / (p.E * ku), 1e-12); // d = 1 - f / (E kappa)
  const double D = rankine_dissipated(pt.state.data());
  const std::vector<double> X = box(h, 2, 3);
  for (int pass = 0; pass < 2; ++pass) // unload to 0, then reload to ku
    for (int i = 0; i <= 500; ++i) {
      const double e = pass == 0 ? ku * (500 - i) / 500 : ku * i / 500;
      const double eps[6] = {e, 0, 0, 0, 0, 0};
      const double s = pt.step(p, StressMode::Solid, eps, X);
      EXPECT_EQ(rankine_damage(pt.state.data()), d);
      EXPECT_NEAR(s, (1 - d) * p.E * e, 1e-12 * (1 - d) * p.E * ku);
      EXPECT_NEAR(rankine_dissipated(pt.state.data()), D, 1e-12 * D);
      if (e == 0) {
        for (double c : pt.sigma)
          EXPECT_EQ(c, 0.0);
      }
    }
}

// 4. Compression is elastic, also across an open crack (unilateral behaviour).
TEST(Rankine, CompressionStaysElastic)
{
  const RankineParams p = concrete(Softening::Linear);
  const double k0 = p.ft / p.E;
  const std::vector<double> X = box(0.1, 0.1, 0.1);
  Point pt;
  for (int i = 1; i <= 1000; ++i) {
    const double e = -100 * k0 * i / 1000;
    const double eps[6] = {e, 0, 0, 0, 0, 0};
    EXPECT_EQ(pt.step(p, StressMode::Solid, eps, X), p.E * e); // nu = 0: 2 mu = E exactly
  }
  EXPECT_EQ(rankine_damage(pt.state.data()), 0.0);
  EXPECT_EQ(rankine_dissipated(pt.state.data()), 0.0);
  EXPECT_EQ(rankine_band_width(pt.state.data()), 0.0);

  // Uniaxial compressive stress with nu = 0.25: lateral strains -nu e, all principal <= ~0.
  const RankineParams q = concrete(Softening::Linear, 0.25);
  Point pq;
  const double e = -100 * k0, eps[6] = {e, -0.25 * e, -0.25 * e, 0, 0, 0};
  pq.step(q, StressMode::Solid, eps, X);
  EXPECT_LT(rel_err(pq.sigma[0], q.E * e), 1e-12);
  EXPECT_EQ(rankine_damage(pq.state.data()), 0.0);

  // Fully open crack across x (d = 1), then compression along x: E eps exactly.
  Point pc;
  drive_uniaxial(p, 0.1, 1.1 * kappa_f(p, 0.1), 2000, pc);
  ASSERT_EQ(rankine_damage(pc.state.data()), 1.0);
  const double ec[6] = {-10 * k0, 0, 0, 0, 0, 0};
  EXPECT_EQ(pc.step(p, StressMode::Solid, ec, box(0.1, 2, 3)), p.E * ec[0]);
}

// 5. Rotating crack: crack opened along x, the same strain magnitude turned about z. kappa and d
// stay put, the degradation follows the new direction, the stored normal rotates with it.
TEST(Rankine, CrackRotatesWithThePrincipalDirection)
{
  const RankineParams p = concrete(Softening::Linear);
  const double h = 0.1, k0 = p.ft / p.E, e1 = k0 + 0.3 * (kappa_f(p, h) - k0);
  const std::vector<double> X = box(h, h, h);
  Point pt;
  drive_uniaxial(p, h, e1, 500, pt);
  const double d = rankine_damage(pt.state.data());
  ASSERT_GT(d, 0.0);
  ASSERT_LT(d, 1.0);
  const double pi = 3.14159265358979323846;
  for (int i = 1; i <= 90; ++i) {
    const double th = pi / 2 * i / 90, c = std::cos(th), s = std::sin(th);
    // e1 (c, s, 0) (c, s, 0)^T, engineering shear 2 e1 c s; exact at 90 degrees.
    double eps[6] = {e1 * c * c, e1 * s * s, 0, 2 * e1 * c * s, 0, 0};
    if (i == 90) eps[0] = eps[3] = 0, eps[1] = e1;
    pt.step(p, StressMode::Solid, eps, X);
    EXPECT_LT(rel_err(rankine_damage(pt.state.data()), d), 1e-12);
    // nu = 0: trial stress E eps, one principal value E e1 along (c, s, 0) degraded by (1 - d).
    const double smax = (1 - d) * p.E * e1;
    EXPECT_NEAR(pt.sigma[0], smax * c * c, 1e-12 * smax);
    EXPECT_NEAR(pt.sigma[1], smax * s * s, 1e-12 * smax);
    EXPECT_NEAR(pt.sigma[3], smax * c * s, 1e-12 * smax);
    const double* n = rankine_crack_normal(pt.state.data());
    EXPECT_NEAR(std::fabs(n[0] * c + n[1] * s), 1.0, 1e-12) << "angle step " << i;
    if (i == 45) {
      EXPECT_NEAR(n[0], std::sqrt(0.5), 1e-12); // normal signed with a positive largest entry
      EXPECT_NEAR(n[1], std::sqrt(0.5), 1e-12);
      EXPECT_EQ(n[2], 0.0);
    }
  }
  EXPECT_LE(pt.sigma[0], 1e-12 * p.ft); // x no longer tensile
  EXPECT_LT(rel_err(pt.sigma[1], (1 - d) * p.E * e1), 1e-12);
  EXPECT_DOUBLE_EQ(rankine_band_width(pt.state.data()), h); // h stays that of onset
}

// 6. Plane stress: sigma_zz = 0 and the reduced matrix
// E / (1 - nu^2) [1 nu 0; nu 1 0; 0 0 (1 - nu) / 2].
TEST(Rankine, PlaneStressMatchesReducedMatrixAndKeepsSigmaZzZero)
{
  const RankineParams p = concrete(Softening::Linear, 0.3);
  const double nu = p.nu, c = p.E / (1 - nu * nu), k0 = p.ft / p.E;
  const std::vector<double> X = box(0.1, 0.1, 0.1);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.4 * k0, 0.4 * k0); // below onset
  for (int t = 0; t < 200; ++t) {
    // zz / yz / zx filled with junk on purpose: plane stress must ignore them.
    const double eps[6] = {u(rng), u(rng), 50 * k0, u(rng), u(rng), u(rng)};
    Point pt;
    pt.step(p, StressMode::PlaneStress, eps, X);
    const double ref[3] = {c * (eps[0] + nu * eps[1]), c * (nu * eps[0] + eps[1]),
                           c * 0.5 * (1 - nu) * eps[3]};
    const double scale = std::sqrt(ref[0] * ref[0] + ref[1] * ref[1] + ref[2] * ref[2]);
    EXPECT_NEAR(pt.sigma[0], ref[0], 1e-12 * scale);
    EXPECT_NEAR(pt.sigma[1], ref[1], 1e-12 * scale);
    EXPECT_NEAR(pt.sigma[3], ref[2], 1e-12 * scale);
    EXPECT_EQ(pt.sigma[2], 0.0);
    EXPECT_EQ(pt.sigma[4], 0.0);
    EXPECT_EQ(pt.sigma[5], 0.0);
    EXPECT_EQ(rankine_damage(pt.state.data()), 0.0);
  }
  // Past onset (equibiaxial tension) sigma_zz stays exactly 0.
  Point pt;
  const double eps[6] = {3 * k0, 2 * k0, 1.0, k0, 0, 0};
  pt.step(p, StressMode::PlaneStress, eps, X);
  EXPECT_GT(rankine_damage(pt.state.data()), 0.0);
  EXPECT_EQ(pt.sigma[2], 0.0);
  EXPECT_EQ(rankine_crack_normal(pt.state.data())[2], 0.0); // crack normal in the plane
}

// Plane strain: eps_zz forced to 0, sigma_zz = lambda (eps_xx + eps_yy) follows.
TEST(Rankine, PlaneStrainIgnoresEpsZzAndCarriesSigmaZz)
{
  const RankineParams p = concrete(Softening::Linear, 0.2);
  const double lam = p.E * p.nu / ((1 + p.nu) * (1 - 2 * p.nu)), mu = p.E / (2 * (1 + p.nu));
  const double k0 = p.ft / p.E, eps[6] = {0.3 * k0, -0.2 * k0, 7 * k0, 0.1 * k0, k0, k0};
  Point pt;
  pt.step(p, StressMode::PlaneStrain, eps, box(1, 1, 1));
  EXPECT_NEAR(pt.sigma[2], lam * (eps[0] + eps[1]), 1e-12 * p.ft);
  EXPECT_NEAR(pt.sigma[0], lam * (eps[0] + eps[1]) + 2 * mu * eps[0], 1e-12 * p.ft);
  EXPECT_NEAR(pt.sigma[3], mu * eps[3], 1e-12 * p.ft);
  EXPECT_EQ(pt.sigma[4], 0.0);
  EXPECT_EQ(pt.sigma[5], 0.0);
}

// Axisymmetric: a hoop (zz slot) tension cracks with its normal along the hoop direction and h
// taken across z of the reference nodes (for a 2D element the caller passes its own extent there).
TEST(Rankine, AxisymmetricHoopTensionCracksAcrossTheHoopSlot)
{
  const RankineParams p = concrete(Softening::Linear);
  const double k0 = p.ft / p.E;
  const double eps[6] = {0.2 * k0, 0.1 * k0, 2 * k0, 0, 5 * k0, 5 * k0}; // yz / zx junk ignored
  Point pt;
  pt.step(p, StressMode::Axisymmetric, eps, box(1, 1, 0.2));
  const double* n = rankine_crack_normal(pt.state.data());
  EXPECT_EQ(n[0], 0.0);
  EXPECT_EQ(n[1], 0.0);
  EXPECT_EQ(n[2], 1.0);
  EXPECT_DOUBLE_EQ(rankine_band_width(pt.state.data()), 0.2);
  const double d = 1 - uniaxial_stress(p, 0.2, 2 * k0) / (p.E * 2 * k0); // nu = 0: s1 = E e_zz
  EXPECT_NEAR(rankine_damage(pt.state.data()), d, 1e-12);
  EXPECT_NEAR(pt.sigma[2], (1 - d) * p.E * 2 * k0, 1e-9 * p.ft);
  EXPECT_EQ(pt.sigma[4], 0.0);
  EXPECT_EQ(pt.sigma[5], 0.0);
}

// 7. Pure shear gamma_xy: principal stresses +-mu gamma along (1, +-1, 0) / sqrt(2), so onset at
// mu gamma = ft with the normal at 45 degrees and h = extent of (x + y) / sqrt(2).
TEST(Rankine, PureShearOnsetAtMuGammaEqualsFtWithNormalAt45Degrees)
{
  for (StressMode m : {StressMode::Solid, StressMode::PlaneStrain, StressMode::PlaneStress}) {
    const RankineParams p = concrete(Softening::Linear, 0.2);
    const double mu = p.E / (2 * (1 + p.nu)), gc = p.ft / mu, L = 0.05;
    const std::vector<double> X = box(L, L, L);
    Point pt;
    for (int i = 1; i <= 999; ++i) { // up to 0.999 gc: elastic
      const double eps[6] = {0, 0, 0, 0.999 * gc * i / 999, 0, 0};
      pt.step(p, m, eps, X);
    }
    EXPECT_EQ(rankine_damage(pt.state.data()), 0.0);
    EXPECT_EQ(rankine_band_width(pt.state.data()), 0.0);
    EXPECT_EQ(rankine_crack_normal(pt.state.data())[0], 0.0);
    // Below onset kappa is only bounded (the Gershgorin fast path skips the eigen-solve).
    EXPECT_LE(pt.state[0], p.ft / p.E);
    EXPECT_LT(rel_err(pt.sigma[3], mu * 0.999 * gc), 1e-12);
    const double g = 1.001 * gc, eps[6] = {0, 0, 0, g, 0, 0};
    pt.step(p, m, eps, X);
    const double h = std::sqrt(2.0) * L; // extent of (x + y) / sqrt(2) over the cube
    EXPECT_NEAR(rankine_band_width(pt.state.data()), h, 1e-12 * h);
    const double* n = rankine_crack_normal(pt.state.data());
    EXPECT_NEAR(n[0], std::sqrt(0.5), 1e-12);
    EXPECT_NEAR(n[1], std::sqrt(0.5), 1e-12);
    EXPECT_NEAR(n[2], 0.0, 1e-15);
    const double kappa = mu * g / p.E;
    EXPECT_NEAR(rankine_damage(pt.state.data()), 1 - uniaxial_stress(p, h, kappa) / (p.E * kappa),
                1e-9);
    // Only the tensile principal stress is degraded: sigma_xy = (2 - d) mu gamma / 2, and the
    // normal components (1 - d) mu g / 2 - mu g / 2 = -d mu g / 2.
    const double d = rankine_damage(pt.state.data());
    EXPECT_NEAR(pt.sigma[3], (1 - 0.5 * d) * mu * g, 1e-9 * p.ft);
    EXPECT_NEAR(pt.sigma[0], -0.5 * d * mu * g, 1e-9 * p.ft);
  }
}

// 8. Snap-back length, parameter checks, bitwise determinism.
TEST(Rankine, SnapbackLengthAndItsLimit)
{
  for (Softening s : {Softening::Linear, Softening::Exponential}) {
    const RankineParams p = concrete(s);
    const double lsb = rankine_snapback_length(p);
    EXPECT_LT(rel_err(lsb, 2 * 30e9 * 100 / (3e6 * 3e6)), 1e-15); // 2 E gf / ft^2 = 2/3
    // Just below: kappa_f > kappa0 (kappa_e > 0), a softening branch exists (d < 1 right after
    // onset). Above: no branch, documented vertical drop (d = 1), no NaN.
    for (double h : {0.99 * lsb, 1.5 * lsb}) {
      Point pt;
      const double k0 = p.ft / p.E, eps[6] = {1.0001 * k0, 0, 0, 0, 0, 0};
      pt.step(p, StressMode::Solid, eps, box(h, 1, 1));
      EXPECT_EQ(rankine_damage(pt.state.data()) < 1.0, h < lsb) << int(s) << " h " << h;
      EXPECT_TRUE(std::isfinite(pt.sigma[0]));
      EXPECT_EQ(rankine_cracked(p, pt.state.data()), h > lsb);
    }
  }
}

TEST(Rankine, CheckNamesTheOffendingParameter)
{
  EXPECT_NO_THROW(rankine_check(concrete()));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    double E, nu, ft, gf;
    const char* name;
  };
  const Case cases[] = {
      {0, 0.2, 3e6, 100, "parameter E "},    {-1, 0.2, 3e6, 100, "parameter E "},
      {nan, 0.2, 3e6, 100, "parameter E "},  {30e9, 0.5, 3e6, 100, "parameter nu "},
      {30e9, -1, 3e6, 100, "parameter nu "}, {30e9, nan, 3e6, 100, "parameter nu "},
      {30e9, 0.2, 0, 100, "parameter ft "},  {30e9, 0.2, -3e6, 100, "parameter ft "},
      {30e9, 0.2, 3e6, 0, "parameter gf "},  {30e9, 0.2, 3e6, -1, "parameter gf "}};
  for (const Case& c : cases) {
    RankineParams p = concrete();
    p.E = c.E, p.nu = c.nu, p.ft = c.ft, p.gf = c.gf;
    try {
      rankine_check(p);
      ADD_FAILURE() << "no throw for " << c.name;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(c.name), std::string::npos) << e.what();
    }
  }
}

TEST(Rankine, SameInputGivesIdenticalBits)
{
  for (Softening s : {Softening::Linear, Softening::Exponential}) {
    const RankineParams p = concrete(s, 0.2);
    const double k0 = p.ft / p.E;
    const double path[3][6] = {{0.5 * k0, 0.2 * k0, -0.1 * k0, 0.3 * k0, 0.1 * k0, -0.2 * k0},
                               {1.7 * k0, 0.9 * k0, -0.3 * k0, 1.1 * k0, 0.4 * k0, -0.6 * k0},
                               {2.3 * k0, 2.1 * k0, 0.7 * k0, -0.8 * k0, 1.4 * k0, 0.9 * k0}};
    const std::vector<double> X = box(0.07, 0.05, 0.09);
    Point a, b;
    for (const auto& eps : path) {
      const double pa = a.step(p, StressMode::Solid, eps, X) + a.psi;
      const double pb = b.step(p, StressMode::Solid, eps, X) + b.psi;
      EXPECT_EQ(std::memcmp(&pa, &pb, sizeof pa), 0);
      EXPECT_EQ(std::memcmp(a.sigma, b.sigma, sizeof a.sigma), 0);
      EXPECT_EQ(std::memcmp(a.state.data(), b.state.data(), kRankineStateSize * sizeof(double)), 0);
    }
    EXPECT_GT(rankine_damage(a.state.data()), 0.0);
  }
}

// work = stored + dissipated at every step of an arbitrary non-proportional 3D path: the kernel's
// D is defined that way (trapezoidal work minus psi), so this holds to round-off.
TEST(Rankine, WorkEqualsStoredPlusDissipatedOnARandomPath)
{
  const RankineParams p = concrete(Softening::Exponential, 0.2);
  const double k0 = p.ft / p.E;
  const std::vector<double> X = box(0.1, 0.12, 0.08);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.3 * k0, 0.3 * k0);
  Point pt;
  double eps[6] = {0, 0, 0, 0, 0, 0}, prev_e[6] = {0, 0, 0, 0, 0, 0};
  double prev_s[6] = {0, 0, 0, 0, 0, 0};
  double work = 0;
  for (int i = 0; i < 400; ++i) {
    for (double& e : eps)
      e += u(rng) + 0.02 * k0; // drifts into tension and softening
    pt.step(p, StressMode::Solid, eps, X);
    for (int k = 0; k < 6; ++k)
      work += 0.5 * (prev_s[k] + pt.sigma[k]) * (eps[k] - prev_e[k]);
    std::copy(eps, eps + 6, prev_e);
    std::copy(pt.sigma, pt.sigma + 6, prev_s);
    EXPECT_NEAR(work, pt.psi + rankine_dissipated(pt.state.data()), 1e-10 * p.ft * k0 * (i + 1));
  }
  EXPECT_GT(rankine_damage(pt.state.data()), 0.5);
  EXPECT_GT(rankine_dissipated(pt.state.data()), 0.0);
}

// 9. No NaN: zero strain, tiny (denormal) strain, degenerate or missing element at onset.
TEST(Rankine, NoNanForZeroTinyStrainAndDegenerateElements)
{
  const RankineParams p = concrete(Softening::Linear, 0.2);
  const double k0 = p.ft / p.E;
  const std::vector<double> X = box(0.1, 0.1, 0.1);
  auto all_finite = [](const Point& pt) {
    for (double v : pt.sigma)
      if (!std::isfinite(v)) return false;
    for (double v : pt.state)
      if (!std::isfinite(v)) return false;
    return std::isfinite(pt.psi);
  };
  Point z;
  const double zero[6] = {0, 0, 0, 0, 0, 0};
  z.step(p, StressMode::Solid, zero, X);
  for (double v : z.sigma)
    EXPECT_EQ(v, 0.0);
  for (double v : z.state)
    EXPECT_EQ(v, 0.0); // still virgin
  for (double t : {1e-300, 4e-320}) {
    for (StressMode m : {StressMode::Solid, StressMode::PlaneStress, StressMode::Axisymmetric}) {
      Point pt;
      const double eps[6] = {t, -2 * t, 3 * t, t, -t, 2 * t};
      pt.step(p, m, eps, X);
      EXPECT_TRUE(all_finite(pt)) << t;
      EXPECT_EQ(rankine_damage(pt.state.data()), 0.0);
    }
  }
  // All nodes equal (h = 0) and no element at all: the point fails at once (d = 1), finitely.
  const std::vector<double> flat(24, 1.5);
  for (int variant = 0; variant < 2; ++variant) {
    Point pt;
    const double eps[6] = {3 * k0, k0, 0, k0, 0, 0};
    if (variant == 0)
      pt.step(p, StressMode::Solid, eps, flat);
    else
      pt.psi = rankine_stress(p, StressMode::Solid, eps, nullptr, 0, pt.state.data(), pt.sigma);
    EXPECT_TRUE(all_finite(pt));
    EXPECT_EQ(rankine_damage(pt.state.data()), 1.0);
    EXPECT_EQ(rankine_band_width(pt.state.data()), 0.0);
    EXPECT_TRUE(rankine_cracked(p, pt.state.data()));
    const double more[6] = {30 * k0, 10 * k0, 0, k0, 0, 0};
    pt.step(p, StressMode::Solid, more, flat);
    EXPECT_TRUE(all_finite(pt));
  }
}
