// fix balance/graph: measures per-rank work from the host's neighbour list and contacts, and
// repartitions the particle graph with METIS when max/avg exceeds the threshold.
#include "fix_balance_graph.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <unordered_map>

#include "atom.h"
#include "balance/compact_partition.h"
#include "balance/graph_partition.h"
#include "balance/layered_partition.h"
#include "balance/scotch_partition.h"
#include "io/input_help.h"
#include "comm.h"
#include "comm_graph.h"
#include "domain.h"
#include "error.h"
#include "fix_fem_body.h"
#include "fix_gravity.h"
#include "fix_wall_gran.h"
#include "force.h"
#include "modify.h"
#include "neigh_list.h"
#include "output.h"
#include "pair.h"
#include "primitive_wall.h"
#include "region.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;

namespace
{

// Sub-models by keyword: one table each, so the parser and the error messages list the same names.
template <typename T> struct KeywordEntry {
  const char* name;
  T value;
};
const KeywordEntry<FixBalanceGraph::GraphModel> kGraphModels[] = {
    {"apriori", FixBalanceGraph::GraphModel::APriori},
    {"aposteriori", FixBalanceGraph::GraphModel::APosteriori}};
const KeywordEntry<FixBalanceGraph::CostModel> kCostModels[] = {
    {"counts", FixBalanceGraph::CostModel::Counts},
    {"calibrated", FixBalanceGraph::CostModel::Calibrated},
    {"timed", FixBalanceGraph::CostModel::Timed},
    {"fitted", FixBalanceGraph::CostModel::Fitted}};
const KeywordEntry<FixBalanceGraph::Strategy> kStrategies[] = {
    {"auto", FixBalanceGraph::Strategy::Auto},
    {"refine", FixBalanceGraph::Strategy::Refine},
    {"scratch", FixBalanceGraph::Strategy::Scratch}};

// Looks `value` up in a table; on failure `expected` lists the table's names ("a, b or c", or
// "a or b or c" with alternatives: each name is a choice of its own, not one of a series).
template <typename T, size_t N>
bool lookup(const KeywordEntry<T> (&table)[N], const std::string& value, T& out,
            std::string& expected, bool alternatives = false)
{
  for (const auto& e : table)
    if (value == e.name) {
      out = e.value;
      return true;
    }
  expected.clear();
  for (size_t k = 0; k < N; ++k)
    expected += std::string(k == 0                       ? ""
                            : k + 1 == N || alternatives ? " or "
                                                         : ", ") +
                table[k].name;
  return false;
}

const KeywordEntry<FixBalanceGraph::Partitioner> kPartitioners[] = {
    {"metis", FixBalanceGraph::Partitioner::Metis},
    {"scotch", FixBalanceGraph::Partitioner::Scotch},
    {"rcb", FixBalanceGraph::Partitioner::Rcb},
    {"layers", FixBalanceGraph::Partitioner::Layers}};

double thread_cpu_seconds()
{
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

constexpr double kMetisImbalanceTolerance = 1.02;
// `repartition auto` diffuses from the current owners below this imbalance of the graph weights,
// and partitions from scratch above it (diffusion from a far-off start degrades part shapes).
constexpr double kRefineBelow = 1.5;
constexpr int kRefinePasses = 64;
// partitioner scotch: cost of moving one unit of vertex weight against cutting one unit of edge
// weight. A particle of average cost weighs kWeightResolution and a contact edge a few units, so
// moving a particle costs about as much as cutting the edges of a few neighbours.
constexpr double kScotchMigrationCost = 0.1;
constexpr double kWeightResolution = 100.0; // integer vertex weight of a particle of average cost
// cost fitted: samples of this many checks enter the fit (older ones are dropped: the costs drift
// as the scene changes), shrunk towards the calibrated ratios with this strength.
constexpr int kFitWindowChecks = 8;
constexpr double kFitShrink = 0.05;

} // namespace

FixBalanceGraph::FixBalanceGraph(LAMMPS* lmp, int narg, char** arg) : Fix(lmp, narg, arg)
{
  auto fail = [&](const std::string& msg) {
    error->all(FLERR, ("fix balance/graph: " + msg).c_str());
  };
  if (narg < 5) fail("expected 'fix ID all balance/graph Nevery thresh [keyword value ...]'");
  // Particle ownership is one per run: two balancers would each impose their own partition at
  // every check. Re-issuing the same ID replaces the fix (its slot is empty while this one is
  // built), which is allowed.
  for (int i = 0; i < modify->nfix; ++i) {
    const auto* other = dynamic_cast<const FixBalanceGraph*>(modify->fix[i]);
    if (other && strcmp(other->id, arg[0]) != 0)
      fail(std::string("fix ") + arg[0] + ": fix " + other->id +
           " is a balance/graph already and only one may be defined (re-issue 'fix " + other->id +
           " all balance/graph ...' to change it, or 'unfix " + other->id + "' first)");
  }
  if (strcmp(arg[1], "all") != 0) fail("group must be 'all' (every particle is balanced)");
  char* end = nullptr;
  errno = 0;
  const long long every = strtoll(arg[3], &end, 10);
  check_every_ = every > 0 && every <= INT_MAX ? static_cast<int>(every) : 0; // no silent wrap
  if (end == arg[3] || *end || errno == ERANGE || check_every_ <= 0)
    fail(std::string("Nevery must be a positive integer, got '") + arg[3] + "'");
  threshold_ = strtod(arg[4], &end);
  if (end == arg[4] || *end || !std::isfinite(threshold_) || !(threshold_ >= 1.0))
    fail(std::string("thresh must be a number >= 1.0 (max/avg work), got '") + arg[4] + "'");

  std::vector<std::string> seen;
  for (int iarg = 5; iarg < narg; iarg += 2) {
    const std::string key = arg[iarg];
    if (iarg + 1 >= narg) fail("keyword '" + key + "' needs a value");
    if (key != "insert_region") {
      if (std::find(seen.begin(), seen.end(), key) != seen.end())
        fail("keyword '" + key + "' given twice");
      seen.push_back(key);
    }
    const std::string val = arg[iarg + 1];
    std::string expected;
    if (key == "model") {
      if (!lookup(kGraphModels, val, graph_model_, expected))
        fail("keyword 'model': expected " + expected + ", got '" + val + "'");
    } else if (key == "cost") {
      if (!lookup(kCostModels, val, cost_model_, expected))
        fail("keyword 'cost': expected " + expected + ", got '" + val + "'");
    } else if (key == "partitioner") {
      if (!lookup(kPartitioners, val, partitioner_, expected, true))
        fail("keyword 'partitioner': expected " + expected + ", got '" + val + "'");
    } else if (key == "repartition") {
      if (!lookup(kStrategies, val, strategy_, expected))
        fail("keyword 'repartition': expected " + expected + ", got '" + val + "'");
    } else if (key == "insert_region") {
      insert_regions_.push_back(val);
    } else if (key == "cells") {
      cell_factor_ = strtod(val.c_str(), &end);
      if (*end || !(cell_factor_ == 0.0 || cell_factor_ >= 1.0))
        fail("keyword 'cells': expected 0 (one vertex per particle) or a cell edge >= 1 in ghost "
             "cutoffs, got '" +
             val + "'");
    } else if (key == "out") {
      if (comm->me == 0) {
        out_ = fopen(val.c_str(), "w");
        if (!out_) fail("keyword 'out': cannot open '" + val + "' for writing");
        fprintf(out_, "step,imbalance,repartitioned,predicted_imbalance,migrated,partition_seconds,"
                      "migration_seconds_total,ghost_max_over_avg,ghosts_total,edge_cut,natoms,"
                      "work_max,work_avg,measured_imbalance,cpu_work_max,cpu_work_avg");
        // Per-rank CPU work of each interval, for per-rank work plots.
        for (int p = 0; p < comm->nprocs; ++p)
          fprintf(out_, ",cpu_rank%d", p);
        fputc('\n', out_);
      }
    } else {
      fail("unknown keyword '" + key +
           "' (expected model, cost, partitioner, repartition, cells, insert_region or out)" +
           fracdem::did_you_mean(key, {"model", "cost", "partitioner", "repartition", "cells",
                                       "insert_region", "out"}));
    }
  }

  if (partitioner_ == Partitioner::Scotch &&
      std::find(seen.begin(), seen.end(), "repartition") != seen.end())
    fail("keyword 'repartition' chooses how METIS is used; with 'partitioner scotch' each "
         "repartition is one SCOTCH_graphRepart call (drop 'repartition')");
  if ((partitioner_ == Partitioner::Rcb || partitioner_ == Partitioner::Layers) &&
      cell_factor_ == 0.0)
    fail(std::string("keyword 'partitioner ") +
         (partitioner_ == Partitioner::Rcb ? "rcb" : "layers") +
         "' cuts the cell grid by coordinates and needs cells (a cell edge >= 1); it does not "
         "work with 'cells 0'");

  scalar_flag = 1;
  vector_flag = 1;
  size_vector = 10;
  global_freq = 1;
  extscalar = 0;
  extvector = 0;
  force_reneighbor = 1;
  next_reneighbor = -1;
  restart_global = 1;
  peratom_flag = 1;
  size_peratom_cols = 0;
  peratom_freq = 1;

  // Calibrated costs are measured once on rank 0 and shared, so every rank weighs alike.
  costs_ = fracdem::balance::unit_costs();
  if (cost_model_ != CostModel::Counts) {
    fracdem::balance::TermCounts c{};
    if (comm->me == 0) c = fracdem::balance::cost_array(fracdem::balance::calibrate_costs());
    MPI_Bcast(c.data(), fracdem::balance::kCostTerms, MPI_DOUBLE, 0, world);
    costs_ = fracdem::balance::interaction_costs(c);
    if (comm->me == 0) {
      char line[400];
      snprintf(line, sizeof line,
               "fix balance/graph: calibrated costs relative to a pair check: particle %.2f, "
               "sphere contact %.2f, wall check %.2f, wall contact %.2f, facet check %.2f, "
               "facet contact %.2f\n",
               costs_.particle, costs_.sphere_contact, costs_.wall_check, costs_.wall_contact,
               costs_.facet_check, costs_.facet_contact);
      if (screen) fputs(line, screen);
      if (logfile) fputs(line, logfile);
    }
  }
  calibrated_ = costs_;
}

FixBalanceGraph::~FixBalanceGraph()
{
  if (out_) fclose(out_);
}

int FixBalanceGraph::setmask()
{
  return INITIAL_INTEGRATE | PRE_EXCHANGE | PRE_NEIGHBOR | PRE_FORCE | POST_FORCE |
         FINAL_INTEGRATE | END_OF_STEP;
}

// Per-atom output (f_ID in dumps): the owner rank, to see the partition in ParaView.
void FixBalanceGraph::setup(int)
{
  owner_rank_.assign(std::max(atom->nlocal, 1), static_cast<double>(comm->me));
  vector_atom = owner_rank_.data();
  cpu_step_end_ = -1; // the set-up's output is not particle work
}

// The integrators' share of the measured work: from the end of the previous step (this fix's
// end_of_step) to this fix's initial_integrate, which runs after those of the fixes defined
// before it (nve/sphere's first half). Steps with output (thermo, dumps: collectives and I/O
// between end_of_step and the next step) are left out.
void FixBalanceGraph::initial_integrate(int)
{
  if (cpu_step_end_ >= 0) cpu_work_ += thread_cpu_seconds() - cpu_step_end_;
  cpu_step_end_ = -1;
}

// From the end of this fix's post_force to its final_integrate: post-force fixes defined after it
// and the second half of the integrators defined before it.
void FixBalanceGraph::final_integrate()
{
  if (cpu_after_force_ >= 0) cpu_work_ += thread_cpu_seconds() - cpu_after_force_;
  cpu_after_force_ = -1;
}

void FixBalanceGraph::end_of_step()
{
  owner_rank_.assign(std::max(atom->nlocal, 1), static_cast<double>(comm->me));
  vector_atom = owner_rank_.data();
  cpu_step_end_ = output->next > update->ntimestep ? thread_cpu_seconds() : -1;
}

// The measured work brackets neighbour build + pair + earlier post-force fixes with the thread's
// CPU clock (not wall time: oversubscribed ranks would count their waiting).
void FixBalanceGraph::pre_neighbor()
{
  cpu_start_ = thread_cpu_seconds();
  cpu_from_neighbor_ = true;
}

void FixBalanceGraph::pre_force(int)
{
  if (!cpu_from_neighbor_) cpu_start_ = thread_cpu_seconds();
  cpu_from_neighbor_ = false;
}

void FixBalanceGraph::post_force(int)
{
  cpu_after_force_ = thread_cpu_seconds();
  cpu_work_ += cpu_after_force_ - cpu_start_;
}

void FixBalanceGraph::init()
{
  comm_graph_ = dynamic_cast<CommGraph*>(comm);
  if (!comm_graph_)
    error->all(FLERR, "fix balance/graph: the communicator is the stock one (was 'clear' used?); "
                      "graph ownership needs the fracdem executable's communicator");
  if (!force->pair)
    error->all(FLERR, "fix balance/graph: needs a pair style (its neighbour list "
                      "is the particle graph)");
  if (!atom->radius_flag)
    error->all(FLERR, "fix balance/graph: needs per-atom radius (atom_style sphere or granular)");

  primitive_walls_.clear();
  fem_bodies_.clear();
  bool inserting = false;
  for (int i = 0; i < modify->nfix; ++i) {
    Fix* f = modify->fix[i];
    // Insertion fixes check overlaps against particles near the brick they insert into.
    if (strncmp(f->style, "insert/", 7) == 0) inserting = true;
    if (strncmp(f->style, "mesh/surface", 12) == 0) {
      char msg[512];
      snprintf(msg, sizeof msg,
               "fix balance/graph: fix %s (%s) distributes its mesh by spatial sub-domain and "
               "cannot follow graph ownership; use a rigid 'fix fem/body ... rigid yes' with "
               "'motion' for meshes such as buckets, hoppers and plates",
               f->id, f->style);
      error->all(FLERR, msg);
    }
    if (auto* w = dynamic_cast<FixWallGran*>(f))
      if (!w->is_mesh_wall() && w->primitiveWall()) primitive_walls_.push_back(w);
    if (auto* b = dynamic_cast<FixFemBody*>(f)) fem_bodies_.push_back(b);
  }
  comm_graph_->set_cover_brick(inserting);
  std::vector<double> limits;
  for (const std::string& id : insert_regions_) {
    const int r = domain->find_region(id.c_str());
    if (r < 0)
      error->all(FLERR,
                 ("fix balance/graph: keyword 'insert_region': no region '" + id + "'").c_str());
    const Region* reg = domain->regions[r];
    if (!reg->bboxflag)
      error->all(FLERR, ("fix balance/graph: keyword 'insert_region': region '" + id +
                         "' has no bounding box")
                            .c_str());
    const double box[6] = {reg->extent_xlo, reg->extent_ylo, reg->extent_zlo,
                           reg->extent_xhi, reg->extent_yhi, reg->extent_zhi};
    limits.insert(limits.end(), box, box + 6);
  }
  if (inserting && limits.empty() && comm->me == 0 && comm->nprocs > 1)
    error->message(FLERR, "fix balance/graph: an insertion fix is present, so ghosts also cover "
                          "every rank's whole brick; name the insertion region(s) with "
                          "'insert_region ID' to cover only those");
  comm_graph_->set_cover_limits(std::move(limits));
}

// Regular checks fall on the multiples of Nevery after the current step.
bigint FixBalanceGraph::next_regular_check() const
{
  return (update->ntimestep / check_every_) * check_every_ + check_every_;
}

// Like LAMMPS fix balance, the first run starts balanced: a check at its first step (the host's
// neighbour list exists only after setup) with the model costs, since nothing has been timed yet.
void FixBalanceGraph::setup_pre_exchange()
{
  const bigint regular = next_regular_check();
  start_check_ = comm->nprocs > 1 && !comm_graph_->graph_ownership();
  if (last_check_step_ < 0) last_check_step_ = update->ntimestep;
  next_reneighbor = start_check_ ? std::min<bigint>(update->ntimestep + 1, regular) : regular;
}

void FixBalanceGraph::pre_exchange()
{
  if (update->ntimestep != next_reneighbor) return;
  const bool start_check = start_check_;
  start_check_ = false;
  next_reneighbor = next_regular_check();

  LocalCosts lc;
  measure(lc);
  const bigint previous_check = last_check_step_;
  last_check_step_ = update->ntimestep;
  // Nothing is timed before the start check: it runs on the model costs.
  if (cost_model_ == CostModel::Fitted && !start_check) {
    fit_to_measured(lc, previous_check);
  } else {
    price(lc);
    if (cost_model_ == CostModel::Timed && !start_check) scale_to_measured(lc);
  }
  double sum = 0, max = 0;
  MPI_Allreduce(&lc.total, &sum, 1, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(&lc.total, &max, 1, MPI_DOUBLE, MPI_MAX, world);
  lc.sum_all = sum;
  const double avg = sum / comm->nprocs;
  imbalance_ = avg > 0 ? max / avg : 1.0;

  double cpu_sum = 0, cpu_max = 0;
  MPI_Allreduce(&cpu_work_, &cpu_sum, 1, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(&cpu_work_, &cpu_max, 1, MPI_DOUBLE, MPI_MAX, world);
  measured_imbalance_ = cpu_sum > 0 ? cpu_max * comm->nprocs / cpu_sum : 1.0;
  std::vector<double> cpu_per_rank(comm->me == 0 ? comm->nprocs : 1);
  MPI_Gather(&cpu_work_, 1, MPI_DOUBLE, cpu_per_rank.data(), 1, MPI_DOUBLE, 0, world);
  cpu_work_ = 0;

  double ghosts = atom->nghost, ghost_max = 0;
  MPI_Allreduce(&ghosts, &ghosts_total_, 1, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(&ghosts, &ghost_max, 1, MPI_DOUBLE, MPI_MAX, world);
  ghost_ratio_ = ghosts_total_ > 0 ? ghost_max * comm->nprocs / ghosts_total_ : 1.0;
  checks_ += 1;

  // B > tau: the paper's trigger; thresh = 1 + tau. Nothing to do on one rank.
  const bool repartition_now = comm->nprocs > 1 && imbalance_ > threshold_;
  double seconds = 0;
  if (repartition_now) {
    const double t0 = MPI_Wtime();
    repartition(lc);
    seconds = MPI_Wtime() - t0;
    seconds_total_ += seconds;
  }
  if (out_) {
    char row[512];
    snprintf(row, sizeof row,
             "%ld,%.6g,%d,%.6g,%.0f,%.6g,%.6g,%.6g,%.0f,%.0f,%ld,%.6g,%.6g,%.6g,%.6g,%.6g\n",
             static_cast<long>(update->ntimestep), imbalance_, repartition_now ? 1 : 0,
             imbalance_predicted_, repartition_now ? migrated_last_ : 0.0, seconds,
             comm_graph_->migration_seconds(), ghost_ratio_, ghosts_total_, edge_cut_,
             static_cast<long>(atom->natoms), max, avg, measured_imbalance_, cpu_max,
             cpu_sum / comm->nprocs);
    row[strlen(row) - 1] = '\0'; // per-rank columns follow
    fputs(row, out_);
    for (double w : cpu_per_rank)
      fprintf(out_, ",%.6g", w);
    fputc('\n', out_);
    fflush(out_);
  }
}

void FixBalanceGraph::measure(LocalCosts& lc)
{
  const int nlocal = atom->nlocal;
  lc.potential.assign(nlocal, 0);
  lc.contacts.assign(nlocal, 0);
  lc.wall_contacts.assign(nlocal, 0);
  lc.facet_checks.assign(nlocal, 0);
  lc.facet_contacts.assign(nlocal, 0);
  lc.edges.clear();
  double** x = atom->x;
  const double* radius = atom->radius;
  const int* tag = atom->tag;
  const bool aposteriori = graph_model_ == GraphModel::APosteriori;
  // With newton off a pair that straddles two ranks is in both ranks' lists; keep one copy.
  const bool newton = force->newton_pair != 0;
  // (A fitted pair-check cost may be zero: the ratio is then taken as 1.)
  const std::int64_t contact_edge_weight =
      costs_.pair_check > 0
          ? std::max<std::int64_t>(
                1, std::llround(std::min(1e6, costs_.sphere_contact / costs_.pair_check)))
          : 1;
  const bool by_cell = cell_factor_ > 0;
  if (by_cell) {
    const bool periodic[3] = {domain->periodicity[0] != 0, domain->periodicity[1] != 0,
                              domain->periodicity[2] != 0};
    grid_ = fracdem::balance::make_cell_grid(domain->boxlo, domain->boxhi,
                                             cell_factor_ * comm->cutghost[0], domain->dimension,
                                             periodic);
    lc.cell.resize(nlocal);
    for (int i = 0; i < nlocal; ++i)
      lc.cell[i] = grid_.cell_of(x[i]);
  }

  // Potential targets and sphere-sphere contacts from the host's own list: no second search.
  NeighList* list = force->pair->list;
  if (list && list->ilist) {
    for (int ii = 0; ii < list->inum; ++ii) {
      const int i = list->ilist[ii];
      if (i >= nlocal) continue;
      const int* jlist = list->firstneigh[i];
      const int jnum = list->numneigh[i];
      lc.potential[i] += jnum;
      for (int jj = 0; jj < jnum; ++jj) {
        const int j = jlist[jj] & NEIGHMASK;
        const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
        const double rs = radius[i] + radius[j];
        const bool touching = dx * dx + dy * dy + dz * dz < rs * rs;
        lc.contacts[i] += touching;
        if (!newton && j >= nlocal && tag[i] > tag[j]) continue;
        const std::int64_t w = (aposteriori && touching) ? 1 + contact_edge_weight : 1;
        if (by_cell) {
          const std::int64_t cj = grid_.cell_of(x[j]);
          if (cj == lc.cell[i]) continue; // inside one vertex
          lc.edges.push_back(lc.cell[i]);
          lc.edges.push_back(cj);
        } else {
          lc.edges.push_back(tag[i]);
          lc.edges.push_back(tag[j]);
        }
        lc.edges.push_back(w);
      }
    }
  }

  // Primitive walls of fix wall/gran (their work runs outside Pair time): a gap test for every
  // particle, and the contact law for those touching.
  for (FixWallGran* w : primitive_walls_) {
    PrimitiveWall* pw = w->primitiveWall();
    double delta[3];
    for (int i = 0; i < nlocal; ++i)
      if (pw->resolveContact(x[i], radius[i], delta) <= 0.0) lc.wall_contacts[i] += 1;
  }

  // Facet checks and contacts of deformable or rigid FE bodies.
  for (FixFemBody* b : fem_bodies_) {
    const auto& checks = b->facet_checks();
    const auto& contacts = b->facet_contacts();
    if (static_cast<int>(checks.size()) != nlocal) continue; // no contact evaluated yet
    for (int i = 0; i < nlocal; ++i)
      lc.facet_checks[i] += checks[i], lc.facet_contacts[i] += contacts[i];
  }

  namespace fb = fracdem::balance;
  lc.term_sums.fill(0.0);
  const double walls = static_cast<double>(primitive_walls_.size());
  for (int i = 0; i < nlocal; ++i) {
    lc.term_sums[fb::kPairCheck] += lc.potential[i];
    lc.term_sums[fb::kSphereContact] += lc.contacts[i];
    lc.term_sums[fb::kWallContact] += lc.wall_contacts[i];
    lc.term_sums[fb::kFacetCheck] += lc.facet_checks[i];
    lc.term_sums[fb::kFacetContact] += lc.facet_contacts[i];
  }
  lc.term_sums[fb::kParticle] = nlocal;
  lc.term_sums[fb::kWallCheck] = walls * nlocal;
  lc.term_sums[fb::kGhost] = atom->nghost;
}

// Work model per particle (paper section 5.1): every particle costs something on its own (list
// traversal, binning, integration), plus each of its checks and contacts.
void FixBalanceGraph::price(LocalCosts& lc) const
{
  const int nlocal = atom->nlocal;
  fracdem::balance::ParticleCounts k;
  k.walls = static_cast<int>(primitive_walls_.size());
  lc.cost.resize(nlocal);
  lc.total = 0;
  for (int i = 0; i < nlocal; ++i) {
    k.pair_checks = static_cast<long>(lc.potential[i]);
    k.sphere_contacts = lc.contacts[i], k.wall_contacts = lc.wall_contacts[i];
    k.facet_checks = lc.facet_checks[i], k.facet_contacts = lc.facet_contacts[i];
    lc.cost[i] = fracdem::balance::particle_cost(costs_, k);
    lc.total += lc.cost[i];
  }
}

// The model only splits this rank's measured time among its particles.
void FixBalanceGraph::scale_to_measured(LocalCosts& lc) const
{
  const double spent = cpu_work_;
  if (lc.total > 0 && spent > 0) {
    const double scale = spent / lc.total;
    for (double& c : lc.cost)
      c *= scale;
    lc.total = spent;
  }
}

// One set of costs for all ranks, fitted to every rank's measured time: unlike `timed`, whose
// per-rank factor stays behind when particles move to another rank, fitted costs travel with the
// particles. The trigger still compares measured times.
void FixBalanceGraph::fit_to_measured(LocalCosts& lc, bigint previous_check)
{
  namespace fb = fracdem::balance;
  const int nprocs = comm->nprocs;
  double mine[fb::kCostTerms + 1];
  std::copy(lc.term_sums.begin(), lc.term_sums.end(), mine);
  mine[fb::kCostTerms] = cpu_work_;
  // Time per step, so that the costs are per item and step whatever the interval.
  const double interval_steps = std::max<double>(1.0, update->ntimestep - previous_check);
  std::vector<double> all((fb::kCostTerms + 1) * nprocs);
  MPI_Allgather(mine, fb::kCostTerms + 1, MPI_DOUBLE, all.data(), fb::kCostTerms + 1, MPI_DOUBLE,
                world);
  for (int p = 0; p < nprocs; ++p) {
    fb::CostSample sample;
    std::copy(&all[p * (fb::kCostTerms + 1)], &all[p * (fb::kCostTerms + 1)] + fb::kCostTerms,
              sample.counts.begin());
    sample.seconds = all[p * (fb::kCostTerms + 1) + fb::kCostTerms] / interval_steps;
    fit_samples_.push_back(sample);
  }
  const size_t keep = static_cast<size_t>(kFitWindowChecks) * nprocs;
  if (fit_samples_.size() > keep)
    fit_samples_.erase(fit_samples_.begin(), fit_samples_.end() - keep);
  // Every rank fits the same samples in the same order: identical costs everywhere.
  costs_ =
      fb::interaction_costs(fb::fit_costs(fit_samples_, fb::cost_array(calibrated_), kFitShrink));
  // The costs are per step; the check compares (and the vertex weights are scaled by) the
  // measured time of the whole interval, so the particle costs must be per interval too.
  price(lc);
  for (double& c : lc.cost)
    c *= interval_steps;
  if (cpu_work_ > 0) lc.total = cpu_work_;
}

FixBalanceGraph::GatheredGraph
FixBalanceGraph::gather_graph(const std::vector<std::int64_t>& verts,
                              const std::vector<std::int64_t>& edges) const
{
  const int nprocs = comm->nprocs;
  GatheredGraph gg;
  int counts[2] = {static_cast<int>(verts.size()), static_cast<int>(edges.size())};
  std::vector<int> all_counts(2 * nprocs);
  MPI_Gather(counts, 2, MPI_INT, all_counts.data(), 2, MPI_INT, 0, world);
  gg.vcount.resize(nprocs), gg.vdisp.resize(nprocs);
  std::vector<int> ecount(nprocs), edisp(nprocs);
  for (int p = 0; p < nprocs; ++p) {
    gg.vcount[p] = all_counts[2 * p], gg.vdisp[p] = gg.vtotal, gg.vtotal += gg.vcount[p];
    ecount[p] = all_counts[2 * p + 1], edisp[p] = gg.etotal, gg.etotal += ecount[p];
  }
  gg.verts.resize(comm->me == 0 ? std::max(gg.vtotal, 1) : 1);
  gg.edges.resize(comm->me == 0 ? std::max(gg.etotal, 1) : 1);
  MPI_Gatherv(verts.data(), counts[0], MPI_INT64_T, gg.verts.data(), gg.vcount.data(),
              gg.vdisp.data(), MPI_INT64_T, 0, world);
  MPI_Gatherv(edges.data(), counts[1], MPI_INT64_T, gg.edges.data(), ecount.data(), edisp.data(),
              MPI_INT64_T, 0, world);
  // The receive buffers had at least one entry (a valid pointer for MPI); hand back the gathered
  // arrays only, so that the edges are whole triples.
  gg.verts.resize(comm->me == 0 ? gg.vtotal : 0);
  gg.edges.resize(comm->me == 0 ? gg.etotal : 0);
  return gg;
}

std::vector<int> FixBalanceGraph::partition_on_root(const fracdem::balance::Graph& g,
                                                    const std::vector<int>& old_owner,
                                                    double stats[2], const std::vector<double>* xyz,
                                                    const std::vector<std::int64_t>* cells,
                                                    std::string* layout) const
{
  namespace fb = fracdem::balance;
  const int nprocs = comm->nprocs;
  const std::vector<double> load(g.vwgt.begin(), g.vwgt.end());
  const double current = fb::imbalance(fb::part_loads(load, old_owner, nprocs));
  std::vector<int> part;
  bool refined = false;
  if (partitioner_ == Partitioner::Scotch) {
    // One call does both: a balanced partition that weighs edge cut against migration.
    part = fb::repartition_scotch(g, old_owner, nprocs, kScotchMigrationCost,
                                  kMetisImbalanceTolerance);
    refined = true;
  } else if (strategy_ == Strategy::Refine ||
             (strategy_ == Strategy::Auto && current < kRefineBelow &&
              partitioner_ != Partitioner::Rcb && partitioner_ != Partitioner::Layers)) {
    // (partitioner rcb and layers: `auto` cuts from scratch every time; diffusion from the
    // current owners erodes the boxes, 9.1 against 8.5 partners per rank at 16 ranks on the
    // settling bed.)
    part = old_owner;
    refined = fb::refine_partition(g, part, nprocs, kMetisImbalanceTolerance, kRefinePasses) <=
              kRefinePasses;
  }
  if (!refined && strategy_ != Strategy::Refine) {
    // From scratch, then relabelled so that most of the load stays where it is.
    std::vector<int> fresh;
    if (partitioner_ == Partitioner::Layers && cells) {
      fb::LayerLayout chosen;
      fresh = fb::partition_layers(g, grid_, *cells, nprocs, kMetisImbalanceTolerance, &chosen,
                                   gravity_axis());
      if (layout) *layout = chosen.describe();
    } else if (partitioner_ == Partitioner::Rcb && xyz) {
      fresh = fb::partition_compact(g, *xyz, nprocs, kMetisImbalanceTolerance);
    } else {
      fresh = fb::partition_kway(g, nprocs, kMetisImbalanceTolerance);
    }
    part = fb::relabel_max_overlap(fresh, old_owner, load, nprocs);
  } else if (partitioner_ == Partitioner::Rcb || partitioner_ == Partitioner::Layers) {
    // Diffusion leaves steps in the boundaries it moved: smooth them without new partners.
    fb::smooth_partition(g, part, nprocs, kMetisImbalanceTolerance);
  }
  stats[0] = fb::imbalance(fb::part_loads(load, part, nprocs));
  stats[1] = static_cast<double>(fb::edge_cut(g, part));
  return part;
}

int FixBalanceGraph::gravity_axis() const
{
  // The axis of the largest component of fix gravity's acceleration (-1: no gravity).
  double g[3] = {0, 0, 0};
  for (int i = 0; i < modify->nfix; ++i)
    if (!strcmp(modify->fix[i]->style, "gravity"))
      static_cast<FixGravity*>(modify->fix[i])->get_gravity(g);
  int axis = -1;
  for (int d = 0; d < 3; ++d)
    if (g[d] != 0.0 && (axis < 0 || std::abs(g[d]) > std::abs(g[axis]))) axis = d;
  return axis;
}

void FixBalanceGraph::repartition(const LocalCosts& lc)
{
  if (cell_factor_ > 0) {
    repartition_cells(lc);
    return;
  }
  const int me = comm->me, nprocs = comm->nprocs;
  const int nlocal = atom->nlocal;

  const std::vector<std::int64_t> weight = vertex_weights(lc);
  std::vector<std::int64_t> verts(2 * nlocal);
  for (int i = 0; i < nlocal; ++i)
    verts[2 * i] = atom->tag[i], verts[2 * i + 1] = weight[i];

  // Gather the graph on rank 0 (METIS is serial); vertices keep the order of their ranks.
  const GatheredGraph gg = gather_graph(verts, lc.edges);
  const std::vector<int>&vcount = gg.vcount, &vdisp = gg.vdisp;
  const std::vector<std::int64_t>&all_verts = gg.verts, &all_edges = gg.edges;
  const int vtotal = gg.vtotal, etotal = gg.etotal;

  std::vector<int> part_all;
  double stats[2] = {1.0, 0.0}; // predicted imbalance, edge cut
  int failed = 0;
  std::string failure;
  if (me == 0) {
    const std::int64_t n = vtotal / 2;
    std::vector<std::int64_t> vwgt(n);
    std::vector<int> old_owner(n);
    for (int p = 0; p < nprocs; ++p)
      for (int k = vdisp[p] / 2; k < (vdisp[p] + vcount[p]) / 2; ++k)
        old_owner[k] = p;
    // Tags are positive and at most a few times the atom count: a dense index, no hashing.
    std::int64_t max_tag = 0;
    for (std::int64_t v = 0; v < n; ++v)
      max_tag = std::max(max_tag, all_verts[2 * v]);
    std::vector<std::int64_t> vertex_of_tag(max_tag + 1, -1);
    for (std::int64_t v = 0; v < n; ++v) {
      vertex_of_tag[all_verts[2 * v]] = v;
      vwgt[v] = all_verts[2 * v + 1];
    }
    const auto vertex = [&](std::int64_t tag) {
      return tag >= 0 && tag <= max_tag ? vertex_of_tag[tag] : std::int64_t{-1};
    };
    std::vector<fracdem::balance::WeightedPair> pairs;
    pairs.reserve(etotal / 3);
    for (int e = 0; e + 2 < etotal; e += 3) {
      const std::int64_t a = vertex(all_edges[e]), b = vertex(all_edges[e + 1]);
      if (a >= 0 && b >= 0) pairs.push_back({a, b, all_edges[e + 2]});
    }
    try {
      const fracdem::balance::Graph g = fracdem::balance::build_graph(n, vwgt, pairs);
      part_all = partition_on_root(g, old_owner, stats);
    } catch (const std::exception& ex) {
      failed = 1;
      failure = ex.what();
    }
    if (failed) part_all = old_owner; // keep the current owners
  }
  MPI_Bcast(&failed, 1, MPI_INT, 0, world);
  if (failed) {
    if (me == 0)
      error->warning(
          FLERR, ("fix balance/graph: partitioning failed, ownership kept: " + failure).c_str());
    return;
  }
  MPI_Bcast(stats, 2, MPI_DOUBLE, 0, world);

  std::vector<int> dest(std::max(nlocal, 1));
  std::vector<int> pcount(nprocs), pdisp(nprocs);
  for (int p = 0; p < nprocs; ++p)
    pcount[p] = vcount[p] / 2, pdisp[p] = vdisp[p] / 2;
  MPI_Scatterv(part_all.data(), pcount.data(), pdisp.data(), MPI_INT, dest.data(), nlocal, MPI_INT,
               0, world);
  dest.resize(nlocal);

  double migrated = 0;
  for (int i = 0; i < nlocal; ++i)
    migrated += dest[i] != me;
  MPI_Allreduce(MPI_IN_PLACE, &migrated, 1, MPI_DOUBLE, MPI_SUM, world);

  comm_graph_->enable_graph_ownership("fix balance/graph");
  comm_graph_->set_destinations(std::move(dest));

  record_repartition(stats, migrated);
}

// Vertex weight per local particle: potential targets (a priori) or the recorded cost
// (a posteriori), as integers >= 1 with an average particle worth kWeightResolution.
std::vector<std::int64_t> FixBalanceGraph::vertex_weights(const LocalCosts& lc) const
{
  const int nlocal = atom->nlocal;
  double n_all = 0, local_n = nlocal;
  MPI_Allreduce(&local_n, &n_all, 1, MPI_DOUBLE, MPI_SUM, world);
  const double mean_cost = n_all > 0 && lc.sum_all > 0 ? lc.sum_all / n_all : 1.0;
  std::vector<std::int64_t> weight(nlocal);
  for (int i = 0; i < nlocal; ++i) {
    const double w = graph_model_ == GraphModel::APriori
                         ? static_cast<double>(std::max<std::int64_t>(1, lc.potential[i]))
                         : kWeightResolution * lc.cost[i] / mean_cost;
    weight[i] = std::max<std::int64_t>(1, std::llround(w));
  }
  return weight;
}

void FixBalanceGraph::record_repartition(const double stats[2], double migrated)
{
  imbalance_before_ = imbalance_;
  imbalance_predicted_ = stats[0];
  edge_cut_ = stats[1];
  migrated_last_ = migrated;
  repartitions_ += 1;

  if (comm->me == 0) {
    char line[512];
    snprintf(line, sizeof line,
             "fix balance/graph: step %ld imbalance %.3f > %.3f: repartitioned (%s%s graph), "
             "predicted %.3f, %.0f particles migrate, edge cut %.0f\n",
             static_cast<long>(update->ntimestep), imbalance_, threshold_,
             graph_model_ == GraphModel::APriori ? "a priori" : "a posteriori",
             cell_factor_ > 0 ? " cell" : " particle", stats[0], migrated, stats[1]);
    if (screen) fputs(line, screen);
    if (logfile) fputs(line, logfile);
    if (cost_model_ == CostModel::Fitted && !fit_samples_.empty() && costs_.pair_check > 0) {
      const double unit = costs_.pair_check;
      snprintf(
          line, sizeof line,
          "fix balance/graph: fitted costs relative to a pair check (%.3g ns per step): particle "
          "%.2f, sphere contact %.2f, wall check %.2f, wall contact %.2f, facet check %.2f, "
          "facet contact %.2f\n",
          1e9 * unit, costs_.particle / unit, costs_.sphere_contact / unit,
          costs_.wall_check / unit, costs_.wall_contact / unit, costs_.facet_check / unit,
          costs_.facet_contact / unit);
      if (screen) fputs(line, screen);
      if (logfile) fputs(line, logfile);
    }
  }
}

void FixBalanceGraph::repartition_cells(const LocalCosts& lc)
{
  const int me = comm->me, nprocs = comm->nprocs;
  const int nlocal = atom->nlocal;

  // Local aggregation: (cell, weight) of this rank's particles, and cell-pair edge weights.
  const std::vector<std::int64_t> weight = vertex_weights(lc);
  std::unordered_map<std::int64_t, std::int64_t> cell_weight;
  for (int i = 0; i < nlocal; ++i)
    cell_weight[lc.cell[i]] += weight[i];
  std::vector<std::int64_t> verts;
  verts.reserve(2 * cell_weight.size());
  for (const auto& cw : cell_weight)
    verts.push_back(cw.first), verts.push_back(cw.second);
  std::unordered_map<std::int64_t, std::int64_t> edge_weight;
  const std::int64_t ncells = grid_.total();
  for (size_t e = 0; e + 2 < lc.edges.size(); e += 3) {
    const std::int64_t a = std::min(lc.edges[e], lc.edges[e + 1]),
                       b = std::max(lc.edges[e], lc.edges[e + 1]);
    edge_weight[a * ncells + b] += lc.edges[e + 2];
  }
  std::vector<std::int64_t> edges;
  edges.reserve(3 * edge_weight.size());
  for (const auto& ew : edge_weight)
    edges.push_back(ew.first / ncells), edges.push_back(ew.first % ncells),
        edges.push_back(ew.second);

  const GatheredGraph gg = gather_graph(verts, edges);
  const std::vector<int>&vcount = gg.vcount, &vdisp = gg.vdisp;
  const std::vector<std::int64_t>&all_verts = gg.verts, &all_edges = gg.edges;

  std::vector<int> owners(ncells);
  double stats[2] = {1.0, 0.0};
  int failed = 0;
  std::string failure;
  if (me == 0) {
    namespace fb = fracdem::balance;
    // Occupied cells; a cell shared by several ranks starts with the one holding most of it.
    // Dense cell index (the owner table broadcast below has one entry per cell anyway).
    std::vector<std::int64_t> vertex_of_cell(ncells, -1);
    std::vector<std::int64_t> cells, vwgt, best_share;
    std::vector<int> old_owner;
    for (int p = 0; p < nprocs; ++p)
      for (int k = vdisp[p]; k < vdisp[p] + vcount[p]; k += 2) {
        const std::int64_t cell = all_verts[k], w = all_verts[k + 1];
        const std::int64_t v = vertex_of_cell[cell];
        if (v < 0) {
          vertex_of_cell[cell] = static_cast<std::int64_t>(cells.size());
          cells.push_back(cell), vwgt.push_back(w), best_share.push_back(w), old_owner.push_back(p);
        } else {
          vwgt[v] += w;
          if (w > best_share[v]) best_share[v] = w, old_owner[v] = p;
        }
      }
    // Unit edges between touching occupied cells keep parts compact where particles have no
    // neighbours yet (free fall, dilute inflow): few ghosts, and no scattered parts.
    try {
      const fb::Graph g = fb::build_cell_graph(grid_, cells, vertex_of_cell, vwgt, all_edges);
      std::vector<double> centre;
      if (partitioner_ == Partitioner::Rcb) {
        centre.resize(3 * cells.size());
        for (size_t v = 0; v < cells.size(); ++v) {
          std::int64_t c[3];
          grid_.coords(cells[v], c);
          for (int d = 0; d < 3; ++d)
            centre[3 * v + d] = grid_.lo[d] + (static_cast<double>(c[d]) + 0.5) * grid_.size[d];
        }
      }
      std::string layout;
      const std::vector<int> part =
          partition_on_root(g, old_owner, stats, &centre, &cells, &layout);
      owners = fb::fill_cell_owners(grid_, cells, part);
      // partitioner layers: say which layout was chosen whenever it changes (the rcb fallback
      // included), not at every repartition.
      const std::string kind = layout.substr(0, layout.find(','));
      if (!layout.empty() && kind != layout_kind_) {
        layout_kind_ = kind;
        const std::string line = "fix balance/graph: partitioner layers: " + layout + "\n";
        if (screen) fputs(line.c_str(), screen);
        if (logfile) fputs(line.c_str(), logfile);
      }
    } catch (const std::exception& ex) {
      failed = 1;
      failure = ex.what();
    }
  }
  MPI_Bcast(&failed, 1, MPI_INT, 0, world);
  if (failed) {
    if (me == 0)
      error->warning(
          FLERR, ("fix balance/graph: partitioning failed, ownership kept: " + failure).c_str());
    return;
  }
  MPI_Bcast(stats, 2, MPI_DOUBLE, 0, world);
  MPI_Bcast(owners.data(), static_cast<int>(ncells), MPI_INT, 0, world);

  double migrated = 0;
  for (int i = 0; i < nlocal; ++i)
    migrated += owners[lc.cell[i]] != me;
  MPI_Allreduce(MPI_IN_PLACE, &migrated, 1, MPI_DOUBLE, MPI_SUM, world);
  comm_graph_->enable_graph_ownership("fix balance/graph");
  comm_graph_->set_cell_owners(grid_, std::move(owners));
  record_repartition(stats, migrated);
}

double FixBalanceGraph::compute_scalar()
{
  return imbalance_;
}

double FixBalanceGraph::compute_vector(int n)
{
  switch (n) {
  case 0:
    return imbalance_before_;
  case 1:
    return repartitions_;
  case 2:
    return migrated_last_;
  case 3:
    return seconds_total_ + (comm_graph_ ? comm_graph_->migration_seconds() : 0.0);
  case 4:
    return ghost_ratio_;
  case 5:
    return edge_cut_;
  case 6:
    return checks_;
  case 7:
    return imbalance_predicted_;
  case 8:
    return ghosts_total_;
  case 9:
    return measured_imbalance_;
  default:
    return 0.0;
  }
}

void FixBalanceGraph::write_restart(FILE* fp)
{
  if (comm->me != 0) return;
  const double state[6] = {imbalance_before_, repartitions_, migrated_last_,
                           seconds_total_,    edge_cut_,     checks_};
  const int size = sizeof(state);
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(state, sizeof(state), 1, fp);
}

void FixBalanceGraph::restart(char* buf)
{
  double state[6];
  memcpy(state, buf, sizeof(state));
  imbalance_before_ = state[0], repartitions_ = state[1], migrated_last_ = state[2];
  seconds_total_ = state[3], edge_cut_ = state[4], checks_ = state[5];
}
