// Cell grid for coarse balancing graphs and the breadth-first cell -> rank fill.
#include "balance/cell_grid.h"

#include <algorithm>
#include <cmath>

namespace fracdem::balance
{

int64_t CellGrid::cell_of(const double x[3]) const
{
  int64_t c[3];
  for (int d = 0; d < 3; ++d) {
    int64_t k = static_cast<int64_t>(std::floor((x[d] - lo[d]) / size[d]));
    if (periodic[d]) k = ((k % n[d]) + n[d]) % n[d];
    c[d] = std::min(std::max<int64_t>(k, 0), n[d] - 1);
  }
  return id(c[0], c[1], c[2]);
}

void CellGrid::coords(int64_t cell, int64_t c[3]) const
{
  c[0] = cell % n[0];
  c[1] = (cell / n[0]) % n[1];
  c[2] = cell / (n[0] * n[1]);
}

CellGrid make_cell_grid(const double lo[3], const double hi[3], double cell, int dim,
                        const bool periodic[3], int64_t max_cells)
{
  CellGrid g;
  double h = cell;
  for (;;) {
    int64_t total = 1;
    for (int d = 0; d < 3; ++d) {
      const double len = hi[d] - lo[d];
      g.n[d] = d < dim ? std::max<int64_t>(1, static_cast<int64_t>(len / h)) : 1;
      total *= g.n[d];
    }
    if (total <= max_cells) break;
    h *= 1.26;
  }
  for (int d = 0; d < 3; ++d) {
    g.lo[d] = lo[d];
    g.size[d] = (hi[d] - lo[d]) / static_cast<double>(g.n[d]);
    g.periodic[d] = periodic[d] && d < dim;
  }
  return g;
}

std::vector<int> fill_cell_owners(const CellGrid& grid, const std::vector<int64_t>& occupied,
                                  const std::vector<int>& owner_of_occupied)
{
  const int64_t total = grid.total();
  std::vector<int> owner(total, -1);
  std::vector<int64_t> frontier, next;
  for (size_t k = 0; k < occupied.size(); ++k)
    if (occupied[k] >= 0 && occupied[k] < total && owner[occupied[k]] < 0) {
      owner[occupied[k]] = owner_of_occupied[k];
      frontier.push_back(occupied[k]);
    }
  while (!frontier.empty()) {
    next.clear();
    for (int64_t cell : frontier) {
      int64_t c[3];
      grid.coords(cell, c);
      for (int d = 0; d < 3; ++d)
        for (int s = -1; s <= 1; s += 2) {
          int64_t m[3] = {c[0], c[1], c[2]};
          m[d] += s;
          if (m[d] < 0 || m[d] >= grid.n[d]) {
            if (!grid.periodic[d]) continue;
            m[d] = (m[d] + grid.n[d]) % grid.n[d];
          }
          const int64_t nb = grid.id(m[0], m[1], m[2]);
          if (owner[nb] >= 0) continue;
          owner[nb] = owner[cell];
          next.push_back(nb);
        }
    }
    frontier.swap(next);
  }
  return owner;
}

} // namespace fracdem::balance
