// Particle graph construction, METIS partitioning, relabelling and pair-search references.
#include "balance/graph_partition.h"

#include <metis.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

namespace fracdem::balance
{

GraphRowWriter::GraphRowWriter(Graph& g, int64_t n, std::size_t entries_hint)
    : g_(g), slot_row_(n, -1), slot_(n)
{
  g_.xadj.assign(n + 1, 0);
  g_.vwgt.resize(n);
  g_.adjncy.clear(), g_.adjwgt.clear();
  g_.adjncy.reserve(entries_hint);
  g_.adjwgt.reserve(entries_hint);
}

void GraphRowWriter::add(int64_t v, int64_t u, int64_t w)
{
  if (slot_row_[u] == v) {
    g_.adjwgt[slot_[u]] += w;
    return;
  }
  slot_row_[u] = v, slot_[u] = static_cast<int64_t>(g_.adjncy.size());
  g_.adjncy.push_back(u);
  g_.adjwgt.push_back(w);
}

// Two counting sorts (O(n + pairs), where a comparison sort of all directed pairs dominated the
// repartition): the directed entries by neighbour, then stably by source vertex.
RowEntries sorted_rows(int64_t n, const std::vector<WeightedPair>& pairs)
{
  std::vector<int64_t> by_nbr(n + 1, 0);
  RowEntries r;
  r.start.assign(n + 1, 0);
  for (const WeightedPair& p : pairs)
    if (p.i != p.j) ++by_nbr[p.i + 1], ++by_nbr[p.j + 1], ++r.start[p.i + 1], ++r.start[p.j + 1];
  for (int64_t v = 0; v < n; ++v)
    by_nbr[v + 1] += by_nbr[v], r.start[v + 1] += r.start[v];
  struct Directed {
    int64_t from, to, w;
  };
  std::vector<Directed> sorted_by_nbr(by_nbr[n]);
  for (const WeightedPair& p : pairs) {
    if (p.i == p.j) continue;
    const int64_t w = std::max<int64_t>(1, p.w);
    sorted_by_nbr[by_nbr[p.j]++] = {p.i, p.j, w};
    sorted_by_nbr[by_nbr[p.i]++] = {p.j, p.i, w};
  }
  r.entries.resize(r.start[n]);
  std::vector<int64_t> fill(r.start.begin(), r.start.end() - 1);
  for (const Directed& d : sorted_by_nbr)
    r.entries[fill[d.from]++] = {d.to, d.w};
  return r;
}

// Both directions of every pair bucketed by source vertex (a counting sort: O(pairs)), each row
// in the order of the pairs.
RowEntries rows_as_listed(int64_t n, const std::vector<WeightedPair>& pairs)
{
  RowEntries r;
  r.start.assign(n + 1, 0);
  for (const WeightedPair& p : pairs)
    if (p.i != p.j) ++r.start[p.i + 1], ++r.start[p.j + 1];
  for (int64_t v = 0; v < n; ++v)
    r.start[v + 1] += r.start[v];
  r.entries.resize(r.start[n]);
  std::vector<int64_t> fill(r.start.begin(), r.start.end() - 1);
  for (const WeightedPair& p : pairs) {
    if (p.i == p.j) continue;
    const int64_t w = std::max<int64_t>(1, p.w);
    r.entries[fill[p.i]++] = {p.j, w};
    r.entries[fill[p.j]++] = {p.i, w};
  }
  return r;
}

Graph build_graph(int64_t n, const std::vector<int64_t>& vertex_weight,
                  const std::vector<WeightedPair>& pairs, RowOrder order)
{
  if (n < 0 || static_cast<int64_t>(vertex_weight.size()) != n)
    throw std::invalid_argument("build_graph: vertex_weight must have one entry per vertex");
  for (const WeightedPair& p : pairs)
    if (p.i < 0 || p.i >= n || p.j < 0 || p.j >= n)
      throw std::invalid_argument("build_graph: pair (" + std::to_string(p.i) + "," +
                                  std::to_string(p.j) + ") out of range");
  const RowEntries sorted =
      order == RowOrder::Ascending ? sorted_rows(n, pairs) : rows_as_listed(n, pairs);
  Graph g;
  GraphRowWriter rows(g, n, sorted.entries.size());
  for (int64_t v = 0; v < n; ++v) {
    g.vwgt[v] = std::max<int64_t>(1, vertex_weight[v]);
    for (int64_t k = sorted.start[v]; k < sorted.start[v + 1]; ++k)
      rows.add(v, sorted.entries[k].first, sorted.entries[k].second);
    rows.end_row(v);
  }
  return g;
}

double imbalance(const std::vector<double>& work_per_part)
{
  if (work_per_part.empty()) throw std::invalid_argument("imbalance: no parts");
  const double sum = std::accumulate(work_per_part.begin(), work_per_part.end(), 0.0);
  if (sum <= 0) return 1.0;
  const double mx = *std::max_element(work_per_part.begin(), work_per_part.end());
  return mx * static_cast<double>(work_per_part.size()) / sum;
}

std::vector<double> part_loads(const std::vector<double>& vertex_load, const std::vector<int>& part,
                               int nparts)
{
  std::vector<double> load(nparts, 0.0);
  for (size_t v = 0; v < part.size() && v < vertex_load.size(); ++v)
    if (part[v] >= 0 && part[v] < nparts) load[part[v]] += vertex_load[v];
  return load;
}

int64_t edge_cut(const Graph& g, const std::vector<int>& part)
{
  if (static_cast<int64_t>(part.size()) != g.num_vertices())
    throw std::invalid_argument("edge_cut: need one part per vertex");
  int64_t cut = 0;
  for (int64_t v = 0; v < g.num_vertices(); ++v)
    for (int64_t k = g.xadj[v]; k < g.xadj[v + 1]; ++k)
      if (part[v] != part[g.adjncy[k]]) cut += g.adjwgt[k];
  return cut / 2; // each cut edge was seen from both ends
}

namespace
{

template <typename T> idx_t to_idx(T v)
{
  if (v > static_cast<T>(std::numeric_limits<idx_t>::max()))
    throw std::overflow_error("partition_kway: graph too large for METIS idx_t");
  return static_cast<idx_t>(v);
}

// METIS sums weights in idx_t: a common factor brings the total under ~2^30 (half the range,
// headroom for its internal sums) while keeping ratios and every weight >= 1.
std::vector<idx_t> scaled_weights(const std::vector<int64_t>& w)
{
  const double limit = static_cast<double>(int64_t(1) << 30);
  const double total = std::accumulate(w.begin(), w.end(), 0.0);
  const double factor = total > limit ? total / limit : 1.0;
  std::vector<idx_t> out(w.size());
  int64_t sum = 0;
  for (size_t k = 0; k < w.size(); ++k) {
    out[k] = static_cast<idx_t>(std::max<int64_t>(
        1, std::llround(static_cast<double>(std::max<int64_t>(w[k], 1)) / factor)));
    sum += out[k];
  }
  // Only reachable when the clamp to 1 dominates, i.e. more than ~2^30 entries.
  if (sum > std::numeric_limits<idx_t>::max() / 2)
    throw std::overflow_error("partition_kway: weights do not fit METIS idx_t");
  return out;
}

} // namespace

std::vector<int> partition_kway(const Graph& g, int nparts, double ubfactor)
{
  const int64_t n = g.num_vertices();
  if (nparts < 1) throw std::invalid_argument("partition_kway: nparts must be >= 1");
  if (static_cast<int64_t>(g.vwgt.size()) != n || g.adjwgt.size() != g.adjncy.size() ||
      (n > 0 && g.xadj.back() != static_cast<int64_t>(g.adjncy.size())))
    throw std::invalid_argument("partition_kway: inconsistent CSR arrays");
  if (n == 0) return {};
  if (nparts == 1) return std::vector<int>(n, 0);
  idx_t nvtxs = to_idx(n), ncon = 1, np = nparts, objval = 0;
  std::vector<idx_t> xadj(g.xadj.size()), adjncy(g.adjncy.size());
  for (size_t k = 0; k < xadj.size(); ++k)
    xadj[k] = to_idx(g.xadj[k]);
  for (size_t k = 0; k < adjncy.size(); ++k)
    adjncy[k] = static_cast<idx_t>(g.adjncy[k]);
  std::vector<idx_t> vwgt = scaled_weights(g.vwgt), adjwgt = scaled_weights(g.adjwgt);
  std::vector<idx_t> part(n, 0);
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_SEED] = 7;
  options[METIS_OPTION_CONTIG] = 0;
  // UFACTOR 0 leaves METIS no room to move vertices during refinement: keep at least 0.1 %.
  options[METIS_OPTION_UFACTOR] =
      std::max<idx_t>(1, static_cast<idx_t>(std::lround((ubfactor - 1.0) * 1000)));
  // METIS rejects an empty adjacency array pointer on some versions: give it a valid one.
  idx_t dummy = 0;
  idx_t* adj = adjncy.empty() ? &dummy : adjncy.data();
  idx_t* adjw = adjwgt.empty() ? &dummy : adjwgt.data();
  int status = METIS_PartGraphKway(&nvtxs, &ncon, xadj.data(), adj, vwgt.data(), nullptr, adjw, &np,
                                   nullptr, nullptr, options, &objval, part.data());
  if (status != METIS_OK)
    status = METIS_PartGraphRecursive(&nvtxs, &ncon, xadj.data(), adj, vwgt.data(), nullptr, adjw,
                                      &np, nullptr, nullptr, options, &objval, part.data());
  if (status != METIS_OK)
    throw std::runtime_error("partition_kway: METIS failed with status " + std::to_string(status));
  return std::vector<int>(part.begin(), part.end());
}

int refine_partition(const Graph& g, std::vector<int>& part, int nparts, double ubfactor,
                     int max_passes)
{
  const int64_t n = g.num_vertices();
  if (nparts <= 1 || n == 0) return 0;
  std::vector<double> load(nparts, 0.0);
  double total = 0;
  for (int64_t v = 0; v < n; ++v) {
    load[part[v]] += static_cast<double>(g.vwgt[v]);
    total += static_cast<double>(g.vwgt[v]);
  }
  const double average = total / nparts, limit = ubfactor * average;
  struct Move {
    double gain;
    int64_t v;
    int to;
  };
  std::vector<Move> moves;
  std::vector<double> conn(nparts, 0.0); // edge weight from v to each part
  std::vector<int> touched;
  int pass = 0;
  for (; pass < max_passes; ++pass) {
    if (*std::max_element(load.begin(), load.end()) <= limit) return pass;
    // Candidate moves out of every part above the average into lighter adjacent parts (parts
    // between the average and the limit must pass load on, or a chain of parts stalls).
    moves.clear();
    for (int64_t v = 0; v < n; ++v) {
      const int from = part[v];
      if (load[from] <= average) continue;
      touched.clear();
      for (int64_t k = g.xadj[v]; k < g.xadj[v + 1]; ++k) {
        const int p = part[g.adjncy[k]];
        if (conn[p] == 0.0) touched.push_back(p);
        conn[p] += static_cast<double>(g.adjwgt[k]);
      }
      const double w = static_cast<double>(g.vwgt[v]);
      int best = -1;
      double best_gain = -1e300;
      for (int p : touched) {
        if (p == from || load[p] + w >= load[from]) continue; // only downhill
        const double gain = conn[p] - conn[from];
        if (gain > best_gain) best_gain = gain, best = p;
      }
      for (int p : touched)
        conn[p] = 0.0;
      if (best >= 0) moves.push_back({best_gain, v, best});
    }
    if (moves.empty()) break;
    std::sort(moves.begin(), moves.end(), [](const Move& a, const Move& b) {
      return a.gain != b.gain ? a.gain > b.gain : a.v < b.v;
    });
    bool moved = false;
    for (const Move& m : moves) {
      const int from = part[m.v];
      const double w = static_cast<double>(g.vwgt[m.v]);
      // Re-check with the loads as they are now: only downhill moves, so the sum of squared
      // loads falls with every move; a part may pass the limit on the way and hand on its excess
      // in the next pass (diffusion through intermediate parts).
      if (load[from] <= average || load[m.to] + w >= load[from]) continue;
      part[m.v] = m.to;
      load[from] -= w;
      load[m.to] += w;
      moved = true;
    }
    if (!moved) break;
  }
  return *std::max_element(load.begin(), load.end()) <= limit ? pass : max_passes + 1;
}

namespace
{

// Hungarian algorithm (potentials, O(n^3)) for a square cost matrix: row r -> column assign[r].
std::vector<int> hungarian_min(const std::vector<double>& cost, int n)
{
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0), v(n + 1, 0), minv(n + 1);
  std::vector<int> p(n + 1, 0), way(n + 1, 0);
  std::vector<char> used(n + 1);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::fill(minv.begin(), minv.end(), inf);
    std::fill(used.begin(), used.end(), 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= n; ++j)
        if (!used[j]) {
          const double cur = cost[(i0 - 1) * n + (j - 1)] - u[i0] - v[j];
          if (cur < minv[j]) minv[j] = cur, way[j] = j0;
          if (minv[j] < delta) delta = minv[j], j1 = j;
        }
      for (int j = 0; j <= n; ++j)
        if (used[j])
          u[p[j]] += delta, v[j] -= delta;
        else
          minv[j] -= delta;
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0);
  }
  std::vector<int> assign(n);
  for (int j = 1; j <= n; ++j)
    assign[p[j] - 1] = j - 1;
  return assign;
}

} // namespace

std::vector<int> relabel_max_overlap(const std::vector<int>& new_part,
                                     const std::vector<int>& old_owner,
                                     const std::vector<double>& vertex_migration_weight, int nparts)
{
  if (nparts <= 1) return new_part;
  // overlap[a][b]: weight of vertices in new part a that live on rank b now.
  std::vector<double> overlap(static_cast<size_t>(nparts) * nparts, 0.0);
  for (size_t v = 0; v < new_part.size(); ++v) {
    const int a = new_part[v], b = v < old_owner.size() ? old_owner[v] : -1;
    if (a < 0 || a >= nparts || b < 0 || b >= nparts) continue;
    overlap[static_cast<size_t>(a) * nparts + b] +=
        v < vertex_migration_weight.size() ? vertex_migration_weight[v] : 1.0;
  }
  const std::vector<int> label = max_overlap_labels(std::move(overlap), nparts);
  std::vector<int> out(new_part.size());
  for (size_t v = 0; v < new_part.size(); ++v)
    out[v] = new_part[v] >= 0 && new_part[v] < nparts ? label[new_part[v]] : new_part[v];
  return out;
}

std::vector<int> max_overlap_labels(std::vector<double> overlap, int nparts)
{
  if (overlap.size() != static_cast<size_t>(nparts) * nparts)
    throw std::invalid_argument("max_overlap_labels: overlap needs nparts * nparts entries");
  for (double& o : overlap)
    o = -o; // maximise overlap = minimise its negative
  return hungarian_min(overlap, nparts);
}

double migration_weight(const std::vector<int>& from, const std::vector<int>& to,
                        const std::vector<double>& vertex_migration_weight)
{
  double w = 0;
  for (size_t v = 0; v < from.size() && v < to.size(); ++v)
    if (from[v] != to[v])
      w += v < vertex_migration_weight.size() ? vertex_migration_weight[v] : 1.0;
  return w;
}

namespace
{

double min_image(double d, int dim, const double lo[3], const double hi[3], const bool per[3])
{
  if (!per[dim]) return d;
  const double L = hi[dim] - lo[dim];
  return d - L * std::round(d / L);
}

// The one predicate both searches use, so that they agree bit for bit on borderline pairs.
inline bool within_reach(const double* xyz, const double* radius, double skin, int64_t i, int64_t j,
                         const double lo[3], const double hi[3], const bool per[3])
{
  double r2 = 0;
  for (int d = 0; d < 3; ++d) {
    const double dd = min_image(xyz[3 * i + d] - xyz[3 * j + d], d, lo, hi, per);
    r2 += dd * dd;
  }
  const double reach = radius[i] + radius[j] + skin;
  return r2 < reach * reach;
}

int64_t sphere_count(const std::vector<double>& xyz, const std::vector<double>& radius)
{
  if (xyz.size() != 3 * radius.size())
    throw std::invalid_argument("pair search: xyz must hold 3 coordinates per radius");
  return static_cast<int64_t>(radius.size());
}

} // namespace

std::vector<std::pair<int64_t, int64_t>>
brute_force_pairs(const std::vector<double>& xyz, const std::vector<double>& radius, double skin,
                  const double box_lo[3], const double box_hi[3], const bool periodic[3])
{
  const int64_t n = sphere_count(xyz, radius);
  std::vector<std::pair<int64_t, int64_t>> out;
  for (int64_t i = 0; i < n; ++i)
    for (int64_t j = i + 1; j < n; ++j)
      if (within_reach(xyz.data(), radius.data(), skin, i, j, box_lo, box_hi, periodic))
        out.emplace_back(i, j);
  return out;
}

std::vector<std::pair<int64_t, int64_t>>
binned_pairs(const std::vector<double>& xyz, const std::vector<double>& radius, double skin,
             const double box_lo[3], const double box_hi[3], const bool periodic[3])
{
  const int64_t n = sphere_count(xyz, radius);
  std::vector<std::pair<int64_t, int64_t>> out;
  if (n < 2) return out;
  const double reach = 2 * *std::max_element(radius.begin(), radius.end()) + skin;
  if (!(reach > 0)) return out; // no distance is below a non-positive reach
  // Bins at least one reach wide (plus a hair, so rounding in the bin index cannot put a pair two
  // bins apart); more bins than about 2n only cost memory, and wider bins stay correct.
  int64_t nb[3];
  double len[3], inv[3];
  for (int d = 0; d < 3; ++d) {
    len[d] = box_hi[d] - box_lo[d];
    const double fit = len[d] > 0 ? len[d] / (reach * (1 + 1e-9)) : 1.0;
    nb[d] = static_cast<int64_t>(std::clamp(fit, 1.0, 1e6));
  }
  const double cap = std::max(27.0, 2.0 * static_cast<double>(n));
  const double nbins = static_cast<double>(nb[0]) * static_cast<double>(nb[1]) * nb[2];
  if (nbins > cap) {
    const double shrink = std::cbrt(nbins / cap);
    for (int64_t& m : nb)
      m = std::max<int64_t>(1, static_cast<int64_t>(static_cast<double>(m) / shrink));
  }
  for (int d = 0; d < 3; ++d)
    inv[d] = len[d] > 0 ? static_cast<double>(nb[d]) / len[d] : 0.0;

  // Counting sort into CSR bins. Periodic coordinates wrap first (atoms may sit just outside the
  // box between re-neighbourings); others clamp, which never separates close atoms by two bins.
  std::vector<int64_t> bin(n), start(static_cast<size_t>(nb[0] * nb[1] * nb[2]) + 1, 0), member(n);
  for (int64_t i = 0; i < n; ++i) {
    int64_t c[3];
    for (int d = 0; d < 3; ++d) {
      double x = xyz[3 * i + d] - box_lo[d];
      if (periodic[d] && len[d] > 0) x -= len[d] * std::floor(x / len[d]);
      const double t = x * inv[d];
      c[d] = !(t > 0)                              ? 0
             : t >= static_cast<double>(nb[d] - 1) ? nb[d] - 1
                                                   : static_cast<int64_t>(t);
    }
    bin[i] = (c[2] * nb[1] + c[1]) * nb[0] + c[0];
    ++start[bin[i] + 1];
  }
  for (size_t k = 1; k < start.size(); ++k)
    start[k] += start[k - 1];
  {
    std::vector<int64_t> fill(start.begin(), start.end() - 1);
    for (int64_t i = 0; i < n; ++i)
      member[fill[bin[i]]++] = i;
  }

  // Distinct neighbour coordinates along one dimension: with fewer than three bins a periodic
  // stencil would visit a bin twice and report its pairs twice.
  auto neighbours = [&](int64_t c, int d, int64_t* q) {
    int m = 0;
    for (int64_t o = -1; o <= 1; ++o) {
      int64_t k = c + o;
      if (k < 0 || k >= nb[d]) {
        if (!periodic[d]) continue;
        k = (k + nb[d]) % nb[d];
      }
      if (std::find(q, q + m, k) == q + m) q[m++] = k;
    }
    return m;
  };

  // Half stencil: each unordered pair of bins is visited once, from its lower linear index.
  const double* x = xyz.data();
  const double* r = radius.data();
  int64_t qx[3], qy[3], qz[3];
  for (int64_t cz = 0, a = 0; cz < nb[2]; ++cz)
    for (int64_t cy = 0; cy < nb[1]; ++cy)
      for (int64_t cx = 0; cx < nb[0]; ++cx, ++a) {
        if (start[a] == start[a + 1]) continue;
        const int mx = neighbours(cx, 0, qx), my = neighbours(cy, 1, qy),
                  mz = neighbours(cz, 2, qz);
        for (int iz = 0; iz < mz; ++iz)
          for (int iy = 0; iy < my; ++iy)
            for (int ix = 0; ix < mx; ++ix) {
              const int64_t b = (qz[iz] * nb[1] + qy[iy]) * nb[0] + qx[ix];
              if (b < a) continue;
              for (int64_t s = start[a]; s < start[a + 1]; ++s) {
                const int64_t i = member[s];
                for (int64_t t = b == a ? s + 1 : start[b]; t < start[b + 1]; ++t) {
                  const int64_t lo = std::min(i, member[t]), hi = std::max(i, member[t]);
                  if (within_reach(x, r, skin, lo, hi, box_lo, box_hi, periodic))
                    out.emplace_back(lo, hi);
                }
              }
            }
      }
  std::sort(out.begin(), out.end());
  return out;
}

} // namespace fracdem::balance
