// The balancing graph left on the ranks that build it: each rank's rows of a global CSR graph,
// made symmetric with point-to-point traffic to the ranks its edges reach, and its quality.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <vector>

#include "balance/graph_partition.h"

namespace fracdem::balance
{

// One rank's share as measured: its vertices' weights (global numbers vtxdist[rank] + local index,
// ranks in order) and edges from a local vertex to any vertex: (local a, global b, weight)
// triples. An edge may be listed by one end's rank or by both (weights then add).
struct DistributedShare {
  std::vector<std::int64_t> vwgt;
  std::vector<std::int64_t> edges;
};

// This rank's rows of the whole graph: `local` has one row per local vertex, neighbours by global
// number, each edge in the rows of both ends (whatever rank holds them), duplicates merged, no
// self loops, weights >= 1.
struct DistributedGraph {
  std::vector<std::int64_t> vtxdist; // nranks + 1: rank p holds [vtxdist[p], vtxdist[p + 1])
  Graph local;
  int rank = 0;
  std::int64_t first() const { return vtxdist[rank]; }
  std::int64_t global_vertices() const { return vtxdist.back(); }
};

// The global numbering: every rank's vertex count (one MPI_Allgather of one number).
std::vector<std::int64_t> vertex_ranges(std::int64_t nlocal, MPI_Comm comm);

// The rank whose range holds global vertex v.
int owner_of(const std::vector<std::int64_t>& vtxdist, std::int64_t v);

// Builds this rank's rows from its share: an edge to another rank's vertex is also sent to that
// rank (one MPI_Alltoall of counts, one MPI_Alltoallv of the edges: each rank receives only the
// edges that cross into it). Throws std::invalid_argument on a local index or global number out
// of range (on the rank that finds it).
DistributedGraph build_distributed_graph(const DistributedShare& share,
                                         std::vector<std::int64_t> vtxdist, MPI_Comm comm);

// The sums over all ranks of vertices, edges, vertex weights and edge weights (each edge once).
struct GraphTotals {
  double vertices = 0, edges = 0, vertex_weight = 0, edge_weight = 0;
};
GraphTotals graph_totals(const DistributedGraph& g, MPI_Comm comm);

// The labels that keep most of the weight where it is: every rank's overlap of its vertices with
// the new parts (weight per part, only the parts it has) to every rank (MPI_Allgatherv), and the
// same assignment solved on each (max_overlap_labels): label[a] is the rank new part a goes to.
std::vector<int> distributed_labels(const std::vector<int>& part, const std::vector<double>& load,
                                    int nparts, MPI_Comm comm);

// Sum of the weights of edges whose ends lie in different parts: the parts of other ranks'
// neighbours are asked of their owners (one MPI_Alltoall of counts, two MPI_Alltoallv: the
// numbers asked, the parts answered).
double distributed_edge_cut(const DistributedGraph& g, const std::vector<int>& part, MPI_Comm comm);

// max/avg of the parts' loads (one MPI_Allreduce of nparts numbers).
double distributed_imbalance(const std::vector<int>& part, const std::vector<double>& load,
                             int nparts, MPI_Comm comm);

} // namespace fracdem::balance
