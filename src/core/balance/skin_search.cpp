// Golden-section search of the neighbour skin on measured cost per step.
#include "balance/skin_search.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace fracdem::balance
{

namespace
{

const double kGolden = (std::sqrt(5.0) - 1.0) / 2.0; // 0.618...

} // namespace

std::string check_skin_search(const SkinSearchSettings& s)
{
  std::ostringstream out;
  if (!(s.lo > 0) || !std::isfinite(s.lo))
    out << "SKIN_MIN must be a number > 0 (got " << s.lo << ")";
  else if (!(s.hi > s.lo) || !std::isfinite(s.hi))
    out << "SKIN_MAX must be a number > SKIN_MIN = " << s.lo << " (got " << s.hi << ")";
  else if (!(s.tolerance > 0 && s.tolerance < 1))
    out << "the search tolerance must lie in (0, 1) (got " << s.tolerance << ")";
  else if (!(s.retune > 0))
    out << "the retune fraction must be > 0 (got " << s.retune << ")";
  else if (s.retune_intervals < 1)
    out << "the retune intervals must be >= 1 (got " << s.retune_intervals << ")";
  return out.str();
}

SkinSearch::SkinSearch(const SkinSearchSettings& s, double start) : s_(s)
{
  skin_ = std::clamp(start, s_.lo, s_.hi);
  ++searches_;
}

// The first interval only warms up (it holds the run's set-up and the first list build); the
// search proper starts at the inner points of the whole range.
void SkinSearch::begin_search()
{
  a_ = s_.lo;
  b_ = s_.hi;
  c_ = b_ - kGolden * (b_ - a_);
  d_ = a_ + kGolden * (b_ - a_);
  phase_ = Phase::Inner;
  skin_ = c_;
}

double SkinSearch::record(double cost)
{
  switch (phase_) {
  case Phase::First:
    begin_search();
    break;
  case Phase::Inner:
    fc_ = cost;
    phase_ = Phase::Outer;
    skin_ = d_;
    break;
  case Phase::Outer:
    fd_ = cost;
    phase_ = Phase::Narrow;
    skin_ = narrow();
    break;
  case Phase::Narrow:
    (new_is_c_ ? fc_ : fd_) = cost;
    skin_ = narrow();
    break;
  case Phase::Hold:
    drifted_ = std::abs(cost - held_cost_) > s_.retune * held_cost_ ? drifted_ + 1 : 0;
    if (drifted_ >= s_.retune_intervals) {
      ++searches_;
      begin_search();
    }
    break;
  }
  return skin_;
}

// One golden-section step with fc_ and fd_ known: drop the worse side, then either measure the
// new inner point or, once the bracket is narrow, hold the better of the two measured points.
double SkinSearch::narrow()
{
  if (fc_ <= fd_) {
    b_ = d_, d_ = c_, fd_ = fc_;
    c_ = b_ - kGolden * (b_ - a_);
    new_is_c_ = true;
  } else {
    a_ = c_, c_ = d_, fc_ = fd_;
    d_ = a_ + kGolden * (b_ - a_);
    new_is_c_ = false;
  }
  if (b_ - a_ > s_.tolerance * (s_.hi - s_.lo)) return new_is_c_ ? c_ : d_;
  // The point kept from the previous step is the best measured one in the bracket.
  phase_ = Phase::Hold;
  drifted_ = 0;
  held_cost_ = new_is_c_ ? fd_ : fc_;
  return new_is_c_ ? d_ : c_;
}

} // namespace fracdem::balance
