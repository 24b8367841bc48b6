// MPI pieces of graph balancing: the costs shared by all ranks, the spread of a per-rank quantity, the graph gathered on one
// rank, the partition solved there and its answer handed back to every rank.
#pragma once

#include <mpi.h>

#include <functional>
#include <string>
#include <vector>

#include "balance/balance_check.h"
#include "balance/cost_model.h"
#include "balance/gathered_graph.h"
#include "balance/partition_strategy.h"

namespace fracdem::balance
{

// The calibrated costs (calibrate_costs) measured on rank 0 and shared, so every rank weighs alike.
InteractionCosts shared_calibrated_costs(MPI_Comm comm);

// max, sum and max/avg of `mine` over the ranks of comm (two reductions: sum, then max).
RankSpread reduce_spread(double mine, MPI_Comm comm);

// Every rank's vertices and edges on rank 0 (elsewhere empty arrays); blocks in rank order.
GatheredGraph gather_graph(const LocalGraph& local, MPI_Comm comm);

// Runs `solve` on rank 0 and tells every rank whether it threw (`failure`: its message, on rank
// 0) and what the result predicts; the part vector stays on rank 0.
struct RootSolve {
  bool failed = false;
  std::string failure;
  PartitionResult result;
};
RootSolve solve_on_root(const std::function<PartitionResult()>& solve, MPI_Comm comm);

// Each rank's entries of a part vector over the gathered particle vertices (rank 0's `part`, in
// the order of gg's vertex blocks): the destinations of its nlocal particles.
std::vector<int> scatter_parts(const std::vector<int>& part, const GatheredGraph& gg,
                               int nlocal, MPI_Comm comm);

} // namespace fracdem::balance
