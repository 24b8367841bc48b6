// Uniform cell grid over the box: coarse graph vertices for balancing and the cell -> rank map.
#ifndef FRACDEM_BALANCE_CELL_GRID_H
#define FRACDEM_BALANCE_CELL_GRID_H

#include <cstdint>
#include <vector>

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

} // namespace fracdem::balance

#endif
