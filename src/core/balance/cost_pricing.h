// The cost models of fix balance/graph (counts, calibrated, timed, fitted): a rank's particle
// costs at a check, from what its particles did and, where the model asks, its measured time.
#ifndef FRACDEM_BALANCE_COST_PRICING_H
#define FRACDEM_BALANCE_COST_PRICING_H

#include <cstddef>
#include <vector>

#include "balance/cost_fit.h"
#include "balance/cost_model.h"

namespace fracdem::balance
{

enum class CostModel { Counts, Calibrated, Timed, Fitted };

// A rank's particle costs at one check and their total (the rank's work at the check).
struct RankWork {
  std::vector<double> cost;
  double total = 0;
};

// `cost fitted` keeps the samples of this many checks (older ones are dropped: the costs drift
// as the scene changes) and shrinks the fit towards the prior's ratios with this strength.
constexpr int kFitWindowChecks = 8;
constexpr double kFitShrink = 0.05;

// One cost model with its current costs. `prior` is the start-up price list: unit costs for
// `counts`, the calibrated ones otherwise (and the prior of the fit).
class CostPricing
{
public:
  CostPricing(CostModel model, const InteractionCosts& prior)
      : model_(model), prior_(prior), costs_(prior)
  {
  }
  CostModel model() const { return model_; }
  const InteractionCosts& costs() const { return costs_; }
  bool has_fit() const { return !samples_.empty(); } // costs() come from a fit

  // Whether a check refits (cost fitted, except the start check: nothing has been timed yet);
  // the host then hands refit() every rank's sample.
  bool refits(bool start_check) const { return model_ == CostModel::Fitted && !start_check; }
  // One check's samples, per_rank[(kCostTerms + 1) * r + k]: rank r's term sums (k < kCostTerms)
  // and its measured seconds of the interval (k = kCostTerms), over interval_steps steps. Every
  // rank refits the same samples in the same order: identical costs everywhere. Throws
  // std::invalid_argument for a size that is not a whole number of samples.
  void refit(const std::vector<double>& per_rank, double interval_steps);

  // The costs of the counted particles. counts, calibrated and the start check: the model.
  // timed: the model only splits the rank's measured seconds among its particles (total =
  // measured, where both are > 0). fitted: the fitted costs per step times interval_steps (the
  // check compares the measured time of the whole interval), total = measured where > 0.
  RankWork price(const WorkCounts& w, bool start_check, double measured_seconds,
                 double interval_steps) const;

  // The state a restart carries: the prior (calibrated costs are measured once, at the start of
  // the first run), the current costs and the fit's samples, as numbers. restore() takes what
  // state() gave (the same model) and throws std::invalid_argument on a size that does not fit.
  std::vector<double> state() const;
  void restore(const std::vector<double>& state);

private:
  CostModel model_;
  InteractionCosts prior_, costs_;
  std::vector<CostSample> samples_; // the last kFitWindowChecks checks', oldest first
};

// The model's price of every counted particle and their sum.
RankWork price_counts(const InteractionCosts& c, const WorkCounts& w);

} // namespace fracdem::balance

#endif
