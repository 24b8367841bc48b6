// Unit tests of the liquid bridge kernels against their closed forms and limits: Willett's force
// at contact and its decrease with the gap, rupture at Lian's distance, symmetry in the radii, the
// sphere-plane limit, the potential as the force's antiderivative, Pitois's lubrication limit.
#include <gtest/gtest.h>

#include <cmath>

#include "contact/liquid_bridge.h"

using namespace fracdem;

namespace
{

constexpr double kPi = 3.14159265358979323846;

// Water-like bridge between millimetre spheres: gamma 0.072 N/m, theta 0.4 rad, V = 8e-12 m^3.
LiquidBridge water(double viscosity = 0)
{
  LiquidBridge b;
  b.surface_tension = 0.072;
  b.contact_angle = 0.4;
  b.volume = 8e-12;
  b.viscosity = viscosity;
  return b;
}

} // namespace

TEST(LiquidBridge, ForceAtContactIsTheDerjaguinLimit)
{
  const LiquidBridge b = water();
  const double r_star = derjaguin_radius(1e-3, 2e-3);
  const double f0 = 2 * kPi * r_star * 0.072 * std::cos(0.4);
  EXPECT_NEAR(capillary_force(b, r_star, 0.0), f0, 1e-12 * f0);
  // Overlapping spheres keep the force at contact.
  EXPECT_NEAR(capillary_force(b, r_star, -1e-5), f0, 1e-12 * f0);
}

TEST(LiquidBridge, ForceFollowsWillettsDenominator)
{
  const LiquidBridge b = water();
  const double r_star = 1e-3;
  // S^ = S sqrt(R*/V) = 1 at S = sqrt(V/R*): F = F0 / (1 + 1.05 + 2.5).
  const double s1 = std::sqrt(b.volume / r_star);
  ASSERT_LT(s1, rupture_distance(b));
  const double f0 = capillary_force(b, r_star, 0.0);
  EXPECT_NEAR(capillary_force(b, r_star, s1), f0 / 4.55, 1e-12 * f0);
}

TEST(LiquidBridge, ForceDecreasesWithTheGapAndVanishesAtRupture)
{
  const LiquidBridge b = water();
  const double r_star = 1e-3, sc = rupture_distance(b);
  // Lian's S_c = (1 + theta/2) V^(1/3) = 1.2 * 2e-4 m.
  EXPECT_NEAR(sc, 1.2 * 2e-4, 1e-15);
  double previous = capillary_force(b, r_star, 0.0);
  for (int k = 1; k < 200; ++k) {
    const double f = capillary_force(b, r_star, sc * k / 200.0);
    EXPECT_LT(f, previous) << "gap " << sc * k / 200.0;
    EXPECT_GT(f, 0.0);
    previous = f;
  }
  EXPECT_EQ(capillary_force(b, r_star, sc), 0.0);
  EXPECT_EQ(capillary_force(b, r_star, 2 * sc), 0.0);
}

TEST(LiquidBridge, SymmetricInTheRadiiWithThePlaneAsLimit)
{
  EXPECT_DOUBLE_EQ(derjaguin_radius(1e-3, 3e-3), derjaguin_radius(3e-3, 1e-3));
  EXPECT_DOUBLE_EQ(derjaguin_radius(2e-3, 2e-3), 2e-3); // equal spheres: R* = R
  const LiquidBridge b = water();
  EXPECT_DOUBLE_EQ(capillary_force(b, derjaguin_radius(1e-3, 3e-3), 1e-5),
                   capillary_force(b, derjaguin_radius(3e-3, 1e-3), 1e-5));
  // R2 -> infinity tends to the plane's R* = 2 R1, which r2 <= 0 stands for.
  EXPECT_NEAR(derjaguin_radius(1e-3, 1e6), 2e-3, 1e-11);
  EXPECT_DOUBLE_EQ(derjaguin_radius(1e-3, 0.0), 2e-3);
  const double far = capillary_force(b, derjaguin_radius(1e-3, 1e6), 5e-5);
  const double plane = capillary_force(b, derjaguin_radius(1e-3, 0.0), 5e-5);
  EXPECT_NEAR(far, plane, 1e-6 * plane);
}

TEST(LiquidBridge, PotentialIsTheForcesAntiderivativeAndZeroAtRupture)
{
  const LiquidBridge b = water();
  const double r_star = 1.5e-3, sc = rupture_distance(b);
  // dU/dS = F_c by central differences, in contact and apart.
  for (double gap : {-2e-5, 1e-6, 3e-5, 1e-4, 0.9 * sc}) {
    const double h = 1e-9;
    const double du = (capillary_potential(b, r_star, gap + h) -
                       capillary_potential(b, r_star, gap - h)) / (2 * h);
    const double f = capillary_force(b, r_star, gap);
    EXPECT_NEAR(du, f, 1e-5 * f) << "gap " << gap;
  }
  EXPECT_NEAR(capillary_potential(b, r_star, sc * (1 - 1e-12)), 0.0, 1e-15);
  EXPECT_EQ(capillary_potential(b, r_star, 2 * sc), 0.0);
  // Trapezoid integral of the force from 0 to S_c is the depth of the well.
  const int n = 20000;
  double work = 0;
  for (int k = 0; k < n; ++k)
    work += 0.5 * sc / n *
            (capillary_force(b, r_star, sc * k / n) +
             capillary_force(b, r_star, std::min(sc * (k + 1) / n, sc * (1 - 1e-15))));
  EXPECT_NEAR(-capillary_potential(b, r_star, 0.0), work, 1e-6 * work);
}

TEST(LiquidBridge, ViscousForceResistsTheGapChangeWithTheLubricationLimit)
{
  const double mu = 0.1, r_star = 1e-3;
  const LiquidBridge b = water(mu);
  // Large V / (R* S^2): Pitois's shape factor -> 1 and F_v -> 6 pi mu R*^2 v / S (Reynolds).
  const double gap = 2e-6, v = 1e-3;
  const double reynolds = 6 * kPi * mu * r_star * r_star * v / gap;
  const double shape = 1 - 1 / std::sqrt(1 + 2 * b.volume / (kPi * r_star * gap * gap));
  EXPECT_NEAR(viscous_force(b, r_star, gap, v), reynolds * shape * shape, 1e-12 * reynolds);
  EXPECT_NEAR(viscous_force(b, r_star, gap, v), reynolds, 0.1 * reynolds);
  EXPECT_GT(viscous_force(b, r_star, gap, v), 0.0);                   // opening: attractive
  EXPECT_DOUBLE_EQ(viscous_force(b, r_star, gap, -v), -viscous_force(b, r_star, gap, v));
  EXPECT_EQ(viscous_force(water(0.0), r_star, gap, v), 0.0);         // no viscosity
  EXPECT_EQ(viscous_force(b, r_star, rupture_distance(b), v), 0.0);  // broken bridge
  // The floor keeps it finite in contact.
  EXPECT_DOUBLE_EQ(viscous_force(b, r_star, -1e-6, v),
                   viscous_force(b, r_star, kViscousGapFloor * r_star, v));
}

TEST(LiquidBridge, FormsOnlyAtContactAndPersistsUntilRupture)
{
  const double sc = 1e-4;
  EXPECT_FALSE(bridge_persists(false, 0.5 * sc, sc)); // close but never touched
  EXPECT_TRUE(bridge_persists(false, 0.0, sc));       // touch forms it
  EXPECT_TRUE(bridge_persists(false, -1e-6, sc));
  EXPECT_TRUE(bridge_persists(true, 0.99 * sc, sc)); // stretched, still there
  EXPECT_FALSE(bridge_persists(true, sc, sc));       // ruptured
  EXPECT_FALSE(bridge_persists(true, 2 * sc, sc));
}

TEST(LiquidBridge, ParameterChecksNameTheKeyword)
{
  EXPECT_EQ(check_liquid_bridge(water()), "");
  LiquidBridge b = water();
  b.surface_tension = -1;
  EXPECT_NE(check_liquid_bridge(b).find("surface_tension"), std::string::npos);
  b = water();
  b.volume = -1e-12;
  EXPECT_NE(check_liquid_bridge(b).find("volume"), std::string::npos);
  b = water();
  b.contact_angle = 0.5 * kPi;
  EXPECT_NE(check_liquid_bridge(b).find("contact_angle"), std::string::npos);
  b.contact_angle = -0.1;
  EXPECT_NE(check_liquid_bridge(b).find("contact_angle"), std::string::npos);
  b = water(-1);
  EXPECT_NE(check_liquid_bridge(b).find("viscosity"), std::string::npos);
}

TEST(LiquidBridge, SettingsParseTheKeywordTable)
{
  BridgeSettings s;
  EXPECT_EQ(parse_bridge_settings({"willett", "surface_tension", "0.072", "contact_angle", "0.2",
                                   "volume", "1e-12", "viscosity", "1e-3", "wet", "no"},
                                  s),
            "");
  EXPECT_TRUE(s.on);
  EXPECT_DOUBLE_EQ(s.law.surface_tension, 0.072);
  EXPECT_DOUBLE_EQ(s.law.contact_angle, 0.2);
  EXPECT_DOUBLE_EQ(s.law.volume, 1e-12);
  EXPECT_DOUBLE_EQ(s.law.viscosity, 1e-3);
  EXPECT_FALSE(s.wet);
  // Defaults: no viscosity, wet yes.
  EXPECT_EQ(parse_bridge_settings({"willett", "volume", "1e-12", "contact_angle", "0",
                                   "surface_tension", "0.07"},
                                  s),
            "");
  EXPECT_EQ(s.law.viscosity, 0.0);
  EXPECT_TRUE(s.wet);
  auto error = [](std::vector<std::string> w) {
    BridgeSettings t;
    std::string e = parse_bridge_settings(w, t);
    EXPECT_FALSE(t.on);
    return e;
  };
  EXPECT_NE(error({"rabinovich"}).find("unknown bridge model 'rabinovich'"), std::string::npos);
  EXPECT_NE(error({"willett", "tension", "1"}).find("unknown bridge keyword 'tension'"),
            std::string::npos);
  EXPECT_NE(error({"willett", "volume", "1e-12"}).find("needs surface_tension"), std::string::npos);
  EXPECT_NE(error({"willett", "surface_tension", "-0.07", "contact_angle", "0", "volume", "1e-12"})
                .find("surface_tension must be >= 0"),
            std::string::npos);
  EXPECT_NE(error({"willett", "surface_tension", "0.07", "contact_angle", "2", "volume", "1e-12"})
                .find("contact_angle"),
            std::string::npos);
  EXPECT_NE(error({"willett", "surface_tension", "0.07", "contact_angle", "0", "volume", "-1"})
                .find("volume must be > 0"),
            std::string::npos);
  EXPECT_NE(error({"willett", "surface_tension", "x"}).find("needs a number"), std::string::npos);
  EXPECT_NE(error({"willett", "wet", "maybe"}).find("yes or no"), std::string::npos);
}

TEST(LiquidBridge, UnknownWordsGetTheNearestKeyword)
{
  BridgeSettings s;
  EXPECT_NE(parse_bridge_settings({"willett", "surface_tenison", "0.07"}, s)
                .find("did you mean 'surface_tension'?"),
            std::string::npos);
  EXPECT_NE(parse_bridge_settings({"willet"}, s).find("did you mean 'willett'?"),
            std::string::npos);
  // Nothing near: no suggestion.
  EXPECT_EQ(parse_bridge_settings({"willett", "colour", "1"}, s).find("did you mean"),
            std::string::npos);
}
