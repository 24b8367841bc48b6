// Zoltan's parallel repartitioning on the distributed balancing graph: every rank hands Zoltan
// its own rows, Zoltan weighs edge cut against migration, and each rank gets its vertices' parts.
#pragma once

#include <mpi.h>

#include "ptscotch_partition.h"

namespace fracdem::balance
{

// This build has Zoltan (CMake found libtrilinos-zoltan-dev).
bool have_zoltan();

// Zoltan's LB_APPROACH REPARTITION into nparts parts within `tolerance` (Zoltan's IMBALANCE_TOL):
// `hypergraph` true is LB_METHOD HYPERGRAPH (PHG on the hypergraph Zoltan builds from the graph,
// one net per vertex and its neighbours), false LB_METHOD GRAPH with GRAPH_PACKAGE PHG. The
// current owner of a vertex is its rank, so part numbers keep their meaning and most vertices
// stay (PHG_REPART_MULTIPLIER prices communication against migration). Then the imbalance and
// edge cut on all ranks (distributed_edge_cut). Never throws: a failure (Zoltan's, or a build
// without Zoltan) is agreed by all ranks and reported in `failure` with the rank count and graph
// size.
DistributedResult partition_zoltan(const DistributedGraph& g, int nparts, double tolerance,
                                   bool hypergraph, MPI_Comm comm);

} // namespace fracdem::balance
