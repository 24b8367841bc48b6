// Layered partitions: weighted rows and brick-wall parts of a cell graph, and the layout rule.
#include "balance/layered_partition.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>
#include <string>

#include "balance/compact_partition.h"

namespace fracdem::balance
{

namespace
{

struct Cells {
  std::vector<std::array<int64_t, 3>> c; // cell coordinates of every vertex
  std::vector<double> w;                 // weights, clamped (or 1 each for a weightless set)
};

Cells cell_data(const Graph& g, const CellGrid& grid, const std::vector<int64_t>& cells)
{
  if (static_cast<int64_t>(cells.size()) != g.num_vertices())
    throw std::invalid_argument("partition_layers: need one cell per vertex");
  Cells d;
  d.c.resize(cells.size());
  d.w.resize(cells.size());
  double total = 0;
  for (size_t v = 0; v < cells.size(); ++v) {
    grid.coords(cells[v], d.c[v].data());
    d.w[v] = static_cast<double>(std::max<int64_t>(0, g.vwgt[v]));
    total += d.w[v];
  }
  if (!(total > 0)) std::fill(d.w.begin(), d.w.end(), 1.0);
  return d;
}

// Splits idx into k consecutive runs of weights closest to total * j / k at every boundary j,
// each run non-empty where there are at least k entries. Returns the k + 1 run boundaries.
std::vector<size_t> weighted_runs(const std::vector<int64_t>& idx, const std::vector<double>& w,
                                  int k)
{
  double total = 0;
  for (int64_t v : idx)
    total += w[v];
  std::vector<size_t> bound(k + 1, 0);
  bound[k] = idx.size();
  size_t s = 0;
  double prefix = 0;
  for (int j = 1; j < k; ++j) {
    const double target = total * j / k;
    const bool room = idx.size() >= static_cast<size_t>(k);
    const size_t lo = room ? bound[j - 1] + 1 : bound[j - 1];
    const size_t hi = room ? idx.size() - (k - j) : idx.size();
    while (s < lo)
      prefix += w[idx[s++]];
    // Advance while taking the next entry brings the prefix closer to the target.
    while (s < hi && std::abs(prefix + w[idx[s]] - target) < std::abs(prefix - target))
      prefix += w[idx[s++]];
    bound[j] = std::min(s, hi);
  }
  return bound;
}

// Orders idx by the cell coordinate along axis (shifted back by origin and wrapped where the axis
// is periodic), then by the other axes (more cells first), then by index.
void order_along(std::vector<int64_t>& idx, const Cells& d, const CellGrid& grid, int axis,
                 int64_t origin, int centre_axis = -1, int last_axis = -1)
{
  // centre_axis >= 0: within a plane, cells nearest the middle of idx's extent along centre_axis
  // come first, so that a cut stepping inside a plane keeps its step away from the row's edges
  // (where it would touch a further part of the neighbouring row diagonally).
  int64_t mid2 = 0;
  if (centre_axis >= 0 && !idx.empty()) {
    int64_t lo = d.c[idx[0]][centre_axis], hi = lo;
    for (int64_t v : idx)
      lo = std::min(lo, d.c[v][centre_axis]), hi = std::max(hi, d.c[v][centre_axis]);
    mid2 = lo + hi;
  }
  const auto off_centre = [&](int64_t v) {
    return centre_axis < 0 ? 0 : std::abs(2 * d.c[v][centre_axis] - mid2);
  };
  std::array<int, 2> rest{};
  for (int a = 0, k = 0; a < 3; ++a)
    if (a != axis) rest[k++] = a;
  if (grid.n[rest[1]] > grid.n[rest[0]] || rest[0] == last_axis) std::swap(rest[0], rest[1]);
  if (rest[0] == last_axis) std::swap(rest[0], rest[1]);
  const int64_t n = grid.n[axis];
  const auto key = [&](int64_t v) {
    const int64_t x = d.c[v][axis] - origin;
    return grid.periodic[axis] ? ((x % n) + n) % n : x;
  };
  std::sort(idx.begin(), idx.end(), [&](int64_t i, int64_t j) {
    const int64_t a = key(i), b = key(j);
    if (a != b) return a < b;
    const int64_t oa = off_centre(i), ob = off_centre(j);
    if (oa != ob) return oa < ob;
    for (int r : rest)
      if (d.c[i][r] != d.c[j][r]) return d.c[i][r] < d.c[j][r];
    return i < j;
  });
}

// Brick-wall origin of row r: the plane of the parts axis where the weight of all cells, counted
// from plane 0, is closest to r / (rows * per_row) of the total (half a part at two rows).
int64_t row_origin(const Cells& d, const CellGrid& grid, const LayerLayout& l, int r)
{
  const int axis = l.parts_axis;
  if (!grid.periodic[axis] || r == 0 || l.rows < 2 || l.per_row < 2) return 0;
  std::vector<double> plane(grid.n[axis], 0.0);
  double total = 0;
  for (size_t v = 0; v < d.c.size(); ++v)
    plane[d.c[v][axis]] += d.w[v], total += d.w[v];
  const double target = total * r / (static_cast<double>(l.rows) * l.per_row);
  int64_t best = 0;
  double prefix = 0, best_err = target;
  for (int64_t p = 1; p < grid.n[axis]; ++p) {
    prefix += plane[p - 1];
    if (std::abs(prefix - target) < best_err) best_err = std::abs(prefix - target), best = p;
  }
  return best;
}

struct Candidate {
  LayerLayout layout;
  std::vector<int> part;
};

void predict(const Graph& g, const CellGrid& grid, const std::vector<int64_t>& cells, int nparts,
             Candidate& c)
{
  const std::vector<int> partners = grid_partners(grid, cells, c.part, nparts);
  c.layout.partners_max = *std::max_element(partners.begin(), partners.end());
  c.layout.partners_avg =
      static_cast<double>(std::accumulate(partners.begin(), partners.end(), int64_t(0))) / nparts;
  double boundary = 0, total = 0;
  for (int64_t v = 0; v < g.num_vertices(); ++v) {
    const double w = static_cast<double>(std::max<int64_t>(0, g.vwgt[v]));
    total += w;
    for (int64_t k = g.xadj[v]; k < g.xadj[v + 1]; ++k)
      if (c.part[g.adjncy[k]] != c.part[v]) {
        boundary += w;
        break;
      }
  }
  c.layout.ghost = total > 0 ? boundary / total : 0.0;
  const std::vector<double> load(g.vwgt.begin(), g.vwgt.end());
  c.layout.imbalance = imbalance(part_loads(load, c.part, nparts));
}

// Variation of the work from plane to plane along an axis: the coefficient of variation of the
// planes' weights between the first and the last occupied plane (empty planes count as 0).
double plane_variation(const Cells& d, const CellGrid& grid, int a)
{
  std::vector<double> plane(grid.n[a], 0.0);
  int64_t lo = grid.n[a], hi = -1;
  for (size_t v = 0; v < d.c.size(); ++v) {
    plane[d.c[v][a]] += d.w[v];
    lo = std::min(lo, d.c[v][a]), hi = std::max(hi, d.c[v][a]);
  }
  if (hi <= lo) return 0.0;
  double m = 0, m2 = 0;
  for (int64_t p = lo; p <= hi; ++p)
    m += plane[p], m2 += plane[p] * plane[p];
  const double k = static_cast<double>(hi - lo + 1);
  m /= k, m2 /= k;
  return m > 0 ? std::sqrt(std::max(0.0, m2 - m * m)) / m : 0.0;
}

// Cut axes: at least two cells; weighted spread of the cell centres (length) at least half the
// largest; and not layered: the plane-to-plane variation of the work along the axis at most
// kLayeredVariation or twice the smallest of the axes' (a settling bed, dense at the floor and
// dilute above, varies ~10 x more along gravity than across it, where the planes are alike; cut
// across its layers, particles settling through the cuts carry work from part to part: with
// z-strips B at the checks reached 1.33, mean 1.18, on the small bed at 8 ranks).
std::vector<int> cut_axes(const Cells& d, const CellGrid& grid, int gravity_axis)
{
  double spread[3] = {0, 0, 0}, variation[3] = {0, 0, 0}, total = 0, least_variation = -1;
  for (double w : d.w)
    total += w;
  for (int a = 0; a < 3 && total > 0; ++a) {
    double m = 0, m2 = 0;
    for (size_t v = 0; v < d.c.size(); ++v) {
      const double x = (static_cast<double>(d.c[v][a]) + 0.5) * grid.size[a];
      m += d.w[v] * x, m2 += d.w[v] * x * x;
    }
    m /= total, m2 /= total;
    spread[a] = std::sqrt(std::max(0.0, m2 - m * m));
    variation[a] = plane_variation(d, grid, a);
    if (grid.n[a] >= 2 && (least_variation < 0 || variation[a] < least_variation))
      least_variation = variation[a];
  }
  const double largest = std::max({spread[0], spread[1], spread[2]});
  std::vector<int> axes;
  for (int a = 0; a < 3; ++a)
    if (grid.n[a] >= 2 && a != gravity_axis && spread[a] >= 0.5 * largest && spread[a] > 0 &&
        variation[a] <= std::max(kLayeredVariation, 2 * least_variation))
      axes.push_back(a);
  return axes;
}

std::vector<LayerLayout> layouts(const std::vector<int>& axes, const CellGrid& grid, int nparts)
{
  std::vector<LayerLayout> out;
  for (int b : axes)
    if (grid.n[b] >= nparts) {
      LayerLayout l;
      l.rows_axis = b, l.parts_axis = b, l.per_row = nparts;
      out.push_back(l);
    }
  for (int a : axes)
    for (int b : axes)
      for (int rows = 2; rows < nparts && a != b; ++rows)
        if (nparts % rows == 0 && grid.n[a] >= rows && grid.n[b] >= nparts / rows) {
          LayerLayout l;
          l.rows_axis = a, l.rows = rows, l.parts_axis = b, l.per_row = nparts / rows;
          out.push_back(l);
        }
  return out;
}

bool better(const LayerLayout& a, const LayerLayout& b)
{
  if (a.partners_avg != b.partners_avg) return a.partners_avg < b.partners_avg;
  if (a.partners_max != b.partners_max) return a.partners_max < b.partners_max;
  return a.ghost < b.ghost;
}

// The rule: within the load tolerance (all, if none is), within the ghost window of the least
// ghost volume, the fewest partners (average, then maximum), then the least ghost volume; exact
// ties to the first enumerated.
size_t choose(const std::vector<Candidate>& cand, double ubfactor)
{
  bool any_within = false;
  for (const Candidate& c : cand)
    any_within = any_within || c.layout.imbalance <= ubfactor;
  const auto admissible_load = [&](const Candidate& c) {
    return !any_within || c.layout.imbalance <= ubfactor;
  };
  double least_ghost = -1;
  for (const Candidate& c : cand)
    if (admissible_load(c) && (least_ghost < 0 || c.layout.ghost < least_ghost))
      least_ghost = c.layout.ghost;
  size_t best = cand.size();
  for (size_t k = 0; k < cand.size(); ++k) {
    const Candidate& c = cand[k];
    if (!admissible_load(c) || c.layout.ghost > kGhostWindow * least_ghost) continue;
    if (best == cand.size() || better(c.layout, cand[best].layout)) best = k;
  }
  return best;
}

} // namespace

std::string LayerLayout::describe() const
{
  char buf[160];
  static const char* axis[3] = {"x", "y", "z"};
  if (rcb)
    snprintf(buf, sizeof buf, "rcb (fallback)");
  else if (rows == 1)
    snprintf(buf, sizeof buf, "%d strips along %s", per_row, axis[parts_axis]);
  else
    snprintf(buf, sizeof buf, "%d rows across %s x %d parts along %s", rows, axis[rows_axis],
             per_row, axis[parts_axis]);
  std::string s = buf;
  snprintf(buf, sizeof buf, ", predicted partners %.2f (max %d), ghost volume %.3f, B %.3f",
           partners_avg, partners_max, ghost, imbalance);
  return s + buf;
}

std::vector<int> layer_partition(const Graph& g, const CellGrid& grid,
                                 const std::vector<int64_t>& cells, const LayerLayout& l)
{
  if (l.rows < 1 || l.per_row < 1 || l.rows_axis < 0 || l.rows_axis > 2 || l.parts_axis < 0 ||
      l.parts_axis > 2 || (l.rows > 1 && l.rows_axis == l.parts_axis))
    throw std::invalid_argument("layer_partition: rows and per_row must be >= 1, axes in [0, 3) "
                                "and different where rows > 1");
  const Cells d = cell_data(g, grid, cells);
  std::vector<int> part(cells.size(), 0);
  std::vector<int64_t> idx(cells.size());
  std::iota(idx.begin(), idx.end(), int64_t(0));
  std::vector<std::vector<int64_t>> rows(1, idx);
  if (l.rows > 1) {
    // A row boundary stepping inside a plane steps across the third axis, not along the parts
    // axis: a step along it would give one row more weight at one end of that axis than the
    // other row, and shift the row's cuts against the brick-wall offset (measured: two rows' cuts
    // within a cell of each other, a fifth partner, on the large settling bed at 16 parts).
    order_along(idx, d, grid, l.rows_axis, 0, -1, l.parts_axis);
    const std::vector<size_t> b = weighted_runs(idx, d.w, l.rows);
    rows.assign(l.rows, {});
    for (int r = 0; r < l.rows; ++r)
      rows[r].assign(idx.begin() + b[r], idx.begin() + b[r + 1]);
  }
  for (int r = 0; r < l.rows; ++r) {
    std::vector<int64_t>& row = rows[r];
    order_along(row, d, grid, l.parts_axis, row_origin(d, grid, l, r),
                l.rows > 1 ? l.rows_axis : -1);
    const std::vector<size_t> b = weighted_runs(row, d.w, l.per_row);
    for (int k = 0; k < l.per_row; ++k)
      for (size_t t = b[k]; t < b[k + 1]; ++t)
        part[row[t]] = r * l.per_row + k;
  }
  return part;
}

std::vector<int> grid_partners(const CellGrid& grid, const std::vector<int64_t>& cells,
                               const std::vector<int>& part, int nparts)
{
  if (nparts < 1 || part.size() != cells.size())
    throw std::invalid_argument("grid_partners: need nparts >= 1 and one part per cell");
  const std::vector<int> owner = fill_cell_owners(grid, cells, part);
  std::vector<std::vector<int>> adj(nparts);
  const int64_t zr = grid.n[2] > 1 ? 1 : 0;
  for (int64_t cell = 0; cell < grid.total(); ++cell) {
    const int p = owner[cell];
    if (p < 0 || p >= nparts) continue;
    int64_t c[3];
    grid.coords(cell, c);
    for (int64_t dz = -zr; dz <= zr; ++dz)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dx = -1; dx <= 1; ++dx) {
          const int64_t nb = grid.neighbour(c, dx, dy, dz);
          if (nb < 0) continue;
          const int q = owner[nb];
          if (q != p && q >= 0) adj[p].push_back(q);
        }
  }
  std::vector<int> out(nparts);
  for (int p = 0; p < nparts; ++p) {
    std::sort(adj[p].begin(), adj[p].end());
    out[p] = static_cast<int>(std::unique(adj[p].begin(), adj[p].end()) - adj[p].begin());
  }
  return out;
}

std::vector<int> partition_layers(const Graph& g, const CellGrid& grid,
                                  const std::vector<int64_t>& cells, int nparts, double ubfactor,
                                  LayerLayout* chosen, int gravity_axis)
{
  if (nparts < 1) throw std::invalid_argument("partition_layers: nparts must be >= 1");
  const Cells d = cell_data(g, grid, cells);
  if (nparts == 1 || cells.empty()) return std::vector<int>(cells.size(), 0);

  std::vector<Candidate> cand(1);
  std::vector<double> xyz(3 * cells.size());
  for (size_t v = 0; v < cells.size(); ++v)
    for (int a = 0; a < 3; ++a)
      xyz[3 * v + a] = grid.lo[a] + (static_cast<double>(d.c[v][a]) + 0.5) * grid.size[a];
  cand[0].layout.rcb = true;
  cand[0].part = partition_compact(g, xyz, nparts, ubfactor);
  for (const LayerLayout& l : layouts(cut_axes(d, grid, gravity_axis), grid, nparts))
    cand.push_back({l, layer_partition(g, grid, cells, l)});
  for (Candidate& c : cand) {
    const std::vector<double> load(g.vwgt.begin(), g.vwgt.end());
    if (!c.layout.rcb && imbalance(part_loads(load, c.part, nparts)) > ubfactor)
      refine_partition(g, c.part, nparts, ubfactor, 64);
    predict(g, grid, cells, nparts, c);
  }
  Candidate& win = cand[choose(cand, ubfactor)];
  Candidate smoothed = win;
  smooth_partition(g, smoothed.part, nparts, ubfactor);
  predict(g, grid, cells, nparts, smoothed);
  if (smoothed.layout.partners_max <= win.layout.partners_max &&
      smoothed.layout.partners_avg <= win.layout.partners_avg)
    win = std::move(smoothed);
  if (chosen) *chosen = win.layout;
  return win.part;
}

} // namespace fracdem::balance
