// PT-Scotch's parallel partitioner on the distributed balancing graph: every rank partitions its
// own rows with the others, and gets the new owner of each of its vertices.
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

#include "distributed_graph.h"

namespace fracdem::balance
{

// This build has PT-Scotch (CMake found libptscotch-dev).
bool have_ptscotch();

// The new owners of this rank's vertices and what they predict (the same on every rank).
struct DistributedResult {
  std::vector<int> part; // per local vertex, in [0, nparts)
  double predicted_imbalance = 1.0;
  double edge_cut = 0;
  bool failed = false;
  std::string failure; // failed: what failed, with the rank count and graph size
};

// SCOTCH_dgraphPart into nparts parts within `tolerance` (1.02: 2 % above the average load), on
// all ranks of comm, collectively; then the labels that keep most of the weight where it is
// (distributed_labels), the imbalance of the vertex weights and the edge cut (ghost parts from
// SCOTCH_dgraphHalo). Weights are divided by a common factor where their sums would pass the
// range of SCOTCH_Num (32 bit in Debian). Never throws: a failure (PT-Scotch's, a graph that does
// not fit, or a build without PT-Scotch) is agreed by all ranks and reported in `failure`.
DistributedResult partition_ptscotch(const DistributedGraph& g, int nparts, double tolerance,
                                     MPI_Comm comm);

} // namespace fracdem::balance
