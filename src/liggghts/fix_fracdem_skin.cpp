// fix fracdem/skin: measures neighbour, pair and communication time per step every N steps and
// moves the skin towards their least sum; the new skin takes effect at the next list rebuild.
#include "fix_fracdem_skin.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <ctime>

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "modify.h"
#include "neighbor.h"
#include "pair.h"
#include "timer.h"
#include "update.h"

#include "fix_balance_graph.h"
#include "pair_fracdem_gran.h"

using namespace LAMMPS_NS;
using namespace FixConst;
namespace fb = fracdem::balance;

namespace
{

// Neighbor keeps the derived cut-offs of the skin protected; a class derived from it may name
// them, and the member pointers it hands out apply to the host's Neighbor object.
struct NeighborCuts : Neighbor {
  static double** Neighbor::*cutneighsq_of() { return &NeighborCuts::cutneighsq; }
  static double** Neighbor::*cutneighghostsq_of() { return &NeighborCuts::cutneighghostsq; }
  static double* Neighbor::*cuttypesq_of() { return &NeighborCuts::cuttypesq; }
  static double Neighbor::*cutneighmaxsq_of() { return &NeighborCuts::cutneighmaxsq; }
  static double Neighbor::*triggersq_of() { return &NeighborCuts::triggersq; }
};

constexpr const char* kSyntax =
    "expected 'fix ID all fracdem/skin N SKIN_MIN SKIN_MAX [clock cpu|wall]'";

double number(const char* s, bool& ok)
{
  char* end = nullptr;
  const double v = std::strtod(s, &end);
  ok = end != s && *end == '\0';
  return v;
}

} // namespace

FixFracdemSkin::FixFracdemSkin(LAMMPS* lmp, int narg, char** arg) : Fix(lmp, narg, arg)
{
  if (narg != 6 && narg != 8) fail(kSyntax);
  if (narg == 8) {
    if (std::strcmp(arg[6], "clock") != 0)
      fail(std::string("unknown keyword '") + arg[6] + "'; " + kSyntax);
    if (std::strcmp(arg[7], "cpu") != 0 && std::strcmp(arg[7], "wall") != 0)
      fail(std::string("keyword 'clock': expected 'cpu' or 'wall', got '") + arg[7] + "'");
    wall_clock_ = std::strcmp(arg[7], "wall") == 0;
  }
  bool ok = false;
  const double every = number(arg[3], ok);
  if (!ok || every < 1 || every != std::floor(every) || every > 1e9)
    fail(std::string("N must be a whole number of steps >= 1 (got '") + arg[3] + "'); " + kSyntax);
  nevery = static_cast<int>(every);
  settings_.lo = number(arg[4], ok);
  if (!ok) fail(std::string("SKIN_MIN '") + arg[4] + "' is not a number; " + kSyntax);
  settings_.hi = number(arg[5], ok);
  if (!ok) fail(std::string("SKIN_MAX '") + arg[5] + "' is not a number; " + kSyntax);
  const std::string bad = fb::check_skin_search(settings_);
  if (!bad.empty()) fail(bad);
  search_ = std::make_unique<fb::SkinSearch>(settings_, neighbor->skin);
  scalar_flag = 1;
  vector_flag = 1;
  size_vector = 3;
  global_freq = 1;
  extscalar = 0;
  extvector = 0;
  restart_global = 1;
  // A new skin is taken at a rebuild forced on the next step, so that the interval measured
  // next is the new skin's.
  force_reneighbor = 1;
  next_reneighbor = -1;
}

FixFracdemSkin::~FixFracdemSkin() = default;

void FixFracdemSkin::fail(const std::string& msg) const
{
  error->all(FLERR, ("fix fracdem/skin: " + msg).c_str());
}

int FixFracdemSkin::setmask()
{
  return PRE_EXCHANGE | END_OF_STEP;
}

// The paper's rule for a medium-range interaction: no skin the search may choose is below the
// reach of the pair style's bridges.
void FixFracdemSkin::check_bridges() const
{
  const auto* pair = dynamic_cast<const PairFracdemGran*>(force->pair);
  if (!pair || settings_.lo >= pair->bridge_reach()) return;
  char msg[400];
  std::snprintf(msg, sizeof msg,
                "SKIN_MIN %.6g is below the bridge rupture distance %.6g of pair_style "
                "fracdem/gran, so a list rebuild at that skin would lose bridges; write SKIN_MIN "
                "%.3g or more",
                settings_.lo, pair->bridge_reach(),
                PairFracdemGran::skin_to_write(pair->bridge_reach()));
  fail(msg);
}

// fix balance/graph reads the lists and forwards over the ghost pattern in its pre_exchange; a
// new skin resets that pattern, so it must come after.
void FixFracdemSkin::check_order() const
{
  bool me_first = false;
  for (int i = 0; i < modify->nfix; ++i) {
    if (modify->fix[i] == this) me_first = true;
    if (me_first && dynamic_cast<FixBalanceGraph*>(modify->fix[i]))
      fail(std::string("fix ") + modify->fix[i]->id +
           " (balance/graph) must be defined before this fix: define fix " + id +
           " after it (a new skin resets the ghost pattern that balance/graph uses first)");
  }
}

// Meshes spread over several ranks take their ghost reach from the cut-off at set-up.
bool FixFracdemSkin::meshes_on_ranks() const
{
  if (comm->nprocs == 1) return false;
  for (int i = 0; i < modify->nfix; ++i)
    if (std::strncmp(modify->fix[i]->style, "mesh/surface", 12) == 0) return true;
  return false;
}

// Runs before the host's Neighbor::init, which derives the cut-offs from neighbor->skin.
void FixFracdemSkin::init()
{
  if (neighbor->style == 2) fail("needs 'neighbor SKIN bin' or 'nsq', not 'multi'");
  check_bridges();
  check_order();
  if (restored_ > 0) {
    search_ = std::make_unique<fb::SkinSearch>(settings_, restored_);
    restored_ = -1;
  }
  const double skin = search_->skin();
  pending_ = -1;
  if (meshes_on_ranks() && skin < settings_.hi) {
    // Set up at SKIN_MAX, so that the mesh's ghosts cover every skin; the search's skin follows
    // at the first rebuild.
    neighbor->skin = settings_.hi;
    pending_ = skin;
    next_reneighbor = update->ntimestep + 1;
  } else {
    neighbor->skin = skin;
  }
}

void FixFracdemSkin::setup(int)
{
  run_start_ = true;
  step_last_ = update->ntimestep;
  if (!wall_clock_) seconds_last_ = measured_seconds();
}

// clock wall: the three parts of a step that the skin changes (neighbour build, pair, comm), from
// the host's wall-clock timers, which it zeroes after the run's set-up. clock cpu: this process's
// CPU time, all of the step (on a shared machine wall time counts the neighbours' work too).
// Averaged over the ranks.
double FixFracdemSkin::measured_seconds() const
{
  double mine = 0;
  if (wall_clock_) {
    mine = timer->array[TIME_NEIGHBOR] + timer->array[TIME_PAIR] + timer->array[TIME_COMM];
  } else {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    mine = ts.tv_sec + 1e-9 * ts.tv_nsec;
  }
  double sum = 0;
  MPI_Allreduce(&mine, &sum, 1, MPI_DOUBLE, MPI_SUM, world);
  return sum / comm->nprocs;
}

void FixFracdemSkin::end_of_step()
{
  const double now = measured_seconds();
  if (run_start_ && wall_clock_) seconds_last_ = 0; // zeroed after this fix's set-up
  run_start_ = false;
  const bigint steps = update->ntimestep - step_last_;
  const double seconds = now - seconds_last_;
  seconds_last_ = now;
  step_last_ = update->ntimestep;
  if (steps <= 0) return;
  last_cost_ = seconds / static_cast<double>(steps);
  const double old = neighbor->skin;
  // Per particle: insertion and outflow change the time per step without changing which skin
  // is best, and must not make a held skin look drifted.
  const double next = search_->record(last_cost_ / std::max<double>(1.0, atom->natoms));
  if (next == old) return;
  pending_ = next;
  next_reneighbor = update->ntimestep + 1;
  if (comm->me != 0) return;
  char line[300];
  std::snprintf(line, sizeof line,
                "fix fracdem/skin: step " BIGINT_FORMAT ": skin %.6g -> %.6g from the next "
                "step (measured %.4g ms per step of %s over %d steps%s)\n",
                update->ntimestep, old, next, 1e3 * last_cost_,
                wall_clock_ ? "neighbour + pair + comm wall time" : "CPU time",
                static_cast<int>(steps), search_->searching() ? ", searching" : ", held");
  if (screen) fputs(line, screen);
  if (logfile) fputs(line, logfile);
}

// The host rebuilds the lists right after pre_exchange: exchange and borders with the new ghost
// cut-off, then the build with the new skin. Until then the old lists and the old trigger hold,
// so no pair is missed on either side of the change.
void FixFracdemSkin::pre_exchange()
{
  if (pending_ <= 0) return;
  next_reneighbor = -1;
  apply_skin(pending_);
  pending_ = -1;
  ++changes_;
}

// What Neighbor::init derives from the skin, and the ghost cut-off and bins derived from those.
void FixFracdemSkin::apply_skin(double skin)
{
  Neighbor* nb = neighbor;
  nb->skin = skin;
  nb->*NeighborCuts::triggersq_of() = 0.25 * skin * skin;
  double** cutsq = nb->*NeighborCuts::cutneighsq_of();
  double** ghostsq = nb->*NeighborCuts::cutneighghostsq_of();
  double* typesq = nb->*NeighborCuts::cuttypesq_of();
  const int n = atom->ntypes;
  Pair* pair = force->pair;
  nb->cutneighmin = 1e20;
  nb->cutneighmax = 0;
  for (int i = 1; i <= n; ++i) {
    nb->cuttype[i] = typesq[i] = 0;
    for (int j = 1; j <= n; ++j) {
      const double cutoff = pair ? std::sqrt(pair->cutsq[i][j]) : 0.0;
      const double cut = cutoff > 0 ? cutoff + skin : 0.0;
      cutsq[i][j] = cut * cut;
      nb->cuttype[i] = std::max(nb->cuttype[i], cut);
      typesq[i] = std::max(typesq[i], cut * cut);
      nb->cutneighmin = std::min(nb->cutneighmin, cut);
      nb->cutneighmax = std::max(nb->cutneighmax, cut);
      const double ghost = pair && pair->ghostneigh ? pair->cutghost[i][j] + skin : cut;
      ghostsq[i][j] = ghost * ghost;
    }
  }
  nb->*NeighborCuts::cutneighmaxsq_of() = nb->cutneighmax * nb->cutneighmax;
  if (atom->radius_flag) {
    double maxrad = 0, minrad = 0;
    modify->max_min_rad(maxrad, minrad);
    nb->cutneighmin = std::min(nb->cutneighmin, 2 * minrad + skin);
  }
  comm->setup();
  if (nb->style) nb->setup_bins();
}

// The skin of the coming steps (a change decided at this step's end is taken at the next).
double FixFracdemSkin::compute_scalar()
{
  return pending_ > 0 ? pending_ : neighbor->skin;
}

// 1: the last interval's seconds per step, 2: skin changes this run, 3: searches begun.
double FixFracdemSkin::compute_vector(int n)
{
  if (n == 0) return last_cost_;
  if (n == 1) return changes_;
  return search_->searches();
}

// The skin in use, so that a restarted run goes on from it (the search starts anew there).
void FixFracdemSkin::write_restart(FILE* fp)
{
  if (comm->me != 0) return;
  const double skin = pending_ > 0 ? pending_ : neighbor->skin;
  const int size = sizeof(double);
  std::fwrite(&size, sizeof(int), 1, fp);
  std::fwrite(&skin, sizeof(double), 1, fp);
}

void FixFracdemSkin::restart(char* buf)
{
  std::memcpy(&restored_, buf, sizeof(double));
}
