// Unit tests of the skin search: convergence on synthetic cost curves, bounds, noise, retuning.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "balance/skin_search.h"

using namespace fracdem::balance;

namespace
{

// Per-step cost of a list of reach r + s rebuilt every s / (2 v) steps: rebuilds of a list whose
// size grows as (r + s)^3 against a pair loop over it. Its minimum is found numerically.
struct Curve {
  double r = 4e-3, v = 2e-5, build = 3.0, pair = 1.0;
  double operator()(double s) const
  {
    const double size = std::pow(r + s, 3) / std::pow(r, 3);
    return pair * size + build * size * (2 * v / s);
  }
};

double argmin(const std::function<double(double)>& f, double lo, double hi)
{
  double best = lo, fbest = f(lo);
  for (int k = 1; k <= 200000; ++k) {
    const double s = lo + (hi - lo) * k / 200000.0;
    if (f(s) < fbest) best = s, fbest = f(s);
  }
  return best;
}

// Runs the search until it holds (at most `limit` intervals); returns the intervals used.
int settle(SkinSearch& search, const std::function<double(double)>& f, int limit = 100)
{
  int n = 0;
  while (n < limit) {
    search.record(f(search.skin()));
    ++n;
    if (!search.searching()) break;
  }
  return n;
}

} // namespace

TEST(SkinSearch, FindsTheMinimumOfASmoothCurve)
{
  const Curve f;
  const SkinSearchSettings s{1e-4, 4e-3};
  const double best = argmin(f, s.lo, s.hi);
  ASSERT_GT(best, s.lo * 1.5);
  ASSERT_LT(best, s.hi * 0.9); // an interior minimum
  SkinSearch search(s, 1e-3);
  const int n = settle(search, f);
  EXPECT_FALSE(search.searching());
  // Golden-section: the bracket shrinks by 0.618 per interval after the warm-up and two probes.
  const int bound = 3 + static_cast<int>(std::ceil(std::log(s.tolerance) / std::log(0.618)));
  EXPECT_LE(n, bound);
  EXPECT_NEAR(search.skin(), best, s.tolerance * (s.hi - s.lo));
  EXPECT_LT(f(search.skin()), 1.01 * f(best));
}

TEST(SkinSearch, AMinimumAtABoundIsApproachedAndNeverLeft)
{
  const SkinSearchSettings s{1e-3, 2e-3};
  for (int sign : {-1, 1}) {
    const auto f = [sign](double skin) { return 1.0 + sign * skin; };
    SkinSearch search(s, 1.5e-3);
    for (int k = 0; k < 30; ++k) {
      const double next = search.record(f(search.skin()));
      EXPECT_GE(next, s.lo);
      EXPECT_LE(next, s.hi);
    }
    const double end = sign > 0 ? s.lo : s.hi;
    EXPECT_NEAR(search.skin(), end, s.tolerance * (s.hi - s.lo));
  }
}

TEST(SkinSearch, NoisyCostsStillGiveANearlyOptimalSkin)
{
  const Curve f;
  const SkinSearchSettings s{1e-4, 4e-3};
  const double fbest = f(argmin(f, s.lo, s.hi));
  // Measured times scatter by a few percent on a shared machine.
  for (unsigned seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-0.03, 0.03);
    const auto noisy = [&](double skin) { return f(skin) * (1 + jitter(rng)); };
    SkinSearchSettings held = s;
    held.retune = 1e9; // hold whatever the noise
    SkinSearch search(held, 2e-3);
    settle(search, noisy);
    EXPECT_FALSE(search.searching());
    EXPECT_LT(f(search.skin()), 1.05 * fbest) << "seed " << seed;
  }
}

TEST(SkinSearch, HoldsUntilTheCostDriftsThenSearchesAgain)
{
  Curve f;
  const SkinSearchSettings s{1e-4, 4e-3};
  SkinSearch search(s, 1e-3);
  settle(search, f);
  ASSERT_FALSE(search.searching());
  const double held = search.skin();
  for (int k = 0; k < 10; ++k)
    EXPECT_EQ(search.record(f(held) * 1.1), held); // within the retune fraction
  EXPECT_EQ(search.searches(), 1);
  // One slow interval (the machine, not the scene) does not start a search.
  search.record(f(held) * 3);
  search.record(f(held));
  EXPECT_FALSE(search.searching());
  // Particles four times faster: rebuilds dominate and a larger skin pays.
  f.v *= 4;
  for (int k = 0; k < s.retune_intervals; ++k) {
    EXPECT_FALSE(search.searching());
    search.record(f(held));
  }
  EXPECT_TRUE(search.searching());
  EXPECT_EQ(search.searches(), 2);
  settle(search, f);
  const double best = argmin(f, s.lo, s.hi);
  EXPECT_GT(best, held);
  EXPECT_NEAR(search.skin(), best, s.tolerance * (s.hi - s.lo));
}

TEST(SkinSearch, StartIsClampedIntoTheBounds)
{
  const SkinSearchSettings s{1e-3, 2e-3};
  EXPECT_EQ(SkinSearch(s, 5e-3).skin(), 2e-3);
  EXPECT_EQ(SkinSearch(s, 1e-4).skin(), 1e-3);
  EXPECT_EQ(SkinSearch(s, 1.5e-3).skin(), 1.5e-3);
}

TEST(SkinSearch, SettingsAreChecked)
{
  EXPECT_EQ(check_skin_search({1e-3, 2e-3}), "");
  EXPECT_NE(check_skin_search({0, 2e-3}).find("SKIN_MIN"), std::string::npos);
  EXPECT_NE(check_skin_search({-1, 2e-3}).find("SKIN_MIN"), std::string::npos);
  EXPECT_NE(check_skin_search({2e-3, 2e-3}).find("SKIN_MAX"), std::string::npos);
  EXPECT_NE(check_skin_search({2e-3, 1e-3}).find("SKIN_MAX"), std::string::npos);
  EXPECT_NE(check_skin_search({1e-3, NAN}).find("SKIN_MAX"), std::string::npos);
  SkinSearchSettings bad{1e-3, 2e-3};
  bad.tolerance = 1.5;
  EXPECT_NE(check_skin_search(bad).find("tolerance"), std::string::npos);
}
