// The neighbour skin that minimises the measured time per step: a golden-section search within
// bounds on a cost measured one interval at a time, which holds its result until the cost drifts.
#ifndef FRACDEM_BALANCE_SKIN_SEARCH_H
#define FRACDEM_BALANCE_SKIN_SEARCH_H

#include <string>

namespace fracdem::balance
{

struct SkinSearchSettings {
  double lo = 0, hi = 0; // bounds of the skin
  // The search stops when its bracket is narrower than this fraction of hi - lo.
  double tolerance = 0.05;
  // Held skin: a cost that moves by more than this fraction from the one it was chosen on, in
  // this many intervals in a row (the scene changed: particles slowed, packed, flowed; a single
  // slow interval is the machine), starts a new search.
  double retune = 0.25;
  int retune_intervals = 3;
};

// Checks bounds and tolerances; returns "" or what is wrong, naming the argument.
std::string check_skin_search(const SkinSearchSettings& s);

// One skin per interval: the host runs an interval at skin(), measures its cost per step and
// hands it to record(), which returns the skin of the next interval. The cost is assumed
// unimodal in the skin (few rebuilds of large lists against many rebuilds of short ones); a
// noisy cost only makes the choice less sharp, it never leaves the bounds.
class SkinSearch
{
public:
  // start: the skin of the first interval (clamped into the bounds).
  SkinSearch(const SkinSearchSettings& s, double start);

  double skin() const { return skin_; }
  bool searching() const { return phase_ != Phase::Hold; }
  int searches() const { return searches_; } // searches begun, the first included

  // The cost per step of the interval just run at skin(); returns the next skin.
  double record(double cost);

private:
  enum class Phase { First, Inner, Outer, Narrow, Hold };
  void begin_search();
  double narrow();

  SkinSearchSettings s_;
  Phase phase_ = Phase::First;
  double skin_ = 0;
  double a_ = 0, b_ = 0, c_ = 0, d_ = 0; // bracket [a, b], inner points c < d
  double fc_ = 0, fd_ = 0;               // their measured costs
  bool new_is_c_ = true;                 // Narrow: which inner point skin() measures
  double held_cost_ = 0;                 // Hold: the cost the held skin was chosen on
  int drifted_ = 0;                      // Hold: intervals in a row beyond the retune fraction
  int searches_ = 0;
};

} // namespace fracdem::balance

#endif
