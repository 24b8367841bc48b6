// The cost models of fix balance/graph: pricing by the model, by measured time, and by the fit.
#include "balance/cost_pricing.h"

#include <algorithm>
#include <stdexcept>

namespace fracdem::balance
{

RankWork price_counts(const InteractionCosts& c, const WorkCounts& w)
{
  RankWork out;
  const int n = w.size();
  out.cost.resize(n);
  for (int i = 0; i < n; ++i) {
    out.cost[i] = particle_cost(c, w.particle(i));
    out.total += out.cost[i];
  }
  return out;
}

void CostPricing::refit(const std::vector<double>& per_rank, double interval_steps)
{
  constexpr std::size_t stride = kCostTerms + 1;
  if (per_rank.size() % stride != 0)
    throw std::invalid_argument("CostPricing::refit: samples must hold the term sums and the "
                                "seconds of every rank");
  const std::size_t nranks = per_rank.size() / stride;
  for (std::size_t r = 0; r < nranks; ++r) {
    CostSample sample;
    std::copy(&per_rank[r * stride], &per_rank[r * stride] + kCostTerms, sample.counts.begin());
    // Time per step, so that the costs are per item and step whatever the interval.
    sample.seconds = per_rank[r * stride + kCostTerms] / interval_steps;
    samples_.push_back(sample);
  }
  const std::size_t keep = static_cast<std::size_t>(kFitWindowChecks) * nranks;
  if (samples_.size() > keep) samples_.erase(samples_.begin(), samples_.end() - keep);
  costs_ = interaction_costs(fit_costs(samples_, cost_array(prior_), kFitShrink));
}

RankWork CostPricing::price(const WorkCounts& w, bool start_check, double measured_seconds,
                            double interval_steps) const
{
  RankWork work = price_counts(costs_, w);
  if (start_check) return work;
  if (model_ == CostModel::Timed && work.total > 0 && measured_seconds > 0) {
    const double scale = measured_seconds / work.total;
    for (double& c : work.cost)
      c *= scale;
    work.total = measured_seconds;
  } else if (model_ == CostModel::Fitted) {
    for (double& c : work.cost)
      c *= interval_steps;
    if (measured_seconds > 0) work.total = measured_seconds;
  }
  return work;
}

} // namespace fracdem::balance
