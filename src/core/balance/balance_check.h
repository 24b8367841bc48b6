// When fix balance/graph checks and when a check repartitions: the check schedule, the spread of
// a per-rank quantity and the imbalance trigger B > tau.
#ifndef FRACDEM_BALANCE_BALANCE_CHECK_H
#define FRACDEM_BALANCE_BALANCE_CHECK_H

#include <vector>

namespace fracdem::balance
{

// max, sum, average and max/avg over the ranks of one per-rank quantity (work, time, ghosts).
struct RankSpread {
  double max = 0, sum = 0, avg = 0;
  double imbalance = 1.0; // max / avg; 1 when the average is not positive
};
RankSpread rank_spread(double max, double sum, int nranks);
// Throws std::invalid_argument for no ranks.
RankSpread rank_spread(const std::vector<double>& per_rank);

// The paper's trigger B > tau with thresh = 1 + tau, on B = max/avg of the ranks' work: fires
// exactly when the imbalance exceeds the threshold, and never on one rank (nothing to balance).
struct ImbalanceTrigger {
  double threshold = 1.0;
  bool fires(double imbalance, int nranks) const { return nranks > 1 && imbalance > threshold; }
};

// Checks fall on the multiples of `every`; a run that must start balanced (more than one rank,
// ownership still the host's) checks once more at its first step, on the model costs, since
// nothing has been timed yet.
class CheckSchedule
{
public:
  // Throws std::invalid_argument unless every >= 1.
  explicit CheckSchedule(int every);
  int every() const { return every_; }
  // The first regular check after `step`.
  long long regular_after(long long step) const { return (step / every_) * every_ + every_; }
  // At the set-up of a run at `step`: schedules its first check; the first set-up also starts
  // the interval the first check measures.
  void setup(long long step, bool start_balanced);
  long long next() const { return next_; }
  // The step of the last check (-1: none yet); a run continued from a restart file resumes from
  // it (before its set-up), so that its first check measures the same interval.
  long long last_check() const { return last_; }
  void resume(long long last_check) { last_ = last_check; }
  bool due(long long step) const { return step == next_; }

  struct Check {
    bool start = false;        // the start check of a run
    double interval_steps = 1; // steps since the previous check (at least 1)
  };
  // At a due check at `step`: what it is, and the next one scheduled.
  Check take(long long step);

private:
  int every_;
  long long next_ = -1, last_ = -1;
  bool start_ = false;
};

} // namespace fracdem::balance

#endif
