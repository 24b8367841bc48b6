// compute fracdem/cost: per-particle a posteriori cost for LAMMPS's fix balance (weight var).
#include "compute_fracdem_cost.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"
#include "utils.h"

#include "balance/cost_model.h"
#include "balance_exchange.h"
#include "io/input_help.h"

#include "fix_fem_body_lammps.h"

using namespace LAMMPS_NS;
using namespace FixConst;

/* ----------------------------------------------------------------------
   FixFracdemCost: the recording (internal fix, style FRACDEM/COST)
------------------------------------------------------------------------- */

FixFracdemCost::FixFracdemCost(LAMMPS* lmp, int narg, char** arg) : Fix(lmp, narg, arg)
{
  if (narg != 3) error->all(FLERR, "Illegal fix FRACDEM/COST command (internal to fracdem/cost)");
  nevery = 1;
  maxexchange = 2;
  comm_reverse = 1;
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  for (int i = 0; i < atom->nlocal; ++i)
    set_arrays(i);
}

FixFracdemCost::~FixFracdemCost()
{
  atom->delete_callback(id, Atom::GROW);
  memory->destroy(sums_);
}

int FixFracdemCost::setmask()
{
  return END_OF_STEP;
}

void FixFracdemCost::init()
{
  if (!atom->radius_flag)
    error->all(FLERR, "compute fracdem/cost requires atom attribute radius (atom_style sphere)");
  // Its own half list with radius-sized cutoffs (the one pair granular asks for, less the
  // history; LAMMPS copies it from the pair's list when they match).
  neighbor->add_request(this, NeighConst::REQ_SIZE);
  bodies_.clear();
  for (Fix* f : modify->get_fix_by_style("^fem/body$"))
    if (auto* b = dynamic_cast<FixFemBodyLammps*>(f)) bodies_.push_back(b);
}

void FixFracdemCost::init_list(int, NeighList* ptr)
{
  list_ = ptr;
}

void FixFracdemCost::setup(int)
{
  run_work = 0;
  run_steps = 0;
}

void FixFracdemCost::end_of_step()
{
  // A fix balance check at step s (pre_exchange, before the forces of step s) reads the steps
  // s - window .. s - 1; step s opens the next window.
  const bigint step = update->ntimestep;
  if (window > 0 && step % window == 0 && window_start_ != step) {
    for (int i = 0; i < atom->nlocal; ++i)
      set_arrays(i);
    window_work = 0;
    window_steps = 0;
    window_start_ = step;
  }
  record();
}

// What this step did for each particle (paper section 5.1): the particle itself, its potential
// pairs in the neighbour list, those in contact (overlap > 0), its facet checks and contacts with
// fix fem/body surfaces. A pair's check and contact cost half to each of its two particles, so a
// particle's cost does not depend on which of the two holds the pair in the half list (and thus
// not on the decomposition); the sum over all particles is the model's total work.
void FixFracdemCost::record()
{
  const int nlocal = atom->nlocal;
  const bool newton = force->newton_pair != 0;
  const int nall = nlocal + (newton ? atom->nghost : 0);
  step_cost_.assign(nall, 0.0);
  for (int i = 0; i < nlocal; ++i)
    step_cost_[i] = weights.particle;

  if (list_ && list_->ilist) {
    double** x = atom->x;
    const double* radius = atom->radius;
    for (int ii = 0; ii < list_->inum; ++ii) {
      const int i = list_->ilist[ii];
      if (i >= nlocal) continue;
      const int* jlist = list_->firstneigh[i];
      const int jnum = list_->numneigh[i];
      for (int jj = 0; jj < jnum; ++jj) {
        const int j = jlist[jj] & NEIGHMASK;
        const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
        const double rs = radius[i] + radius[j];
        const double w =
            fracdem::balance::half_pair_cost(weights, dx * dx + dy * dy + dz * dz < rs * rs);
        step_cost_[i] += w;
        // newton on: the pair is in one rank's list only, the ghost's half goes to its owner by
        // reverse communication; newton off: the owner of j holds the pair too and adds its half.
        if (j < nlocal || newton) step_cost_[j] += w;
      }
    }
  }
  if (newton) comm->reverse_comm(this);

  for (FixFemBodyLammps* b : bodies_) {
    const auto& checks = b->contact().checks();
    const auto& contacts = b->contact().contacts();
    if (static_cast<int>(checks.size()) != nlocal || contacts.size() != checks.size())
      continue; // no contact evaluated this step (no `contact` keyword)
    for (int i = 0; i < nlocal; ++i)
      step_cost_[i] += weights.facet_check * checks[i] + weights.facet_contact * contacts[i];
  }

  double local = 0;
  for (int i = 0; i < nlocal; ++i) {
    sums_[i][0] += step_cost_[i];
    sums_[i][1] += 1;
    local += step_cost_[i];
  }
  window_work += local;
  run_work += local;
  ++window_steps;
  ++run_steps;
}

double FixFracdemCost::mean_cost(int i) const
{
  return sums_[i][1] > 0 ? sums_[i][0] / sums_[i][1] : weights.particle;
}

void FixFracdemCost::grow_arrays(int nmax)
{
  memory->grow(sums_, nmax, 2, "fracdem/cost:sums");
}

void FixFracdemCost::copy_arrays(int i, int j, int)
{
  sums_[j][0] = sums_[i][0];
  sums_[j][1] = sums_[i][1];
}

void FixFracdemCost::set_arrays(int i)
{
  sums_[i][0] = sums_[i][1] = 0.0;
}

int FixFracdemCost::pack_exchange(int i, double* buf)
{
  buf[0] = sums_[i][0];
  buf[1] = sums_[i][1];
  return 2;
}

int FixFracdemCost::unpack_exchange(int nlocal, double* buf)
{
  sums_[nlocal][0] = buf[0];
  sums_[nlocal][1] = buf[1];
  return 2;
}

int FixFracdemCost::pack_reverse_comm(int n, int first, double* buf)
{
  for (int i = first; i < first + n; ++i)
    buf[i - first] = step_cost_[i];
  return n;
}

void FixFracdemCost::unpack_reverse_comm(int n, int* list, double* buf)
{
  for (int k = 0; k < n; ++k)
    step_cost_[list[k]] += buf[k];
}

double FixFracdemCost::memory_usage()
{
  return 2.0 * sizeof(double) * atom->nmax + sizeof(double) * step_cost_.capacity();
}

/* ----------------------------------------------------------------------
   ComputeFracdemCost: compute ID group fracdem/cost [cost NAME C ...] [every N]
------------------------------------------------------------------------- */

namespace
{
constexpr int kVectorSize = 9;
using Costs = fracdem::balance::InteractionCosts;
// The compute's names of the recorded items and the work model's terms they price.
constexpr int kNamedCosts = 5;
const char* const kCostNames[kNamedCosts] = {"base", "check", "pair", "facet_check", "facet"};
double Costs::*const kCostFields[kNamedCosts] = {&Costs::particle, &Costs::pair_check,
                                                 &Costs::sphere_contact, &Costs::facet_check,
                                                 &Costs::facet_contact};
} // namespace

double ComputeFracdemCost::number(const char* keyword, const char* word)
{
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(word, &end);
  if (end == word || *end != '\0' || errno != 0 || !(v >= 0))
    error->all(FLERR, "compute fracdem/cost: keyword '{}' expects a non-negative number, got '{}'",
               keyword, word);
  return v;
}

// `cost NAME C ...` from arg[iarg + 1] on: the costs given (given[k]); returns the next argument.
int ComputeFracdemCost::parse_costs(int iarg, int narg, char** arg, bool given[])
{
  ++iarg;
  int pairs = 0;
  while (iarg + 1 < narg) {
    int k = 0;
    while (k < kNamedCosts && std::strcmp(arg[iarg], kCostNames[k]) != 0)
      ++k;
    if (k == kNamedCosts) break;
    weights_.*kCostFields[k] = number(kCostNames[k], arg[iarg + 1]);
    given[k] = true;
    iarg += 2;
    ++pairs;
  }
  if (pairs == 0)
    error->all(FLERR, "compute fracdem/cost: keyword 'cost' expects NAME C pairs (NAME: base, "
                      "check, pair, facet_check, facet)");
  return iarg;
}

ComputeFracdemCost::ComputeFracdemCost(LAMMPS* lmp, int narg, char** arg) : Compute(lmp, narg, arg)
{
  bool given[kNamedCosts] = {false, false, false, false, false};
  int iarg = 3;
  while (iarg < narg) {
    const std::string key = arg[iarg];
    if (key == "cost") {
      iarg = parse_costs(iarg, narg, arg, given);
    } else if (key == "every") {
      if (iarg + 1 >= narg) error->all(FLERR, "compute fracdem/cost: keyword 'every' needs N");
      const double v = number("every", arg[iarg + 1]);
      if (v != static_cast<double>(static_cast<bigint>(v)))
        error->all(FLERR, "compute fracdem/cost: keyword 'every' expects a whole number");
      every_ = static_cast<bigint>(v);
      iarg += 2;
    } else {
      error->all(FLERR, "compute fracdem/cost: unknown keyword '{}' (expected cost or every){}",
                 key, fracdem::did_you_mean(key, {"cost", "every"}));
    }
  }
  // Costs not given: fix balance/graph's calibrated ones (a micro-benchmark of the kernels,
  // relative to one pair check), measured on rank 0 and shared so all ranks weigh alike.
  const bool all_given = std::all_of(given, given + kNamedCosts, [](bool g) { return g; });
  if (!all_given) {
    const Costs calibrated = fracdem::balance::shared_calibrated_costs(world);
    for (int k = 0; k < kNamedCosts; ++k)
      if (!given[k]) weights_.*kCostFields[k] = calibrated.*kCostFields[k];
  }
  if (comm->me == 0)
    utils::logmesg(lmp,
                   "compute fracdem/cost {}: relative costs{}: base {:.3g}, check {:.3g}, pair "
                   "{:.3g}, facet_check {:.3g}, facet {:.3g}\n",
                   id, all_given ? "" : " (calibrated unless given)", weights_.particle,
                   weights_.pair_check, weights_.sphere_contact, weights_.facet_check,
                   weights_.facet_contact);

  peratom_flag = 1;
  size_peratom_cols = 0;
  vector_flag = 1;
  size_vector = kVectorSize;
  extvector = 0;
  vector = new double[kVectorSize];

  id_fix_ = std::string(id) + "_FRACDEM_COST";
  fix_ = dynamic_cast<FixFracdemCost*>(modify->add_fix(id_fix_ + " all FRACDEM/COST"));
  if (!fix_) error->all(FLERR, "compute fracdem/cost: could not create its internal fix");
  fix_->weights = weights_;
}

ComputeFracdemCost::~ComputeFracdemCost()
{
  if (modify && modify->nfix && modify->get_fix_by_id(id_fix_)) modify->delete_fix(id_fix_);
  memory->destroy(cost_);
  delete[] vector;
}

void ComputeFracdemCost::init()
{
  fix_ = dynamic_cast<FixFracdemCost*>(modify->get_fix_by_id(id_fix_));
  if (!fix_) error->all(FLERR, "compute fracdem/cost {}: its internal fix is gone", id);
  bigint window = every_;
  if (window < 0) {
    window = 0;
    const auto balances = modify->get_fix_by_style("^balance$");
    if (!balances.empty()) window = balances.front()->nevery;
  }
  fix_->window = window;
}

void ComputeFracdemCost::compute_peratom()
{
  invoked_peratom = update->ntimestep;
  if (atom->nmax > nmax_) {
    memory->destroy(cost_);
    nmax_ = atom->nmax;
    memory->create(cost_, nmax_, "fracdem/cost:cost");
    vector_atom = cost_;
  }
  const int* mask = atom->mask;
  for (int i = 0; i < atom->nlocal; ++i)
    cost_[i] = (mask[i] & groupbit) ? fix_->mean_cost(i) : 0.0;
}

// 1: imbalance (max/avg over ranks) of the recorded work in the current window, 2: of the work
// recorded in this run, 3, 4: max and average per rank of the latter, per step; 5-9: the
// relative costs (base, check, pair, facet_check, facet).
void ComputeFracdemCost::compute_vector()
{
  invoked_vector = update->ntimestep;
  const double mine[2] = {fix_->window_work, fix_->run_work};
  double max[2], sum[2];
  MPI_Allreduce(mine, max, 2, MPI_DOUBLE, MPI_MAX, world);
  MPI_Allreduce(mine, sum, 2, MPI_DOUBLE, MPI_SUM, world);
  const double n = comm->nprocs;
  vector[0] = sum[0] > 0 ? max[0] * n / sum[0] : 1.0;
  vector[1] = sum[1] > 0 ? max[1] * n / sum[1] : 1.0;
  const double steps = fix_->run_steps > 0 ? static_cast<double>(fix_->run_steps) : 1.0;
  vector[2] = max[1] / steps;
  vector[3] = sum[1] / n / steps;
  for (int k = 0; k < kNamedCosts; ++k)
    vector[4 + k] = weights_.*kCostFields[k];
}

double ComputeFracdemCost::memory_usage()
{
  return sizeof(double) * nmax_;
}
