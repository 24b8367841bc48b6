// Unit tests of the online cost fit (`cost fitted`): recovery of known costs, shrinkage, bounds.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "balance/cost_fit.h"

using namespace fracdem::balance;

namespace
{

const TermCounts kPrior = {1.0, 0.5, 1.0, 4.0, 3.0, 2.0, 6.0, 5.0, 1.0};

// Samples of ranks with independent random counts of every present term; seconds from `truth`
// with relative noise `noise`.
std::vector<CostSample> synthetic(const TermCounts& truth,
                                  const std::array<bool, kCostTerms>& present, int n, double noise,
                                  unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> count(100.0, 5000.0), jitter(-noise, noise);
  std::vector<CostSample> out(n);
  for (CostSample& s : out) {
    for (int k = 0; k < kCostTerms; ++k)
      s.counts[k] = present[k] ? count(rng) : 0.0;
    double t = 0;
    for (int k = 0; k < kCostTerms; ++k)
      t += truth[k] * s.counts[k];
    s.seconds = t * (1.0 + jitter(rng));
  }
  return out;
}

std::array<bool, kCostTerms> all_present()
{
  std::array<bool, kCostTerms> p;
  p.fill(true);
  return p;
}

} // namespace

// Enough independent samples and 0.5 % noise: every cost within 5 % of the truth (weak shrinkage;
// the statistical error is ~1-2 % here: seeds 1-30 all pass).
TEST(CostFit, RecoversKnownCosts)
{
  const TermCounts truth = {2.0e-8, 1.0e-8, 1.5e-8, 3.0e-8, 3.0e-8, 2.5e-8, 5.0e-8, 0.7e-8};
  const auto samples = synthetic(truth, all_present(), 120, 0.005, 3);
  const TermCounts fit = fit_costs(samples, kPrior, 1e-4);
  for (int k = 0; k < kCostTerms; ++k)
    EXPECT_NEAR(fit[k], truth[k], 0.05 * truth[k]) << "term " << k;
}

// Terms the samples never see keep the prior's ratio to the common factor of the others.
TEST(CostFit, AbsentTermsKeepThePriorRatio)
{
  std::array<bool, kCostTerms> present = all_present();
  present[kFacetCheck] = present[kFacetContact] = false;
  TermCounts truth;
  for (int k = 0; k < kCostTerms; ++k)
    truth[k] = 3e-9 * kPrior[k];
  const TermCounts fit = fit_costs(synthetic(truth, present, 40, 0.0, 5), kPrior, 0.05);
  EXPECT_NEAR(fit[kFacetCheck] / kPrior[kFacetCheck], 3e-9, 1e-12);
  EXPECT_NEAR(fit[kFacetContact] / kPrior[kFacetContact], 3e-9, 1e-12);
  EXPECT_NEAR(fit[kPairCheck], truth[kPairCheck], 1e-6 * truth[kPairCheck]);
}

// Counts in fixed proportion cannot separate the terms: the fit keeps the prior's ratios and
// matches the total time.
TEST(CostFit, CollinearSamplesKeepPriorRatiosAndTotal)
{
  std::vector<CostSample> samples(6);
  double time = 0, model = 0;
  for (int r = 0; r < 6; ++r) {
    const double n = 1000.0 * (r + 1);
    samples[r].counts = {n, 2 * n, 12 * n, 5 * n, 0.1 * n, 0, 0, 0.3 * n};
    samples[r].seconds = 1e-6 * n;
  }
  const TermCounts fit = fit_costs(samples, kPrior, 0.05);
  for (const CostSample& s : samples)
    for (int k = 0; k < kCostTerms; ++k)
      model += fit[k] * s.counts[k];
  for (const CostSample& s : samples)
    time += s.seconds;
  EXPECT_NEAR(model, time, 1e-9 * time);
  for (int k = 1; k < kCostTerms; ++k)
    EXPECT_NEAR(fit[k] / fit[kParticle], kPrior[k] / kPrior[kParticle], 1e-9) << "term " << k;
}

// A term that costs nothing (its least-squares multiplier goes negative with noise) is held at
// zero, never below, and the time is still predicted within the noise.
TEST(CostFit, CostsStayNonNegative)
{
  const TermCounts truth = {2.0e-8, 0.0, 1.5e-8, 3.0e-8, 0.0, 2.5e-8, 5.0e-8, 0.0};
  const auto samples = synthetic(truth, all_present(), 60, 0.05, 9);
  const TermCounts fit = fit_costs(samples, kPrior, 1e-4);
  for (int k = 0; k < kCostTerms; ++k)
    EXPECT_GE(fit[k], 0.0) << "term " << k;
  for (const CostSample& s : samples) {
    double t = 0;
    for (int k = 0; k < kCostTerms; ++k)
      t += fit[k] * s.counts[k];
    EXPECT_NEAR(t, s.seconds, 0.1 * s.seconds);
  }
}

TEST(CostFit, DegenerateInputReturnsPriorAndBadInputThrows)
{
  EXPECT_EQ(fit_costs({}, kPrior), kPrior);
  CostSample idle; // no counts, no time
  EXPECT_EQ(fit_costs({idle, idle}, kPrior), kPrior);
  TermCounts negative = kPrior;
  negative[kPairCheck] = -1;
  EXPECT_THROW(fit_costs({}, negative), std::invalid_argument);
  EXPECT_THROW(fit_costs({}, kPrior, -0.1), std::invalid_argument);
}

TEST(CostFit, ArrayRoundTrip)
{
  InteractionCosts c;
  c.particle = 2, c.wall_check = 3, c.pair_check = 5, c.sphere_contact = 7;
  c.wall_contact = 11, c.facet_check = 13, c.facet_contact = 17, c.bridge = 19;
  const TermCounts a = cost_array(c);
  EXPECT_EQ(a[kGhost], c.particle);
  const InteractionCosts back = interaction_costs(a);
  EXPECT_EQ(back.particle, 2);
  EXPECT_EQ(back.wall_check, 3);
  EXPECT_EQ(back.pair_check, 5);
  EXPECT_EQ(back.sphere_contact, 7);
  EXPECT_EQ(back.wall_contact, 11);
  EXPECT_EQ(back.facet_check, 13);
  EXPECT_EQ(back.facet_contact, 17);
  EXPECT_EQ(back.bridge, 19);
}
