// fix balance/graph: measures per-rank work from the host's neighbour list, walls and FE contacts,
// hands it to the balance policy (src/core/balance) and applies the owners it chooses.
#include "fix_balance_graph.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ctime>
#include <exception>
#include <string>

#include "atom.h"
#include "balance/balance_restart.h"
#include "balance/gathered_graph.h"
#include "ptscotch_partition.h"
#include "zoltan_partition.h"
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
#include "pair_fracdem_gran.h"
#include "primitive_wall.h"
#include "region.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;
namespace fb = fracdem::balance;

namespace
{

// The distributed partitioners' engines: whether this build has them, and the call.
const char* engine(fb::Partitioner p)
{
  return p == fb::Partitioner::PtScotch ? "PT-Scotch" : "Zoltan";
}

bool built_with(fb::Partitioner p)
{
  return p == fb::Partitioner::PtScotch ? fb::have_ptscotch() : fb::have_zoltan();
}

fb::DistributedResult partition_distributed(fb::Partitioner p, const fb::DistributedGraph& g,
                                            int nparts, MPI_Comm comm)
{
  if (p == fb::Partitioner::PtScotch)
    return fb::partition_ptscotch(g, nparts, fb::kDistributedTolerance, comm);
  return fb::partition_zoltan(g, nparts, fb::kDistributedTolerance, p == fb::Partitioner::ZoltanPhg,
                              comm);
}

double thread_cpu_seconds()
{
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

} // namespace

FixBalanceGraph::FixBalanceGraph(LAMMPS* lmp, int narg, char** arg)
    : Fix(lmp, narg, arg), spec_(read_spec(narg, arg)),
      schedule_(spec_.every), trigger_{spec_.threshold}, pricing_(spec_.cost_model, start_costs()),
      strategy_(spec_.partitioner, spec_.strategy)
{
  const fb::PartitionerInfo& partitioner = fb::partitioner_info(spec_.partitioner);
  if (partitioner.distributed && !built_with(partitioner.id))
    fail(std::string("keyword 'partitioner ") + partitioner.name + "': this build has no " +
         engine(partitioner.id) + "; install the Debian package " + partitioner.package +
         " (apt-get install --no-install-recommends " + partitioner.package +
         ") and rebuild fracdem, or choose another partitioner");
  if (!spec_.out_file.empty() && comm->me == 0) {
    out_ = fopen(spec_.out_file.c_str(), "w");
    if (!out_) fail("keyword 'out': cannot open '" + spec_.out_file + "' for writing");
    fputs(fb::report_header(comm->nprocs).c_str(), out_);
  }
  scalar_flag = 1;
  vector_flag = 1;
  size_vector = fb::BalanceOutputs::kVectorSize;
  global_freq = 1;
  extscalar = 0;
  extvector = 0;
  force_reneighbor = 1;
  next_reneighbor = -1;
  restart_global = 1;
  restart_peratom = 1; // each particle's owner
  atom->add_callback(1);
  peratom_flag = 1;
  size_peratom_cols = 0;
  peratom_freq = 1;
  comm_forward = 1; // the distributed graph's vertex numbers, to ghosts
}

FixBalanceGraph::~FixBalanceGraph()
{
  atom->delete_callback(id, 1);
  if (out_) fclose(out_);
}

void FixBalanceGraph::fail(const std::string& msg) const
{
  error->all(FLERR, ("fix balance/graph: " + msg).c_str());
}

void FixBalanceGraph::log(const std::string& line) const
{
  if (screen) fputs(line.c_str(), screen);
  if (logfile) fputs(line.c_str(), logfile);
}

fb::BalanceSpec FixBalanceGraph::read_spec(int narg, char** arg) const
{
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
  try {
    return fb::parse_balance_spec(std::vector<std::string>(arg + 3, arg + narg));
  } catch (const fb::BalanceSpecError& e) {
    fail(e.what());
  }
  return {};
}

// Calibrated costs are measured once on rank 0 and shared, so every rank weighs alike.
fb::InteractionCosts FixBalanceGraph::start_costs() const
{
  if (spec_.cost_model == fb::CostModel::Counts) return fb::unit_costs();
  const fb::InteractionCosts c = fb::shared_calibrated_costs(world);
  if (comm->me == 0) log(fb::calibrated_costs_line(c));
  return c;
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
  // The pair counts the step before a check (the check runs at the next step's pre_exchange).
  if (pair_counts_ && next_reneighbor == update->ntimestep + 1) pair_counts_->request_counts();
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
  find_work_fixes();
  pair_counts_ = spec_.pair_counts ? dynamic_cast<PairFracdemGran*>(force->pair) : nullptr;
}

// The fixes whose work the model counts (primitive walls, FE bodies), the refusal of mesh walls,
// and the ghost cover that insertion fixes need.
void FixBalanceGraph::find_work_fixes()
{
  primitive_walls_.clear();
  fem_bodies_.clear();
  bool inserting = false;
  for (int i = 0; i < modify->nfix; ++i) {
    Fix* f = modify->fix[i];
    // Insertion fixes check overlaps against particles near the brick they insert into.
    if (strncmp(f->style, "insert/", 7) == 0) inserting = true;
    if (strncmp(f->style, "mesh/surface", 12) == 0)
      fail(std::string("fix ") + f->id + " (" + f->style +
           ") distributes its mesh by spatial sub-domain and cannot follow graph ownership; use "
           "a rigid 'fix fem/body ... rigid yes' with 'motion' for meshes such as buckets, "
           "hoppers and plates");
    if (auto* w = dynamic_cast<FixWallGran*>(f))
      if (!w->is_mesh_wall() && w->primitiveWall()) primitive_walls_.push_back(w);
    if (auto* b = dynamic_cast<FixFemBody*>(f)) fem_bodies_.push_back(b);
  }
  comm_graph_->set_cover_brick(inserting);
  std::vector<double> limits = insert_limits();
  if (inserting && limits.empty() && comm->me == 0 && comm->nprocs > 1)
    error->message(FLERR, "fix balance/graph: an insertion fix is present, so ghosts also cover "
                          "every rank's whole brick; name the insertion region(s) with "
                          "'insert_region ID' to cover only those");
  comm_graph_->set_cover_limits(std::move(limits));
}

// The bounding boxes of the insert_region regions (6 numbers each).
std::vector<double> FixBalanceGraph::insert_limits() const
{
  std::vector<double> limits;
  for (const std::string& id : spec_.insert_regions) {
    const int r = domain->find_region(id.c_str());
    if (r < 0) fail("keyword 'insert_region': no region '" + id + "'");
    const Region* reg = domain->regions[r];
    if (!reg->bboxflag) fail("keyword 'insert_region': region '" + id + "' has no bounding box");
    const double box[6] = {reg->extent_xlo, reg->extent_ylo, reg->extent_zlo,
                           reg->extent_xhi, reg->extent_yhi, reg->extent_zhi};
    limits.insert(limits.end(), box, box + 6);
  }
  return limits;
}

// The first run starts balanced, as LAMMPS fix balance does: on more than one rank while
// ownership is still the stock brick, a check at its first step (the host's neighbour list
// exists only after setup).
void FixBalanceGraph::setup_pre_exchange()
{
  const bool restored = restore_ownership();
  schedule_.setup(update->ntimestep,
                  comm->nprocs > 1 && !restored && !comm_graph_->graph_ownership());
  next_reneighbor = schedule_.next();
}

void FixBalanceGraph::pre_exchange()
{
  if (!schedule_.due(update->ntimestep)) return;
  const fb::CheckSchedule::Check check = schedule_.take(update->ntimestep);
  next_reneighbor = schedule_.next();

  const Measured m = measure();
  if (pricing_.refits(check.start)) refit_costs(m, check.interval_steps);
  const fb::RankWork work = pricing_.price(m.counts, check.start, cpu_work_, check.interval_steps);
  fb::CheckRow row = check_row(work);
  if (trigger_.fires(row.work.imbalance, comm->nprocs)) {
    const double t0 = MPI_Wtime();
    repartition(m, work, row.work.sum);
    row.partition_seconds = MPI_Wtime() - t0;
    outputs_.seconds_total += row.partition_seconds;
    row.repartitioned = true;
    row.migrated = outputs_.migrated_last;
  }
  if (out_) write_row(row);
}

// The spreads of one check over the ranks (work, measured time, ghosts); opens the next interval
// of measured time.
fb::CheckRow FixBalanceGraph::check_row(const fb::RankWork& work)
{
  fb::CheckRow row;
  row.step = update->ntimestep;
  row.natoms = atom->natoms;
  row.work = fb::reduce_spread(work.total, world);
  row.cpu = fb::reduce_spread(cpu_work_, world);
  row.cpu_per_rank.resize(comm->me == 0 ? comm->nprocs : 1);
  MPI_Gather(&cpu_work_, 1, MPI_DOUBLE, row.cpu_per_rank.data(), 1, MPI_DOUBLE, 0, world);
  cpu_work_ = 0;
  row.ghosts = fb::reduce_spread(atom->nghost, world);
  outputs_.record_check(row.work, row.cpu, row.ghosts);
  return row;
}

void FixBalanceGraph::write_row(fb::CheckRow row) const
{
  row.predicted_imbalance = outputs_.predicted_imbalance;
  row.edge_cut = outputs_.edge_cut;
  row.migration_seconds_total = comm_graph_->migration_seconds();
  fputs(fb::report_row(row).c_str(), out_);
  fflush(out_);
}

FixBalanceGraph::Measured FixBalanceGraph::measure()
{
  Measured m;
  m.counts.reset(atom->nlocal, static_cast<int>(primitive_walls_.size()));
  if (spec_.cell_factor > 0) bin_cells(m);
  count_pairs(m);
  count_walls_and_facets(m);
  return m;
}

// The cell grid over the box (cells cell_factor ghost cutoffs wide) and each particle's cell.
void FixBalanceGraph::bin_cells(Measured& m)
{
  const bool periodic[3] = {domain->periodicity[0] != 0, domain->periodicity[1] != 0,
                            domain->periodicity[2] != 0};
  grid_ = fb::make_cell_grid(domain->boxlo, domain->boxhi, spec_.cell_factor * comm->cutghost[0],
                             domain->dimension, periodic);
  m.cell.resize(atom->nlocal);
  for (int i = 0; i < atom->nlocal; ++i)
    m.cell[i] = grid_.cell_of(atom->x[i]);
}

// Potential targets, sphere-sphere contacts and the graph's edges from the host's own neighbour
// list: no second search.
void FixBalanceGraph::count_pairs(Measured& m) const
{
  NeighList* list = force->pair->list;
  if (!list || !list->ilist) return;
  const int nlocal = atom->nlocal;
  double** x = atom->x;
  const double* radius = atom->radius;
  const int* tag = atom->tag;
  // With newton off a pair that straddles two ranks is in both ranks' lists; keep one copy.
  const bool newton = force->newton_pair != 0;
  const fb::EdgeWeights weights = fb::edge_weights(spec_.graph_model, pricing_.costs());
  const bool by_cell = spec_.cell_factor > 0;
  const bool distributed = fb::partitioner_info(spec_.partitioner).distributed;
  const bool recount = !take_pair_counts(m);
  for (int ii = 0; ii < list->inum; ++ii) {
    const int i = list->ilist[ii];
    if (i >= nlocal) continue;
    const int* jlist = list->firstneigh[i];
    const int jnum = list->numneigh[i];
    for (int jj = 0; jj < jnum; ++jj) {
      const int j = jlist[jj] & NEIGHMASK;
      const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
      const double rs = radius[i] + radius[j];
      const bool touching = dx * dx + dy * dy + dz * dz < rs * rs;
      // A pair of two local particles goes to the one with the lower tag, not to the one whose
      // row the half list put it in: the costs do not depend on the order of the atoms.
      const int payer = j < nlocal && tag[j] < tag[i] ? j : i;
      m.counts.potential[payer] += 1;
      if (recount) m.counts.contacts[payer] += touching;
      if (!newton && j >= nlocal && tag[i] > tag[j]) continue;
      const std::int64_t a = by_cell ? m.cell[i] : tag[i];
      const std::int64_t b = by_cell ? grid_.cell_of(x[j]) : tag[j];
      if (by_cell && a == b) continue; // inside one vertex
      m.edges.insert(m.edges.end(), {a, b, weights.of(touching)});
      if (distributed) m.ends.insert(m.ends.end(), {i, j});
    }
  }
}

// Contacts and bridges of the last step as pair_style fracdem/gran counted them while computing
// them; false where it has none of that step (another pair style, 'counts recount').
bool FixBalanceGraph::take_pair_counts(Measured& m) const
{
  if (!pair_counts_) return false;
  const PairFracdemGran::WorkCounts& c = pair_counts_->work_counts();
  // Particles inserted since (earlier in this pre_exchange) have done nothing yet.
  const int n = std::min<int>(atom->nlocal, static_cast<int>(c.contacts.size()));
  if (c.step != update->ntimestep - 1 && c.step != update->ntimestep) return false;
  std::copy(c.contacts.begin(), c.contacts.begin() + n, m.counts.contacts.begin());
  std::copy(c.bridges.begin(), c.bridges.begin() + n, m.counts.bridges.begin());
  return true;
}

// Primitive walls of fix wall/gran (their work runs outside Pair time): a gap test for every
// particle, and the contact law for those touching. Facet checks and contacts of FE bodies.
void FixBalanceGraph::count_walls_and_facets(Measured& m) const
{
  const int nlocal = atom->nlocal;
  for (FixWallGran* w : primitive_walls_) {
    PrimitiveWall* pw = w->primitiveWall();
    double delta[3];
    for (int i = 0; i < nlocal; ++i)
      if (pw->resolveContact(atom->x[i], atom->radius[i], delta) <= 0.0)
        m.counts.wall_contacts[i] += 1;
  }
  for (FixFemBody* b : fem_bodies_) {
    const auto& checks = b->facet_checks();
    const auto& contacts = b->facet_contacts();
    if (static_cast<int>(checks.size()) != nlocal) continue; // no contact evaluated yet
    for (int i = 0; i < nlocal; ++i)
      m.counts.facet_checks[i] += checks[i], m.counts.facet_contacts[i] += contacts[i];
  }
}

// cost fitted: every rank's term sums and measured time of the interval, the same on every rank.
void FixBalanceGraph::refit_costs(const Measured& m, double interval_steps)
{
  constexpr int stride = fb::kCostTerms + 1;
  const fb::TermCounts sums = m.counts.term_sums(atom->nghost);
  double mine[stride];
  std::copy(sums.begin(), sums.end(), mine);
  mine[fb::kCostTerms] = cpu_work_;
  std::vector<double> all(static_cast<std::size_t>(stride) * comm->nprocs);
  MPI_Allgather(mine, stride, MPI_DOUBLE, all.data(), stride, MPI_DOUBLE, world);
  pricing_.refit(all, interval_steps);
}

void FixBalanceGraph::repartition(const Measured& m, const fb::RankWork& work, double work_sum)
{
  const double n_all = sum_over_ranks(atom->nlocal);
  const double mean_cost = n_all > 0 && work_sum > 0 ? work_sum / n_all : 1.0;
  const std::vector<std::int64_t> weight =
      fb::vertex_weights(spec_.graph_model, work.cost, m.counts.potential, mean_cost);
  if (fb::partitioner_info(spec_.partitioner).distributed)
    repartition_distributed(m, weight);
  else if (spec_.cell_factor > 0)
    repartition_cells(m, weight);
  else
    repartition_particles(m, weight);
}

// A partitioner failure keeps the current owners, with a warning naming the failure.
bool FixBalanceGraph::kept_owners(bool failed, const std::string& failure) const
{
  if (failed && comm->me == 0)
    error->warning(FLERR,
                   ("fix balance/graph: partitioning failed, ownership kept: " + failure).c_str());
  return failed;
}

double FixBalanceGraph::sum_over_ranks(double mine) const
{
  double sum = 0;
  MPI_Allreduce(&mine, &sum, 1, MPI_DOUBLE, MPI_SUM, world);
  return sum;
}

// One vertex per particle: the graph is gathered on rank 0 (METIS is serial) and each particle
// is sent to its part's rank at the exchange that follows.
void FixBalanceGraph::repartition_particles(const Measured& m,
                                            const std::vector<std::int64_t>& weight)
{
  const int nlocal = atom->nlocal;
  const std::vector<std::int64_t> tags(atom->tag, atom->tag + nlocal);
  const fb::GatheredGraph gg =
      fb::gather_graph(fb::particle_vertices(tags, weight, m.edges), world);
  const fb::RootSolve s = fb::solve_on_root(
      [&] {
        const fb::RootGraph rg = fb::particle_graph(gg, comm->nprocs);
        fb::PartitionResult r = strategy_.partition(rg.g, rg.old_owner, comm->nprocs);
        r.part = fb::parts_of_entries(rg, r.part);
        return r;
      },
      world);
  if (kept_owners(s.failed, s.failure)) return;
  apply_destinations(fb::scatter_parts(s.result.part, gg, nlocal, world), s.result);
}

// Each particle is sent to the rank dest names at the exchange that follows.
void FixBalanceGraph::apply_destinations(std::vector<int> dest, const fb::PartitionResult& r)
{
  double migrated = 0;
  for (int i = 0; i < atom->nlocal; ++i)
    migrated += dest[i] != comm->me;
  migrated = sum_over_ranks(migrated);
  comm_graph_->enable_graph_ownership("fix balance/graph");
  comm_graph_->set_destinations(std::move(dest));
  record_repartition(r, migrated);
}

// One vertex per particle, left on its rank: vertices numbered rank by rank, the ghosts' numbers
// from their owners, and a partitioner that runs on all ranks; each rank learns the new owners
// of its own particles only.
void FixBalanceGraph::repartition_distributed(const Measured& m,
                                              const std::vector<std::int64_t>& weight)
{
  std::vector<std::int64_t> vtxdist = fb::vertex_ranges(atom->nlocal, world);
  const std::int64_t first = vtxdist[comm->me];
  fb::DistributedGraph g;
  try {
    g = fb::build_distributed_graph(distributed_share(m, weight, first), std::move(vtxdist), world);
  } catch (const std::exception& e) {
    error->one(FLERR, (std::string("fix balance/graph: ") + e.what()).c_str());
  }
  const fb::DistributedResult r =
      fb::partitioner_info(spec_.partitioner).geometric
          ? partition_geometric(g)
          : partition_distributed(spec_.partitioner, g, comm->nprocs, world);
  if (kept_owners(r.failed, r.failure)) return;
  fb::PartitionResult result;
  result.predicted_imbalance = r.predicted_imbalance;
  result.edge_cut = r.edge_cut;
  apply_destinations(r.part, result);
}

// partitioner zoltan-rcb|rib|hsfc: Zoltan cuts this rank's particle positions weighted by the
// graph's vertex weights; the graph's edges measure the cut.
fb::DistributedResult FixBalanceGraph::partition_geometric(const fb::DistributedGraph& g)
{
  const fb::PartitionerInfo& info = fb::partitioner_info(spec_.partitioner);
  if (!geometric_)
    geometric_ = std::make_unique<fb::ZoltanGeometric>(info.zoltan_method, info.name, world);
  const int dim = domain->dimension, nlocal = atom->nlocal;
  std::vector<double> coords(static_cast<std::size_t>(dim) * nlocal);
  for (int i = 0; i < nlocal; ++i)
    for (int d = 0; d < dim; ++d)
      coords[static_cast<std::size_t>(i) * dim + d] = atom->x[i][d];
  const std::vector<double> weight(g.local.vwgt.begin(), g.local.vwgt.end());
  fb::DistributedResult r =
      geometric_->partition(coords, dim, weight, comm->nprocs, fb::kDistributedTolerance);
  if (!r.failed) r.edge_cut = fb::distributed_edge_cut(g, r.part, world);
  return r;
}

// This rank's vertices (weights) and edges (local i, global number of j, weight).
fb::DistributedShare FixBalanceGraph::distributed_share(const Measured& m,
                                                        const std::vector<std::int64_t>& weight,
                                                        std::int64_t first)
{
  // Sized to the per-atom arrays: an insertion fix earlier in this pre_exchange resets nghost,
  // while the forward communication still fills the ghost slots of the last borders.
  const int nlocal = atom->nlocal, nall = atom->nlocal + atom->nghost;
  vertex_number_.assign(std::max({nall, atom->nmax, 1}), -1.0);
  for (int i = 0; i < nlocal; ++i)
    vertex_number_[i] = static_cast<double>(first + i);
  comm->forward_comm_fix(this);
  fb::DistributedShare share;
  share.vwgt = weight;
  share.edges.reserve(m.edges.size());
  for (std::size_t e = 0; 2 * e + 1 < m.ends.size(); ++e) {
    const double j = vertex_number_[m.ends[2 * e + 1]];
    if (j < 0) continue; // a ghost the forward communication did not reach
    share.edges.insert(share.edges.end(),
                       {m.ends[2 * e], static_cast<std::int64_t>(j), m.edges[3 * e + 2]});
  }
  return share;
}

// Returns the values per atom, as LIGGGHTS's forward loop sizes its receives by it.
int FixBalanceGraph::pack_comm(int n, int* list, double* buf, int, int*)
{
  for (int k = 0; k < n; ++k)
    buf[k] = vertex_number_[list[k]];
  return 1;
}

void FixBalanceGraph::unpack_comm(int n, int first, double* buf)
{
  for (int k = 0; k < n; ++k)
    vertex_number_[first + k] = buf[k];
}

// Particles aggregated into cells: every cell of the box gets an owner (empty ones that of the
// nearest occupied cell) and ownership follows the cells from then on.
void FixBalanceGraph::repartition_cells(const Measured& m, const std::vector<std::int64_t>& weight)
{
  const fb::GatheredGraph gg =
      fb::gather_graph(fb::aggregate_cells(weight, m.cell, m.edges, grid_.total()), world);
  std::vector<int> owners(grid_.total());
  const fb::RootSolve s = fb::solve_on_root(
      [&] {
        const fb::RootGraph rg = fb::cell_graph(gg, grid_, comm->nprocs);
        std::vector<double> centres;
        if (spec_.partitioner == fb::Partitioner::Rcb) centres = fb::cell_centres(grid_, rg.cells);
        const int gravity = spec_.partitioner == fb::Partitioner::Layers ? gravity_axis() : -1;
        const fb::PartitionGeometry geometry{&grid_, &rg.cells, &centres, gravity};
        fb::PartitionResult r = strategy_.partition(rg.g, rg.old_owner, comm->nprocs, geometry);
        owners = fb::fill_cell_owners(grid_, rg.cells, r.part);
        note_layout(r.layout);
        return r;
      },
      world);
  if (kept_owners(s.failed, s.failure)) return;
  MPI_Bcast(owners.data(), static_cast<int>(grid_.total()), MPI_INT, 0, world);
  double migrated = 0;
  for (int i = 0; i < atom->nlocal; ++i)
    migrated += owners[m.cell[i]] != comm->me;
  migrated = sum_over_ranks(migrated);
  comm_graph_->enable_graph_ownership("fix balance/graph");
  comm_graph_->set_cell_owners(grid_, std::move(owners));
  record_repartition(s.result, migrated);
}

// partitioner layers: say which layout was chosen whenever it changes (the rcb fallback
// included), not at every repartition.
void FixBalanceGraph::note_layout(const std::string& layout)
{
  const std::string kind = layout.substr(0, layout.find(','));
  if (layout.empty() || kind == layout_kind_) return;
  layout_kind_ = kind;
  log("fix balance/graph: partitioner layers: " + layout + "\n");
}

void FixBalanceGraph::record_repartition(const fb::PartitionResult& r, double migrated)
{
  outputs_.record_repartition(r.predicted_imbalance, r.edge_cut, migrated);
  if (comm->me != 0) return;
  log(fb::repartition_line(update->ntimestep, outputs_.imbalance, spec_.threshold,
                           spec_.graph_model, spec_.cell_factor > 0, r.predicted_imbalance,
                           migrated, r.edge_cut));
  if (spec_.cost_model == fb::CostModel::Fitted && pricing_.has_fit() &&
      pricing_.costs().pair_check > 0)
    log(fb::fitted_costs_line(pricing_.costs()));
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

double FixBalanceGraph::compute_scalar()
{
  return outputs_.imbalance;
}

double FixBalanceGraph::compute_vector(int n)
{
  return outputs_.vector(n, comm_graph_ ? comm_graph_->migration_seconds() : 0.0);
}

// The outputs, schedule, costs and cell owners (rank 0 writes them; every rank holds the same).
void FixBalanceGraph::write_restart(FILE* fp)
{
  if (comm->me != 0) return;
  fb::BalanceRestart r;
  r.outputs = outputs_;
  r.nranks = comm_graph_ && comm_graph_->graph_ownership() ? comm->nprocs : 0;
  r.last_check = schedule_.last_check();
  if (comm_graph_ && comm_graph_->has_cell_owners()) {
    r.grid = comm_graph_->cell_grid();
    r.cell_owners = comm_graph_->cell_owners();
  }
  r.pricing = pricing_.state();
  const std::vector<double> state = fb::pack_balance_restart(r);
  const int size = static_cast<int>(state.size() * sizeof(double));
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(state.data(), sizeof(double), state.size(), fp);
}

void FixBalanceGraph::restart(char* buf)
{
  std::vector<double> state(1);
  memcpy(state.data(), buf, sizeof(double));
  state.resize(state[0] < 0 ? static_cast<std::size_t>(-state[0])
                            : fb::BalanceOutputs::kRestartSize);
  memcpy(state.data(), buf, state.size() * sizeof(double));
  try {
    const fb::BalanceRestart r = fb::unpack_balance_restart(state.data());
    outputs_ = r.outputs;
    if (!r.complete) return;
    schedule_.resume(r.last_check);
    if (!r.pricing.empty()) pricing_.restore(r.pricing);
    restored_ranks_ = r.nranks;
    restored_grid_ = r.grid;
    restored_cells_ = r.cell_owners;
  } catch (const std::exception& e) {
    fail(std::string("reading the restart file: ") + e.what());
  }
}

// Per particle: the rank that owns it.
int FixBalanceGraph::pack_restart(int, double* buf)
{
  buf[0] = 2;
  buf[1] = comm->me;
  return 2;
}

void FixBalanceGraph::unpack_restart(int nlocal, int nth)
{
  double** extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; ++k)
    m += static_cast<int>(extra[nlocal][m]);
  if (static_cast<int>(restored_owner_.size()) < nlocal + 1) restored_owner_.resize(nlocal + 1, -1);
  restored_owner_[nlocal] = static_cast<int>(extra[nlocal][m + 1]);
}

int FixBalanceGraph::size_restart(int)
{
  return 2;
}

int FixBalanceGraph::maxsize_restart()
{
  return 2;
}

// At the first set-up after a restart: the owners the file kept, if it was written on as many
// ranks under graph ownership (cell owners, else each particle's). Collective; whether applied.
bool FixBalanceGraph::restore_ownership()
{
  const int ranks = restored_ranks_;
  restored_ranks_ = 0;
  std::vector<int> owner = std::move(restored_owner_);
  restored_owner_.clear();
  if (ranks == 0) return false;
  const int nlocal = atom->nlocal;
  int mine = ranks == comm->nprocs &&
             (!restored_cells_.empty() || static_cast<int>(owner.size()) == nlocal);
  for (int i = 0; mine && restored_cells_.empty() && i < nlocal; ++i)
    mine = owner[i] >= 0 && owner[i] < comm->nprocs;
  int all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, world);
  if (!all) {
    if (comm->me == 0)
      error->warning(FLERR,
                     ("fix balance/graph: the restart file's owners (" + std::to_string(ranks) +
                      " ranks) do not fit this run (" + std::to_string(comm->nprocs) +
                      " ranks, or particles added or removed since): ownership starts "
                      "from the host's bricks")
                         .c_str());
    return false;
  }
  comm_graph_->enable_graph_ownership("fix balance/graph");
  if (!restored_cells_.empty())
    comm_graph_->set_cell_owners(restored_grid_, std::move(restored_cells_));
  else
    comm_graph_->set_destinations(std::move(owner));
  restored_cells_.clear();
  return true;
}
