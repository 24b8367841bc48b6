// Online fit of the interaction costs to measured per-rank CPU time (`cost fitted`).
#ifndef FRACDEM_BALANCE_COST_FIT_H
#define FRACDEM_BALANCE_COST_FIT_H

#include <array>
#include <vector>

#include "balance/cost_model.h"

namespace fracdem::balance
{

// What one rank did in one check interval, by term of the work model, and the CPU time it took.
struct CostSample {
  TermCounts counts{};
  double seconds = 0;
};

// Costs as an array in CostTerm order; the ghost term starts at the per-particle cost (a ghost is
// binned and checked like a particle, but not integrated).
TermCounts cost_array(const InteractionCosts& c);
InteractionCosts interaction_costs(const TermCounts& a);

// Least-squares fit of seconds ~= sum_k s_k prior_k counts_k over the samples, in multipliers s_k
// >= 0 of the prior costs, shrunk towards the one common multiplier that fits the total time
// (ridge, strength `shrink` relative to the mean diagonal of the normal matrix): terms the
// samples cannot tell apart (too few ranks, collinear counts, absent terms) keep the prior's
// ratios. Returns the fitted costs (in seconds per item); the prior when there is no time or
// count in the samples. Throws std::invalid_argument for a negative prior cost or shrink.
TermCounts fit_costs(const std::vector<CostSample>& samples, const TermCounts& prior,
                     double shrink = 0.05);

} // namespace fracdem::balance

#endif
