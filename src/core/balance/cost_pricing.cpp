// The cost models of fix balance/graph: pricing by the model, by measured time, and by the fit.
#include "balance/cost_pricing.h"

#include <algorithm>
#include <stdexcept>
#include <string>

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

std::vector<double> CostPricing::state() const
{
  std::vector<double> s;
  for (const InteractionCosts& c : {prior_, costs_}) {
    const TermCounts a = cost_array(c);
    s.insert(s.end(), a.begin(), a.end());
  }
  for (const CostSample& sample : samples_) {
    s.insert(s.end(), sample.counts.begin(), sample.counts.end());
    s.push_back(sample.seconds);
  }
  return s;
}

void CostPricing::restore(const std::vector<double>& state)
{
  constexpr std::size_t stride = kCostTerms + 1;
  if (state.size() < 2 * kCostTerms || (state.size() - 2 * kCostTerms) % stride != 0)
    throw std::invalid_argument("CostPricing::restore: expected the prior and current costs (" +
                                std::to_string(2 * kCostTerms) + " numbers) and whole samples (" +
                                std::to_string(stride) + " each), got " +
                                std::to_string(state.size()) + " numbers");
  TermCounts a;
  std::copy(state.begin(), state.begin() + kCostTerms, a.begin());
  prior_ = interaction_costs(a);
  std::copy(state.begin() + kCostTerms, state.begin() + 2 * kCostTerms, a.begin());
  costs_ = interaction_costs(a);
  samples_.clear();
  for (std::size_t k = 2 * kCostTerms; k < state.size(); k += stride) {
    CostSample sample;
    std::copy(&state[k], &state[k] + kCostTerms, sample.counts.begin());
    sample.seconds = state[k + kCostTerms];
    samples_.push_back(sample);
  }
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
