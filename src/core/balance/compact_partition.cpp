// Compact partitions: RCB seed, diffusion to the load tolerance, partner-preserving shape pass.
#include "balance/compact_partition.h"

#include <algorithm>
#include <array>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace fracdem::balance
{

namespace
{

void check_part(const Graph& g, const std::vector<int>& part, int nparts, const char* who)
{
  if (nparts < 1) throw std::invalid_argument(std::string(who) + ": nparts must be >= 1");
  if (static_cast<int64_t>(part.size()) != g.num_vertices())
    throw std::invalid_argument(std::string(who) + ": need one part per vertex");
  for (int p : part)
    if (p < 0 || p >= nparts)
      throw std::invalid_argument(std::string(who) + ": part " + std::to_string(p) +
                                  " outside [0, nparts)");
}

struct Rcb {
  const std::vector<double>& xyz;
  std::vector<double> w; // weights clamped to >= 0
  std::vector<int>& part;

  // Parts [first, first + k) for the points idx[b, e).
  void split(std::vector<int64_t>& idx, size_t b, size_t e, int first, int k)
  {
    if (b >= e) return;
    if (k == 1) {
      for (size_t t = b; t < e; ++t)
        part[idx[t]] = first;
      return;
    }
    // Longest side of the bounding box first, then the others by length: the order of the sort.
    double lo[3], hi[3];
    for (int d = 0; d < 3; ++d)
      lo[d] = hi[d] = xyz[3 * idx[b] + d];
    for (size_t t = b; t < e; ++t)
      for (int d = 0; d < 3; ++d)
        lo[d] = std::min(lo[d], xyz[3 * idx[t] + d]), hi[d] = std::max(hi[d], xyz[3 * idx[t] + d]);
    double len[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    std::array<int, 3> dims = {0, 1, 2};
    std::stable_sort(dims.begin(), dims.end(), [&](int a, int c) { return len[a] > len[c]; });
    std::sort(idx.begin() + b, idx.begin() + e, [&](int64_t i, int64_t j) {
      for (int d : dims) {
        const double a = xyz[3 * i + d], c = xyz[3 * j + d];
        if (a != c) return a < c;
      }
      return i < j;
    });
    const int kl = k / 2, kr = k - kl;
    double total = 0;
    for (size_t t = b; t < e; ++t)
      total += w[idx[t]];
    const bool by_count = !(total > 0);
    if (by_count) total = static_cast<double>(e - b);
    const double target = total * kl / k;
    // The split s (points [b, s) to the left) whose left weight is closest to the target; both
    // sides keep a point where there are two or more.
    size_t best = b + (e - b) / 2;
    double best_err = -1, prefix = 0;
    const size_t first_s = e - b >= 2 ? b + 1 : b, last_s = e - b >= 2 ? e - 1 : e;
    for (size_t s = b; s <= last_s; ++s) {
      if (s > b) prefix += by_count ? 1.0 : w[idx[s - 1]];
      if (s < first_s) continue;
      const double err = std::abs(prefix - target);
      if (best_err < 0 || err < best_err) best_err = err, best = s;
    }
    split(idx, b, best, first, kl);
    split(idx, best, e, first + kl, kr);
  }
};

// Directed edge entries between each pair of parts (a < b), for the "no new pair" test.
using PairCounts = std::unordered_map<int64_t, int64_t>;
inline int64_t pair_key(int a, int b, int nparts)
{
  return a < b ? static_cast<int64_t>(a) * nparts + b : static_cast<int64_t>(b) * nparts + a;
}

} // namespace

std::vector<int> partition_rcb(const std::vector<double>& xyz, const std::vector<int64_t>& weight,
                               int nparts)
{
  if (nparts < 1) throw std::invalid_argument("partition_rcb: nparts must be >= 1");
  if (xyz.size() != 3 * weight.size())
    throw std::invalid_argument("partition_rcb: xyz must hold 3 coordinates per weight");
  const size_t n = weight.size();
  std::vector<int> part(n, 0);
  if (nparts == 1 || n == 0) return part;
  Rcb rcb{xyz, std::vector<double>(n), part};
  for (size_t v = 0; v < n; ++v)
    rcb.w[v] = static_cast<double>(std::max<int64_t>(0, weight[v]));
  std::vector<int64_t> idx(n);
  std::iota(idx.begin(), idx.end(), int64_t(0));
  rcb.split(idx, 0, n, 0, nparts);
  return part;
}

int64_t smooth_partition(const Graph& g, std::vector<int>& part, int nparts, double ubfactor,
                         int max_passes)
{
  check_part(g, part, nparts, "smooth_partition");
  const int64_t n = g.num_vertices();
  if (nparts == 1 || n == 0) return 0;
  std::vector<double> load(nparts, 0.0);
  std::vector<int64_t> members(nparts, 0);
  double total = 0;
  for (int64_t v = 0; v < n; ++v) {
    load[part[v]] += static_cast<double>(g.vwgt[v]);
    members[part[v]] += 1;
    total += static_cast<double>(g.vwgt[v]);
  }
  // Receiving parts stay within the tolerance and below the heaviest part: the pass never makes
  // the imbalance worse, nor uses up the tolerance that the seed left unused.
  const double limit =
      std::min(ubfactor * total / nparts, *std::max_element(load.begin(), load.end()));
  PairCounts pairs;
  for (int64_t v = 0; v < n; ++v)
    for (int64_t k = g.xadj[v]; k < g.xadj[v + 1]; ++k) {
      const int q = part[g.adjncy[k]];
      if (q != part[v]) pairs[pair_key(part[v], q, nparts)] += 1;
    }
  const auto adjacent = [&](int a, int b) {
    if (a == b) return true;
    const auto it = pairs.find(pair_key(a, b, nparts));
    return it != pairs.end() && it->second > 0;
  };

  std::vector<double> conn(nparts, 0.0);
  std::vector<int> touched;
  int64_t moved = 0;
  for (int pass = 0; pass < max_passes; ++pass) {
    int64_t moved_now = 0;
    for (int64_t v = 0; v < n; ++v) {
      const int from = part[v];
      touched.clear();
      for (int64_t k = g.xadj[v]; k < g.xadj[v + 1]; ++k) {
        if (g.adjncy[k] == v) continue;
        const int p = part[g.adjncy[k]];
        if (conn[p] == 0.0) touched.push_back(p);
        conn[p] += static_cast<double>(g.adjwgt[k]);
      }
      const double w = static_cast<double>(g.vwgt[v]);
      int best = -1;
      double best_conn = conn[from];
      if (members[from] > 1)
        for (int p : touched) {
          if (p == from || conn[p] <= best_conn || load[p] + w > limit) continue;
          bool no_new_pair = true;
          for (int q : touched)
            no_new_pair = no_new_pair && (q == from || adjacent(p, q));
          if (no_new_pair) best_conn = conn[p], best = p;
        }
      for (int p : touched)
        conn[p] = 0.0;
      if (best < 0) continue;
      // Move v: its edges leave from's pairs and join best's.
      for (int64_t k = g.xadj[v]; k < g.xadj[v + 1]; ++k) {
        if (g.adjncy[k] == v) continue;
        const int q = part[g.adjncy[k]];
        if (q != from) pairs[pair_key(from, q, nparts)] -= 2;
        if (q != best) pairs[pair_key(best, q, nparts)] += 2;
      }
      part[v] = best;
      load[from] -= w, load[best] += w;
      members[from] -= 1, members[best] += 1;
      ++moved_now;
    }
    moved += moved_now;
    if (moved_now == 0) break;
  }
  return moved;
}

std::vector<int> partition_compact(const Graph& g, const std::vector<double>& xyz, int nparts,
                                   double ubfactor)
{
  if (static_cast<int64_t>(xyz.size()) != 3 * g.num_vertices())
    throw std::invalid_argument("partition_compact: xyz must hold 3 coordinates per vertex");
  std::vector<int> part = partition_rcb(xyz, g.vwgt, nparts);
  if (nparts == 1 || part.empty()) return part;
  const std::vector<double> load(g.vwgt.begin(), g.vwgt.end());
  if (imbalance(part_loads(load, part, nparts)) > ubfactor)
    refine_partition(g, part, nparts, ubfactor, 64);
  smooth_partition(g, part, nparts, ubfactor);
  return part;
}

std::vector<int> part_partners(const Graph& g, const std::vector<int>& part, int nparts)
{
  check_part(g, part, nparts, "part_partners");
  std::vector<std::vector<int>> adj(nparts);
  for (int64_t v = 0; v < g.num_vertices(); ++v)
    for (int64_t k = g.xadj[v]; k < g.xadj[v + 1]; ++k) {
      const int q = part[g.adjncy[k]];
      if (q != part[v]) adj[part[v]].push_back(q);
    }
  std::vector<int> out(nparts);
  for (int p = 0; p < nparts; ++p) {
    std::sort(adj[p].begin(), adj[p].end());
    out[p] = static_cast<int>(std::unique(adj[p].begin(), adj[p].end()) - adj[p].begin());
  }
  return out;
}

} // namespace fracdem::balance
