// FeOnlyScene: turns atom sorting off for a run whose box has no particles and no cut-off.
#include "fe_only_scene.h"

#include <cstdio>

#include "atom.h"
#include "comm.h"
#include "fix.h"
#include "force.h"
#include "pair.h"

using namespace LAMMPS_NS;

namespace
{

// Atom::userbinsize (the bin size of 'atom_modify sort N BINSIZE') is private in LIGGGHTS 3.8.
// The explicit-instantiation access idiom names it without changing the host: explicit
// instantiations may refer to private members, and the friend defined in the instantiated
// template hands out the member pointer (the same idiom as in register_styles.cpp).
struct AtomUserBinsizeTag {
  using type = double Atom::*;
  friend type member_of(AtomUserBinsizeTag);
};

template <typename Tag, typename Tag::type Member> struct PrivateMemberAccess {
  friend typename Tag::type member_of(Tag) { return Member; }
};
template struct PrivateMemberAccess<AtomUserBinsizeTag, &Atom::userbinsize>;

} // namespace

FeOnlyScene::~FeOnlyScene()
{
  // Fixes are deleted before the Atom (LAMMPS::destroy), so atom is still valid here.
  if (atom) restore_sorting();
}

void FeOnlyScene::restore_sorting()
{
  // Put back the input's interval only if nothing changed it meanwhile ('atom_modify sort'
  // between runs sets a new value, which then stands).
  if (saved_sortfreq_ > 0 && atom->sortfreq == 0) atom->sortfreq = saved_sortfreq_;
  saved_sortfreq_ = 0;
}

// The condition of Atom::setup_sort_bins: sorting on, no user bin size, and a neighbour cut-off
// of zero. Neighbor::init sets cutneighmax after Fix::init, but it is zero exactly when there is
// no pair style or every pair cut-off is zero (neighbor.cpp adds the skin only to a non-zero
// cut-off), i.e. when Pair::cutforce, set by Pair::init before Fix::init, is zero.
bool FeOnlyScene::sort_bins_would_fail() const
{
  if (atom->sortfreq <= 0 || atom->*member_of(AtomUserBinsizeTag{}) > 0.0) return false;
  return !force->pair || force->pair->cutforce <= 0.0;
}

void FeOnlyScene::init(const Fix* owner)
{
  restore_sorting();
  if (atom->natoms > 0 || !sort_bins_would_fail()) return;
  saved_sortfreq_ = atom->sortfreq;
  atom->sortfreq = 0;
  if (comm->me == 0) {
    char line[256];
    snprintf(line, sizeof(line),
             "fix %s %s: no particles and no pair cut-off, atom sorting off for this run "
             "(as 'atom_modify sort 0 0.0')\n",
             owner->style, owner->id);
    if (screen) fputs(line, screen);
    if (logfile) fputs(line, logfile);
  }
}
