// Cell grid for coarse balancing graphs and the breadth-first cell -> rank fill.
#include "balance/cell_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

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

int64_t CellGrid::neighbour(const int64_t c[3], int64_t dx, int64_t dy, int64_t dz) const
{
  int64_t m[3] = {c[0] + dx, c[1] + dy, c[2] + dz};
  for (int d = 0; d < 3; ++d)
    if (m[d] < 0 || m[d] >= n[d]) {
      if (!periodic[d]) return -1;
      m[d] = (m[d] + n[d]) % n[d];
    }
  return id(m[0], m[1], m[2]);
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
          const int64_t nb = grid.neighbour(c, d == 0 ? s : 0, d == 1 ? s : 0, d == 2 ? s : 0);
          if (nb < 0 || owner[nb] >= 0) continue;
          owner[nb] = owner[cell];
          next.push_back(nb);
        }
    }
    frontier.swap(next);
  }
  return owner;
}

Graph build_cell_graph(const CellGrid& grid, const std::vector<int64_t>& cells,
                       const std::vector<int64_t>& vertex_of_cell, const std::vector<int64_t>& vwgt,
                       const std::vector<int64_t>& cell_edges)
{
  const int64_t n = static_cast<int64_t>(cells.size()), total = grid.total();
  if (static_cast<int64_t>(vertex_of_cell.size()) != total)
    throw std::invalid_argument("build_cell_graph: vertex_of_cell needs one entry per grid cell");
  if (static_cast<int64_t>(vwgt.size()) != n)
    throw std::invalid_argument("build_cell_graph: vwgt needs one entry per occupied cell");
  if (cell_edges.size() % 3 != 0)
    throw std::invalid_argument("build_cell_graph: cell_edges must hold (cell, cell, weight) "
                                "triples");
  for (int64_t v = 0; v < n; ++v)
    if (cells[v] < 0 || cells[v] >= total || vertex_of_cell[cells[v]] != v)
      throw std::invalid_argument("build_cell_graph: cells[" + std::to_string(v) +
                                  "] and vertex_of_cell disagree");
  const auto vertex = [&](int64_t cell) {
    return cell >= 0 && cell < total ? vertex_of_cell[cell] : int64_t{-1};
  };

  // Contact entries of both directions by source vertex, in ascending neighbour order: the graph
  // does not depend on the order in which the ranks listed their edges.
  std::vector<WeightedPair> pairs;
  pairs.reserve(cell_edges.size() / 3);
  for (size_t e = 0; e < cell_edges.size(); e += 3) {
    const int64_t a = vertex(cell_edges[e]), b = vertex(cell_edges[e + 1]);
    if (a >= 0 && b >= 0 && a != b) pairs.push_back({a, b, cell_edges[e + 2]});
  }
  const RowEntries contacts = sorted_rows(n, pairs);

  Graph g;
  const int zr = grid.n[2] > 1 ? 1 : 0;
  const size_t stencil = zr ? 26 : 8;
  GraphRowWriter rows(g, n, contacts.entries.size() + stencil * static_cast<size_t>(n));
  for (int64_t v = 0; v < n; ++v) {
    g.vwgt[v] = std::max<int64_t>(1, vwgt[v]);
    for (int64_t k = contacts.start[v]; k < contacts.start[v + 1]; ++k)
      rows.add(v, contacts.entries[k].first, contacts.entries[k].second);
    int64_t c[3];
    grid.coords(cells[v], c);
    for (int dz = -zr; dz <= zr; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int64_t nb = grid.neighbour(c, dx, dy, dz);
          if (nb < 0) continue;
          const int64_t u = vertex_of_cell[nb];
          if (u >= 0 && u != v) rows.add(v, u, 1);
        }
    rows.end_row(v);
  }
  return g;
}

} // namespace fracdem::balance
