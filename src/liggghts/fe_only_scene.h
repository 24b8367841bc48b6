// FeOnlyScene: per-run host settings that let a box without particles run beside a fix fem/body.
#pragma once

#include "pointers.h"

namespace LAMMPS_NS
{

// LIGGGHTS 3.8 sorts atoms into bins of half the neighbour cut-off (Atom::setup_sort_bins) and
// stops with "Atom sorting has bin size = 0.0" when that cut-off is zero. In a box without
// particles it is zero: pair gran sizes it from particle radii (and from the radii that
// insertion fixes announce), and no pair style at all gives none. With no atoms sorting has
// nothing to do, so the run goes ahead with sorting off, which is what
// 'atom_modify sort 0 0.0' asks for. The input's own setting is put back at the next run that
// has particles or a cut-off, and when the owner is deleted.
//
// The owner (a fix fem/body) calls init() from its Fix::init(): that runs after Pair::init
// (the pair cut-off is known) and before Atom::setup (where the host would stop).
class FeOnlyScene : protected Pointers
{
public:
  explicit FeOnlyScene(LAMMPS* lmp) : Pointers(lmp) {}
  ~FeOnlyScene() override;
  FeOnlyScene(const FeOnlyScene&) = delete;
  FeOnlyScene& operator=(const FeOnlyScene&) = delete;

  // owner: the fix that calls, named in the note printed when sorting is switched off.
  void init(const class Fix* owner);

private:
  void restore_sorting();
  bool sort_bins_would_fail() const;
  int saved_sortfreq_ = 0; // > 0: the input's sort interval, while this object holds it at 0
};

} // namespace LAMMPS_NS
