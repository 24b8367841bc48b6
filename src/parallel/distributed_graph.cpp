// The distributed balancing graph: global numbering, symmetric rows from each rank's measured
// edges, and the partition's labels and balance agreed over the ranks.
#include "distributed_graph.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>

namespace fracdem::balance
{

namespace
{

struct Entry {
  std::int64_t row, nbr, w; // row: local vertex; nbr: global number
};

// CSR rows from unordered entries: sorted by row and neighbour, duplicates summed.
Graph rows_of(std::vector<Entry> entries, const std::vector<std::int64_t>& vwgt)
{
  std::sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
    return x.row != y.row ? x.row < y.row : x.nbr < y.nbr;
  });
  Graph g;
  const std::int64_t n = static_cast<std::int64_t>(vwgt.size());
  g.xadj.assign(n + 1, 0);
  g.vwgt.resize(n);
  for (std::int64_t v = 0; v < n; ++v)
    g.vwgt[v] = std::max<std::int64_t>(vwgt[v], 1);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const Entry& e = entries[k];
    if (k > 0 && entries[k - 1].row == e.row && entries[k - 1].nbr == e.nbr) {
      g.adjwgt.back() += std::max<std::int64_t>(e.w, 1);
      continue;
    }
    g.adjncy.push_back(e.nbr);
    g.adjwgt.push_back(std::max<std::int64_t>(e.w, 1));
    g.xadj[e.row + 1] = static_cast<std::int64_t>(g.adjncy.size());
  }
  for (std::int64_t v = 0; v < n; ++v) // rows without entries end where the previous one does
    g.xadj[v + 1] = std::max(g.xadj[v + 1], g.xadj[v]);
  return g;
}

// Alltoallv of per-rank buckets of T; returns what arrived, with the per-rank counts and where
// each rank's block starts.
template <typename T>
std::vector<T> exchange(const std::vector<std::vector<T>>& out, MPI_Datatype type, MPI_Comm comm,
                        std::vector<int>& rcount, std::vector<int>& rdisp)
{
  const int nranks = static_cast<int>(out.size());
  std::vector<int> scount(nranks), sdisp(nranks);
  rcount.assign(nranks, 0), rdisp.assign(nranks, 0);
  std::vector<T> sbuf;
  for (int p = 0; p < nranks; ++p) {
    sdisp[p] = static_cast<int>(sbuf.size()), scount[p] = static_cast<int>(out[p].size());
    sbuf.insert(sbuf.end(), out[p].begin(), out[p].end());
  }
  MPI_Alltoall(scount.data(), 1, MPI_INT, rcount.data(), 1, MPI_INT, comm);
  int total = 0;
  for (int p = 0; p < nranks; ++p)
    rdisp[p] = total, total += rcount[p];
  std::vector<T> rbuf(std::max(total, 1));
  sbuf.resize(std::max<std::size_t>(sbuf.size(), 1));
  MPI_Alltoallv(sbuf.data(), scount.data(), sdisp.data(), type, rbuf.data(), rcount.data(),
                rdisp.data(), type, comm);
  rbuf.resize(total);
  return rbuf;
}

} // namespace

std::vector<std::int64_t> vertex_ranges(std::int64_t nlocal, MPI_Comm comm)
{
  int nranks = 1;
  MPI_Comm_size(comm, &nranks);
  std::vector<std::int64_t> counts(nranks);
  MPI_Allgather(&nlocal, 1, MPI_INT64_T, counts.data(), 1, MPI_INT64_T, comm);
  std::vector<std::int64_t> vtxdist(nranks + 1, 0);
  for (int p = 0; p < nranks; ++p)
    vtxdist[p + 1] = vtxdist[p] + counts[p];
  return vtxdist;
}

int owner_of(const std::vector<std::int64_t>& vtxdist, std::int64_t v)
{
  const auto it = std::upper_bound(vtxdist.begin(), vtxdist.end(), v);
  return static_cast<int>(it - vtxdist.begin()) - 1;
}

DistributedGraph build_distributed_graph(const DistributedShare& share,
                                         std::vector<std::int64_t> vtxdist, MPI_Comm comm)
{
  DistributedGraph g;
  MPI_Comm_rank(comm, &g.rank);
  g.vtxdist = std::move(vtxdist);
  const std::int64_t first = g.first(), n = static_cast<std::int64_t>(share.vwgt.size());
  const std::int64_t total = g.global_vertices();
  if (g.vtxdist[g.rank + 1] - first != n)
    throw std::invalid_argument("build_distributed_graph: vtxdist does not match the vertices");
  std::vector<Entry> entries;
  entries.reserve(share.edges.size() / 3 * 2);
  std::vector<std::vector<std::int64_t>> out(g.vtxdist.size() - 1);
  for (std::size_t e = 0; e + 2 < share.edges.size(); e += 3) {
    const std::int64_t a = share.edges[e], b = share.edges[e + 1], w = share.edges[e + 2];
    if (a < 0 || a >= n || b < 0 || b >= total)
      throw std::invalid_argument("build_distributed_graph: edge (" + std::to_string(a) + ", " +
                                  std::to_string(b) + ") out of range");
    if (b == first + a) continue; // a periodic image of the particle itself
    entries.push_back({a, b, w});
    const int owner = owner_of(g.vtxdist, b);
    if (owner == g.rank)
      entries.push_back({b - first, first + a, w});
    else
      out[owner].insert(out[owner].end(), {b, first + a, w});
  }
  std::vector<int> rcount, rdisp;
  const std::vector<std::int64_t> in = exchange(out, MPI_INT64_T, comm, rcount, rdisp);
  for (std::size_t k = 0; k + 2 < in.size(); k += 3)
    entries.push_back({in[k] - first, in[k + 1], in[k + 2]});
  g.local = rows_of(std::move(entries), share.vwgt);
  return g;
}

GraphTotals graph_totals(const DistributedGraph& g, MPI_Comm comm)
{
  double mine[4] = {static_cast<double>(g.local.vwgt.size()),
                    static_cast<double>(g.local.adjncy.size()) / 2, 0, 0};
  for (std::int64_t w : g.local.vwgt)
    mine[2] += static_cast<double>(w);
  for (std::int64_t w : g.local.adjwgt)
    mine[3] += static_cast<double>(w) / 2;
  double sum[4];
  MPI_Allreduce(mine, sum, 4, MPI_DOUBLE, MPI_SUM, comm);
  return {sum[0], sum[1], sum[2], sum[3]};
}

std::vector<int> distributed_labels(const std::vector<int>& part, const std::vector<double>& load,
                                    int nparts, MPI_Comm comm)
{
  int me = 0, nranks = 1;
  MPI_Comm_rank(comm, &me);
  MPI_Comm_size(comm, &nranks);
  std::map<int, double> mine; // the few new parts this rank's vertices fall into
  for (std::size_t v = 0; v < part.size(); ++v)
    mine[part[v]] += load[v];
  std::vector<double> pairs; // (part, weight)
  for (const auto& pw : mine)
    pairs.push_back(pw.first), pairs.push_back(pw.second);
  int count = static_cast<int>(pairs.size());
  std::vector<int> counts(nranks), disp(nranks);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  int total = 0;
  for (int p = 0; p < nranks; ++p)
    disp[p] = total, total += counts[p];
  std::vector<double> all(std::max(total, 1));
  pairs.resize(std::max<std::size_t>(pairs.size(), 1));
  MPI_Allgatherv(pairs.data(), count, MPI_DOUBLE, all.data(), counts.data(), disp.data(),
                 MPI_DOUBLE, comm);
  std::vector<double> overlap(static_cast<std::size_t>(nparts) * nparts, 0.0);
  for (int p = 0; p < nranks && p < nparts; ++p)
    for (int k = disp[p]; k + 1 < disp[p] + counts[p]; k += 2)
      overlap[static_cast<std::size_t>(all[k]) * nparts + p] += all[k + 1];
  return nparts > 1 ? max_overlap_labels(std::move(overlap), nparts) : std::vector<int>(1, 0);
}

double distributed_imbalance(const std::vector<int>& part, const std::vector<double>& load,
                             int nparts, MPI_Comm comm)
{
  std::vector<double> mine(nparts, 0.0), all(nparts, 0.0);
  for (std::size_t v = 0; v < part.size(); ++v)
    mine[part[v]] += load[v];
  MPI_Allreduce(mine.data(), all.data(), nparts, MPI_DOUBLE, MPI_SUM, comm);
  return imbalance(all);
}

double distributed_edge_cut(const DistributedGraph& g, const std::vector<int>& part, MPI_Comm comm)
{
  const int nranks = static_cast<int>(g.vtxdist.size()) - 1;
  const std::int64_t first = g.first(), last = g.vtxdist[g.rank + 1];
  std::vector<std::vector<std::int64_t>> asks(nranks);
  for (std::int64_t u : g.local.adjncy)
    if (u < first || u >= last) asks[owner_of(g.vtxdist, u)].push_back(u);
  std::map<std::int64_t, int> remote; // global number -> its part
  for (auto& a : asks) {
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
  }
  std::vector<int> qcount, qdisp, acount, adisp;
  const std::vector<std::int64_t> asked = exchange(asks, MPI_INT64_T, comm, qcount, qdisp);
  std::vector<std::vector<int>> answers(nranks);
  for (int p = 0; p < nranks; ++p)
    for (int k = qdisp[p]; k < qdisp[p] + qcount[p]; ++k)
      answers[p].push_back(part[asked[k] - first]);
  const std::vector<int> parts = exchange(answers, MPI_INT, comm, acount, adisp);
  for (int p = 0; p < nranks; ++p)
    for (std::size_t k = 0; k < asks[p].size(); ++k)
      remote[asks[p][k]] = parts[adisp[p] + k];
  double mine = 0, sum = 0;
  for (std::size_t v = 0; v + 1 < g.local.xadj.size(); ++v)
    for (std::int64_t e = g.local.xadj[v]; e < g.local.xadj[v + 1]; ++e) {
      const std::int64_t u = g.local.adjncy[e];
      const int pu = u >= first && u < last ? part[u - first] : remote[u];
      if (pu != part[v]) mine += static_cast<double>(g.local.adjwgt[e]);
    }
  MPI_Allreduce(&mine, &sum, 1, MPI_DOUBLE, MPI_SUM, comm);
  return sum / 2;
}

} // namespace fracdem::balance
