// Online fit of the interaction costs to measured per-rank CPU time: non-negative ridge least
// squares on a handful of terms.
#include "balance/cost_fit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fracdem::balance
{

TermCounts cost_array(const InteractionCosts& c)
{
  TermCounts a{};
  a[kParticle] = c.particle, a[kWallCheck] = c.wall_check, a[kPairCheck] = c.pair_check;
  a[kSphereContact] = c.sphere_contact, a[kWallContact] = c.wall_contact;
  a[kFacetCheck] = c.facet_check, a[kFacetContact] = c.facet_contact, a[kBridge] = c.bridge;
  a[kGhost] = c.particle;
  return a;
}

InteractionCosts interaction_costs(const TermCounts& a)
{
  InteractionCosts c;
  c.particle = a[kParticle], c.wall_check = a[kWallCheck], c.pair_check = a[kPairCheck];
  c.sphere_contact = a[kSphereContact], c.wall_contact = a[kWallContact];
  c.facet_check = a[kFacetCheck], c.facet_contact = a[kFacetContact], c.bridge = a[kBridge];
  return c;
}

namespace
{

constexpr int K = kCostTerms;
using Matrix = std::array<std::array<double, K>, K>;

// Solves M x = r restricted to the free terms (others fixed at zero) by Gaussian elimination with
// partial pivoting; M is symmetric positive definite on the free terms (ridge), so it is regular.
TermCounts solve_free(const Matrix& m, const TermCounts& r, const std::array<bool, K>& free)
{
  int idx[K], n = 0;
  for (int k = 0; k < K; ++k)
    if (free[k]) idx[n++] = k;
  double a[K][K + 1];
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j)
      a[i][j] = m[idx[i]][idx[j]];
    a[i][n] = r[idx[i]];
  }
  for (int c = 0; c < n; ++c) {
    int piv = c;
    for (int i = c + 1; i < n; ++i)
      if (std::fabs(a[i][c]) > std::fabs(a[piv][c])) piv = i;
    for (int j = 0; j <= n; ++j)
      std::swap(a[c][j], a[piv][j]);
    for (int i = c + 1; i < n; ++i) {
      const double f = a[i][c] / a[c][c];
      for (int j = c; j <= n; ++j)
        a[i][j] -= f * a[c][j];
    }
  }
  TermCounts x{};
  for (int i = n - 1; i >= 0; --i) {
    double s = a[i][n];
    for (int j = i + 1; j < n; ++j)
      s -= a[i][j] * x[idx[j]];
    x[idx[i]] = s / a[i][i];
  }
  return x;
}

} // namespace

TermCounts fit_costs(const std::vector<CostSample>& samples, const TermCounts& prior, double shrink)
{
  if (!(shrink >= 0)) throw std::invalid_argument("fit_costs: shrink must be >= 0");
  for (double p : prior)
    if (!(p >= 0)) throw std::invalid_argument("fit_costs: prior costs must be >= 0");

  // Columns are the prior's modelled time of each term, so the unknowns are dimensionless
  // multipliers of comparable size and one shrink strength suits every term.
  Matrix ata{};
  TermCounts atb{};
  double time_sum = 0, model_sum = 0;
  for (const CostSample& s : samples) {
    TermCounts z;
    for (int k = 0; k < K; ++k)
      z[k] = prior[k] * s.counts[k];
    for (int i = 0; i < K; ++i) {
      for (int j = 0; j < K; ++j)
        ata[i][j] += z[i] * z[j];
      atb[i] += z[i] * s.seconds;
      model_sum += z[i];
    }
    time_sum += s.seconds;
  }
  double trace = 0;
  int present = 0;
  for (int k = 0; k < K; ++k)
    if (ata[k][k] > 0) trace += ata[k][k], ++present;
  if (present == 0 || model_sum <= 0 || time_sum <= 0) return prior;

  const double common = time_sum / model_sum;
  const double lambda = std::max(shrink * trace / present, 1e-12 * trace);
  for (int k = 0; k < K; ++k) {
    ata[k][k] += lambda;
    atb[k] += lambda * common;
  }
  // Active set: a term driven below zero is fixed at zero and the rest refitted.
  std::array<bool, K> free;
  free.fill(true);
  TermCounts mult{};
  for (int round = 0; round < K; ++round) {
    mult = solve_free(ata, atb, free);
    int worst = -1;
    for (int k = 0; k < K; ++k)
      if (free[k] && mult[k] < 0 && (worst < 0 || mult[k] < mult[worst])) worst = k;
    if (worst < 0) break;
    free[worst] = false;
    mult[worst] = 0;
  }
  TermCounts fitted;
  for (int k = 0; k < K; ++k)
    fitted[k] = std::max(0.0, mult[k]) * prior[k];
  return fitted;
}

} // namespace fracdem::balance
