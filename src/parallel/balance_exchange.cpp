// Graph balancing over MPI: shared costs, reductions, the gather on rank 0 and the partition
// handed back.
#include "balance_exchange.h"

#include <algorithm>
#include <exception>

#include "balance/cost_fit.h"
#include "contact/cost_calibration.h"

namespace fracdem::balance
{

InteractionCosts shared_calibrated_costs(MPI_Comm comm)
{
  int me = 0;
  MPI_Comm_rank(comm, &me);
  TermCounts c{};
  if (me == 0) c = cost_array(calibrate_costs());
  MPI_Bcast(c.data(), kCostTerms, MPI_DOUBLE, 0, comm);
  return interaction_costs(c);
}

RankSpread reduce_spread(double mine, MPI_Comm comm)
{
  int nranks = 1;
  MPI_Comm_size(comm, &nranks);
  double sum = 0, max = 0;
  MPI_Allreduce(&mine, &sum, 1, MPI_DOUBLE, MPI_SUM, comm);
  MPI_Allreduce(&mine, &max, 1, MPI_DOUBLE, MPI_MAX, comm);
  return rank_spread(max, sum, nranks);
}

GatheredGraph gather_graph(const LocalGraph& local, MPI_Comm comm)
{
  int me = 0, nprocs = 1;
  MPI_Comm_rank(comm, &me);
  MPI_Comm_size(comm, &nprocs);
  GatheredGraph gg;
  int counts[2] = {static_cast<int>(local.verts.size()), static_cast<int>(local.edges.size())};
  std::vector<int> all_counts(2 * nprocs);
  MPI_Gather(counts, 2, MPI_INT, all_counts.data(), 2, MPI_INT, 0, comm);
  gg.vcount.resize(nprocs), gg.vdisp.resize(nprocs);
  std::vector<int> ecount(nprocs), edisp(nprocs);
  for (int p = 0; p < nprocs; ++p) {
    gg.vcount[p] = all_counts[2 * p], gg.vdisp[p] = gg.vtotal, gg.vtotal += gg.vcount[p];
    ecount[p] = all_counts[2 * p + 1], edisp[p] = gg.etotal, gg.etotal += ecount[p];
  }
  gg.verts.resize(me == 0 ? std::max(gg.vtotal, 1) : 1);
  gg.edges.resize(me == 0 ? std::max(gg.etotal, 1) : 1);
  MPI_Gatherv(local.verts.data(), counts[0], MPI_INT64_T, gg.verts.data(), gg.vcount.data(),
              gg.vdisp.data(), MPI_INT64_T, 0, comm);
  MPI_Gatherv(local.edges.data(), counts[1], MPI_INT64_T, gg.edges.data(), ecount.data(),
              edisp.data(), MPI_INT64_T, 0, comm);
  // The receive buffers had at least one entry (a valid pointer for MPI); hand back the gathered
  // arrays only, so that the edges are whole triples.
  gg.verts.resize(me == 0 ? gg.vtotal : 0);
  gg.edges.resize(me == 0 ? gg.etotal : 0);
  return gg;
}

RootSolve solve_on_root(const std::function<PartitionResult()>& solve, MPI_Comm comm)
{
  int me = 0;
  MPI_Comm_rank(comm, &me);
  RootSolve s;
  int failed = 0;
  if (me == 0) {
    try {
      s.result = solve();
    } catch (const std::exception& ex) {
      failed = 1;
      s.failure = ex.what();
    }
  }
  MPI_Bcast(&failed, 1, MPI_INT, 0, comm);
  s.failed = failed != 0;
  if (s.failed) return s;
  double stats[2] = {s.result.predicted_imbalance, s.result.edge_cut};
  MPI_Bcast(stats, 2, MPI_DOUBLE, 0, comm);
  s.result.predicted_imbalance = stats[0], s.result.edge_cut = stats[1];
  return s;
}

std::vector<int> scatter_parts(const std::vector<int>& part, const GatheredGraph& gg,
                               int nlocal, MPI_Comm comm)
{
  int nprocs = 1;
  MPI_Comm_size(comm, &nprocs);
  std::vector<int> dest(std::max(nlocal, 1));
  std::vector<int> pcount(nprocs), pdisp(nprocs);
  for (int p = 0; p < nprocs; ++p)
    pcount[p] = gg.vcount[p] / 2, pdisp[p] = gg.vdisp[p] / 2;
  MPI_Scatterv(part.data(), pcount.data(), pdisp.data(), MPI_INT, dest.data(), nlocal, MPI_INT, 0,
               comm);
  dest.resize(nlocal);
  return dest;
}

} // namespace fracdem::balance
