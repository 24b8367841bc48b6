// Uniform cell grid over the box: coarse graph vertices for balancing and the cell -> rank map.
#ifndef FRACDEM_BALANCE_CELL_GRID_H
#define FRACDEM_BALANCE_CELL_GRID_H

#include <cstdint>
#include <vector>

#include "balance/graph_partition.h"

namespace fracdem::balance
{

struct CellGrid {
  double lo[3] = {0, 0, 0};
  double size[3] = {1, 1, 1}; // cell edge per dimension
  int64_t n[3] = {1, 1, 1};   // cells per dimension
  bool periodic[3] = {false, false, false};

  int64_t total() const { return n[0] * n[1] * n[2]; }
  // Cell of a point: periodic coordinates wrap, others clamp to the edge cells.
  int64_t cell_of(const double x[3]) const;
  int64_t id(int64_t cx, int64_t cy, int64_t cz) const { return (cz * n[1] + cy) * n[0] + cx; }
  void coords(int64_t id, int64_t c[3]) const;
  // The cell at offset (dx, dy, dz) from the cell at coordinates c, wrapped along periodic
  // dimensions; -1 beyond a non-periodic edge.
  int64_t neighbour(const int64_t c[3], int64_t dx, int64_t dy, int64_t dz) const;
};

// Cells of edge >= `cell` over [lo, hi) (dim 2 or 3; z has one cell in 2D); coarsened uniformly
// until there are at most max_cells.
CellGrid make_cell_grid(const double lo[3], const double hi[3], double cell, int dim,
                        const bool periodic[3], int64_t max_cells = int64_t(1) << 22);

// Owner of every cell: occupied cells keep theirs, empty cells take the owner of the nearest
// occupied cell (breadth-first over face neighbours, periodic wrap), so that particles entering
// an empty region go to the rank that owns its surroundings. All -1 if nothing is occupied.
std::vector<int> fill_cell_owners(const CellGrid& grid, const std::vector<int64_t>& occupied,
                                  const std::vector<int>& owner_of_occupied);

// The graph of occupied cells: vertex v is cell cells[v] (vertex_of_cell maps every cell of the
// grid to its vertex, or -1 if unoccupied) with weight vwgt[v]; an edge of weight 1 joins every
// two touching occupied cells (26 neighbours in 3D, 8 in 2D, periodic wrap, counted once per
// offset that reaches the neighbour) and cell_edges, triples (cell a, cell b, weight >= 1 after
// clamping), add their weights to the edge between a and b (creating it where the cells do not
// touch). Triples naming an unoccupied cell or the same cell twice are dropped. The same graph as
// build_graph over the contact and touching pairs, in one pass over the rows instead of a bucket
// sort of every touching pair (most of a repartition's time on rank 0 went there).
Graph build_cell_graph(const CellGrid& grid, const std::vector<int64_t>& cells,
                       const std::vector<int64_t>& vertex_of_cell, const std::vector<int64_t>& vwgt,
                       const std::vector<int64_t>& cell_edges);

} // namespace fracdem::balance

#endif
