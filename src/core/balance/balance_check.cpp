// Check schedule, rank spread and imbalance trigger of fix balance/graph.
#include "balance/balance_check.h"

#include <algorithm>
#include <stdexcept>

namespace fracdem::balance
{

RankSpread rank_spread(double max, double sum, int nranks)
{
  RankSpread s;
  s.max = max, s.sum = sum, s.avg = sum / nranks;
  s.imbalance = s.avg > 0 ? max / s.avg : 1.0;
  return s;
}

RankSpread rank_spread(const std::vector<double>& per_rank)
{
  if (per_rank.empty()) throw std::invalid_argument("rank_spread: no ranks");
  double sum = 0;
  for (double v : per_rank)
    sum += v;
  const double max = *std::max_element(per_rank.begin(), per_rank.end());
  return rank_spread(max, sum, static_cast<int>(per_rank.size()));
}

CheckSchedule::CheckSchedule(int every) : every_(every)
{
  if (every < 1) throw std::invalid_argument("CheckSchedule: every must be >= 1");
}

void CheckSchedule::setup(long long step, bool start_balanced)
{
  const long long regular = regular_after(step);
  start_ = start_balanced;
  if (last_ < 0) last_ = step;
  next_ = start_ ? std::min(step + 1, regular) : regular;
}

CheckSchedule::Check CheckSchedule::take(long long step)
{
  Check c;
  c.start = start_;
  c.interval_steps = std::max<double>(1.0, static_cast<double>(step - last_));
  start_ = false;
  last_ = step;
  next_ = regular_after(step);
  return c;
}

} // namespace fracdem::balance
