// The balancing graph as ranks hand it over (each rank's vertices and edges) and as the rank that
// partitions it builds it: particle vertices by tag, or particles aggregated into cells.
#ifndef FRACDEM_BALANCE_GATHERED_GRAPH_H
#define FRACDEM_BALANCE_GATHERED_GRAPH_H

#include <cstdint>
#include <vector>

#include "balance/cell_grid.h"
#include "balance/graph_partition.h"

namespace fracdem::balance
{

// One rank's share: vertices as (id, weight) pairs, edges as (id a, id b, weight) triples; ids are
// particle tags or cells.
struct LocalGraph {
  std::vector<std::int64_t> verts, edges;
};

// Every rank's share on one rank, blocks in rank order.
struct GatheredGraph {
  std::vector<std::int64_t> verts, edges; // exactly vtotal and etotal entries
  std::vector<int> vcount, vdisp;         // per rank: its entries of verts and where they start
  int vtotal = 0, etotal = 0;
};

// This rank's particles as vertices (tag, weight) with their edges as measured.
LocalGraph particle_vertices(const std::vector<std::int64_t>& tag,
                             const std::vector<std::int64_t>& weight,
                             std::vector<std::int64_t> edges);
// This rank's particles aggregated into cells: one vertex per occupied cell weighing the sum of its
// particles' weights, and one edge per pair of cells summing the particle edges between them (edges
// of cell ids; ncells: cells of the grid).
LocalGraph aggregate_cells(const std::vector<std::int64_t>& weight,
                           const std::vector<std::int64_t>& cell,
                           const std::vector<std::int64_t>& edges, std::int64_t ncells);

// The graph the partitioner cuts, with each vertex's current owner (and, for cells, its cell).
struct RootGraph {
  Graph g;
  std::vector<int> old_owner;
  std::vector<std::int64_t> cells;        // cell graph: the cell of each vertex
  std::vector<std::int64_t> entry_vertex; // particle graph: the vertex of each gathered entry
};

// Vertices are numbered in ascending tag or cell order, so that the graph (and the partition)
// does not depend on the order in which the ranks hold their particles (a run continued from a
// restart file holds them in another order).
//
// Particle vertices of all ranks (tags positive, at most a few times the particle count: a dense
// index); edges naming a tag not among the vertices are dropped. Owner: the rank that sent it.
RootGraph particle_graph(const GatheredGraph& gg, int nranks);
// The parts of the particle graph's vertices in the order of the gathered entries (scatter_parts).
std::vector<int> parts_of_entries(const RootGraph& rg, const std::vector<int>& part);
// Occupied cells of all ranks; a cell shared by several ranks weighs the sum of their shares and
// starts with the rank holding most of it. Unit edges join touching occupied cells
// (build_cell_graph), which keeps parts compact where particles have no neighbours yet.
RootGraph cell_graph(const GatheredGraph& gg, const CellGrid& grid, int nranks);
// The centres of the cells, three coordinates each (partitioner rcb).
std::vector<double> cell_centres(const CellGrid& grid, const std::vector<std::int64_t>& cells);

} // namespace fracdem::balance

#endif
