// MPI check of the distributed partitioners: a grid graph held in pieces by the ranks is made
// symmetric, partitioned by PT-Scotch or Zoltan on all ranks, and checked against the whole graph
// gathered on rank 0 for the check only (edge count, cut, balance recomputed) and against METIS
// there (edge cut at most 1.5 x METIS's; zoltan-phg, which minimises another measure, 3 x).
//
//   mpirun -np P fracdem_partition_check [N] [scrambled|slabs] [ptscotch|zoltan-graph|zoltan-phg]
//
// The graph: an N x N x N grid, vertex weights 1..3, x edges listed by both ends (weight 1 each,
// so 2 after merging), the others by their lower end only (weight 1). `scrambled` hands the ranks
// the cells in a shuffled order, unequal counts; `slabs` hands rank p the p-th z slab. Prints
// "partition_check ..." on rank 0 and exits 1 when a check fails.
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <string>
#include <vector>

#include "distributed_graph.h"
#include "ptscotch_partition.h"
#include "zoltan_partition.h"

namespace fb = fracdem::balance;

namespace
{

int g_failures = 0;

fb::DistributedResult partition(const std::string& engine, const fb::DistributedGraph& g,
                                int nparts, double tolerance)
{
  if (engine == "ptscotch") return fb::partition_ptscotch(g, nparts, tolerance, MPI_COMM_WORLD);
  return fb::partition_zoltan(g, nparts, tolerance, engine == "zoltan-phg", MPI_COMM_WORLD);
}

void check(bool ok, const std::string& what)
{
  std::printf("%s: %s\n", ok ? "ok" : "FAIL", what.c_str());
  g_failures += !ok;
}

struct Layout {
  std::vector<std::int64_t> cell_of;   // global vertex number -> grid cell
  std::vector<std::int64_t> vertex_of; // grid cell -> global vertex number
  std::vector<std::int64_t> vtxdist;
};

// Which rank holds which cells: vertex numbers are contiguous per rank.
Layout make_layout(std::int64_t n, int nranks, bool scrambled)
{
  const std::int64_t total = n * n * n;
  Layout l;
  l.cell_of.resize(total);
  std::iota(l.cell_of.begin(), l.cell_of.end(), 0);
  l.vtxdist.assign(nranks + 1, 0);
  if (scrambled) {
    std::uint64_t s = 12345;
    for (std::int64_t k = total - 1; k > 0; --k) { // Fisher-Yates with a fixed LCG
      s = s * 6364136223846793005ULL + 1442695040888963407ULL;
      std::swap(l.cell_of[k], l.cell_of[(s >> 33) % (k + 1)]);
    }
    // Unequal shares: rank p's share grows with p.
    const std::int64_t units = static_cast<std::int64_t>(nranks) * (nranks + 1) / 2;
    for (int p = 0; p < nranks; ++p)
      l.vtxdist[p + 1] = p + 1 == nranks ? total : l.vtxdist[p] + total * (p + 1) / units;
  } else {
    for (int p = 0; p < nranks; ++p)
      l.vtxdist[p + 1] = total * (p + 1) / nranks; // z-major cells: slabs
  }
  l.vertex_of.resize(total);
  for (std::int64_t v = 0; v < total; ++v)
    l.vertex_of[l.cell_of[v]] = v;
  return l;
}

// This rank's share: the weights and edges of its cells as a host would list them.
fb::DistributedShare make_share(const Layout& l, std::int64_t n, int me)
{
  fb::DistributedShare s;
  const std::int64_t first = l.vtxdist[me];
  for (std::int64_t v = first; v < l.vtxdist[me + 1]; ++v) {
    const std::int64_t c = l.cell_of[v], x = c % n, y = c / n % n, z = c / (n * n);
    s.vwgt.push_back(1 + c % 3);
    const std::int64_t step[3] = {1, n, n * n};
    const std::int64_t at[3] = {x, y, z};
    for (int d = 0; d < 3; ++d) {
      if (at[d] + 1 < n) s.edges.insert(s.edges.end(), {v - first, l.vertex_of[c + step[d]], 1});
      if (d == 0 && x > 0) s.edges.insert(s.edges.end(), {v - first, l.vertex_of[c - 1], 1});
    }
  }
  return s;
}

// The whole graph and partition on rank 0 (this check only): rows and parts by vertex number.
struct Whole {
  fb::Graph g;
  std::vector<int> part;
};

Whole gather_whole(const fb::DistributedGraph& dg, const std::vector<int>& part, MPI_Comm comm)
{
  int me = 0, nranks = 1;
  MPI_Comm_rank(comm, &me);
  MPI_Comm_size(comm, &nranks);
  std::vector<std::int64_t> triples; // (global a, global b, w) for every arc with a < b
  for (std::size_t v = 0; v + 1 < dg.local.xadj.size(); ++v)
    for (std::int64_t e = dg.local.xadj[v]; e < dg.local.xadj[v + 1]; ++e)
      if (dg.first() + static_cast<std::int64_t>(v) < dg.local.adjncy[e])
        triples.insert(triples.end(), {dg.first() + static_cast<std::int64_t>(v),
                                       dg.local.adjncy[e], dg.local.adjwgt[e]});
  auto gather = [&](std::vector<std::int64_t> mine) {
    int count = static_cast<int>(mine.size());
    std::vector<int> counts(nranks), disp(nranks);
    MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
    int total = 0;
    for (int p = 0; p < nranks; ++p)
      disp[p] = total, total += counts[p];
    std::vector<std::int64_t> all(std::max(total, 1));
    mine.resize(std::max<std::size_t>(mine.size(), 1));
    MPI_Gatherv(mine.data(), count, MPI_INT64_T, all.data(), counts.data(), disp.data(),
                MPI_INT64_T, 0, comm);
    all.resize(total);
    return all;
  };
  const std::vector<std::int64_t> edges = gather(triples);
  const std::vector<std::int64_t> vwgt = gather(dg.local.vwgt);
  const std::vector<std::int64_t> parts =
      gather(std::vector<std::int64_t>(part.begin(), part.end()));
  Whole w;
  if (me != 0) return w;
  std::vector<fb::WeightedPair> pairs;
  for (std::size_t k = 0; k + 2 < edges.size(); k += 3)
    pairs.push_back({edges[k], edges[k + 1], edges[k + 2]});
  w.g = fb::build_graph(static_cast<std::int64_t>(vwgt.size()), vwgt, pairs);
  w.part.assign(parts.begin(), parts.end());
  return w;
}

// Rank 0: the reported figures against the gathered graph, and against METIS on it.
void check_whole(const Whole& w, const fb::DistributedResult& r, std::int64_t n, int nranks,
                 double cut_factor)
{
  const std::int64_t edges = 3 * n * n * (n - 1);
  check(w.g.num_edges() == edges, "symmetric graph: " + std::to_string(w.g.num_edges()) +
                                      " edges, grid has " + std::to_string(edges));
  std::int64_t wsum = 0;
  for (std::int64_t x : w.g.adjwgt)
    wsum += x;
  const std::int64_t want = 2 * (2 * n * n * (n - 1) + 2 * n * n * (n - 1)); // both directions
  check(wsum == want, "edge weights merged: arc weight sum " + std::to_string(wsum) +
                          " (x edges listed twice weigh 2): expected " + std::to_string(want));
  const double cut = static_cast<double>(fb::edge_cut(w.g, w.part));
  const std::vector<double> load(w.g.vwgt.begin(), w.g.vwgt.end());
  const double b = fb::imbalance(fb::part_loads(load, w.part, nranks));
  check(cut == r.edge_cut, "reported edge cut " + std::to_string(r.edge_cut) +
                               " = cut of the gathered partition " + std::to_string(cut));
  check(std::abs(b - r.predicted_imbalance) < 1e-12,
        "reported imbalance " + std::to_string(r.predicted_imbalance) +
            " = imbalance of the gathered partition " + std::to_string(b));
  check(b <= 1.05, "balanced: max/avg of the vertex weights per part " + std::to_string(b) +
                       " <= 1.05 (asked for 1.02)");
  const std::vector<int> metis = fb::partition_kway(w.g, nranks);
  const double metis_cut = static_cast<double>(fb::edge_cut(w.g, metis));
  check(cut <= cut_factor * metis_cut, "edge cut " + std::to_string(cut) +
                                           " <= " + std::to_string(cut_factor) + " x METIS's " +
                                           std::to_string(metis_cut) + " on the gathered graph");
}

// The result against the gathered graph (rank 0), and the share of the weight that stays.
void check_result(const fb::DistributedGraph& g, const fb::DistributedResult& r, std::int64_t n,
                  const std::string& engine)
{
  const int me = g.rank, nranks = static_cast<int>(g.vtxdist.size()) - 1;
  double sums[2] = {0, 0}, all[2];
  for (std::size_t v = 0; v < r.part.size(); ++v)
    sums[0] += (r.part[v] == me) * g.local.vwgt[v], sums[1] += g.local.vwgt[v];
  MPI_Reduce(sums, all, 2, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
  const Whole w = gather_whole(g, r.part, MPI_COMM_WORLD);
  if (me != 0) return;
  // zoltan-phg minimises the nets' connectivity (the ghost copies of the hypergraph Zoltan
  // builds from the graph, one net per vertex and its neighbours), not the edge cut.
  check_whole(w, r, n, nranks, engine == "zoltan-phg" ? 3.0 : 1.5);
  std::printf("weight kept on its rank: %.3f\n", all[0] / all[1]);
}

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  int me = 0, nranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  MPI_Comm_size(MPI_COMM_WORLD, &nranks);
  const std::int64_t n = argc > 1 ? std::atoll(argv[1]) : 16;
  const bool scrambled = argc <= 2 || std::string(argv[2]) != "slabs";
  const std::string engine = argc > 3 ? argv[3] : "ptscotch";
  const Layout l = make_layout(n, nranks, scrambled);
  const fb::DistributedGraph g =
      fb::build_distributed_graph(make_share(l, n, me), l.vtxdist, MPI_COMM_WORLD);
  const fb::DistributedResult r = partition(engine, g, nranks, 1.02);
  if (me == 0 && r.failed) check(false, engine + " partitioned: " + r.failure);
  if (!r.failed) check_result(g, r, n, engine);
  // A failure is agreed by all ranks and names the rank count and graph size.
  const fb::DistributedResult bad = partition(engine, g, nranks, 0.5);
  if (me == 0)
    check(bad.failed &&
              bad.failure.find(std::to_string(nranks) + " ranks, graph of ") != std::string::npos,
          "an impossible tolerance fails, agreed: '" + bad.failure + "'");
  int failures = g_failures;
  MPI_Bcast(&failures, 1, MPI_INT, 0, MPI_COMM_WORLD);
  if (me == 0)
    std::printf("partition_check %s ranks=%d n=%lld layout=%s engine=%s failures=%d\n",
                failures ? "FAIL" : "ok", nranks, static_cast<long long>(n),
                scrambled ? "scrambled" : "slabs", engine.c_str(), failures);
  MPI_Finalize();
  return failures ? 1 : 0;
}
