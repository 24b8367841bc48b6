// Unit tests of the compact partitioner (`partitioner rcb`): RCB seed, partner-preserving shape
// pass, and against METIS k-way on cell graphs shaped like the settling bed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "balance/cell_grid.h"
#include "balance/compact_partition.h"
#include "balance/graph_partition.h"
#include "test_support.h"

using namespace fracdem::balance;

namespace
{

// Every cell of an nx x ny x nz grid (x, y periodic as in the settling bed) as a vertex of the
// fix's cell graph (26 touching neighbours), weighted by weight(cx, cy, cz); centres in xyz.
struct CellScene {
  CellGrid grid;
  Graph g;
  std::vector<double> xyz;
};

template <typename W> CellScene cell_scene(int nx, int ny, int nz, W weight)
{
  CellScene s;
  const double lo[3] = {0, 0, 0}, hi[3] = {double(nx), double(ny), double(nz)};
  const bool periodic[3] = {true, true, false};
  s.grid = make_cell_grid(lo, hi, 1.0, 3, periodic);
  const int64_t n = s.grid.total();
  std::vector<int64_t> cells(n), vertex_of_cell(n), vwgt(n);
  std::iota(cells.begin(), cells.end(), int64_t(0));
  std::iota(vertex_of_cell.begin(), vertex_of_cell.end(), int64_t(0));
  s.xyz.resize(3 * n);
  for (int64_t v = 0; v < n; ++v) {
    int64_t c[3];
    s.grid.coords(v, c);
    vwgt[v] = weight(c[0], c[1], c[2]);
    for (int d = 0; d < 3; ++d)
      s.xyz[3 * v + d] = static_cast<double>(c[d]) + 0.5;
  }
  s.g = build_cell_graph(s.grid, cells, vertex_of_cell, vwgt, {});
  return s;
}

// The settling bed in cells: a dense bed (weight 100 per cell) under a dilute cloud (weight 6),
// fine enough that one cell is about 1 % of a part at 16 parts.
int64_t bed_weight(int64_t, int64_t, int64_t cz)
{
  return cz < 9 ? 100 : 6;
}

double mean(const std::vector<int>& v)
{
  return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

double load_imbalance(const Graph& g, const std::vector<int>& part, int nparts)
{
  return imbalance(part_loads(std::vector<double>(g.vwgt.begin(), g.vwgt.end()), part, nparts));
}

std::set<std::pair<int, int>> part_pairs(const Graph& g, const std::vector<int>& part)
{
  std::set<std::pair<int, int>> out;
  for (int64_t v = 0; v < g.num_vertices(); ++v)
    for (int64_t k = g.xadj[v]; k < g.xadj[v + 1]; ++k) {
      const int a = part[v], b = part[g.adjncy[k]];
      if (a != b) out.insert({std::min(a, b), std::max(a, b)});
    }
  return out;
}

} // namespace

TEST(CompactPartition, RcbCutsAUniformGridIntoEqualBoxes)
{
  const CellScene s = cell_scene(8, 8, 8, [](int64_t, int64_t, int64_t) { return 1; });
  const std::vector<int> part = partition_rcb(s.xyz, s.g.vwgt, 8);
  EXPECT_DOUBLE_EQ(load_imbalance(s.g, part, 8), 1.0);
  // Eight 4 x 4 x 4 octants: each part's cells span 4 per dimension.
  for (int p = 0; p < 8; ++p) {
    double lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9};
    for (int64_t v = 0; v < s.g.num_vertices(); ++v)
      if (part[v] == p)
        for (int d = 0; d < 3; ++d)
          lo[d] = std::min(lo[d], s.xyz[3 * v + d]), hi[d] = std::max(hi[d], s.xyz[3 * v + d]);
    for (int d = 0; d < 3; ++d)
      EXPECT_DOUBLE_EQ(hi[d] - lo[d], 3.0) << "part " << p << " dim " << d;
  }
  // Uneven part counts split the weight in proportion (3 parts: 1/3 and 2/3 first).
  const std::vector<int> three = partition_rcb(s.xyz, s.g.vwgt, 3);
  EXPECT_LE(load_imbalance(s.g, three, 3), 1.0 + 8.0 * 8.0 / (512.0 / 3.0));
}

TEST(CompactPartition, RcbStaircaseSplitsInsideAPlaneAndHandlesDegenerateInput)
{
  // One row of 5 cells with equal weight into 2 parts along x: 2 | 3 or 3 | 2, never 0 | 5.
  std::vector<double> xyz;
  for (int i = 0; i < 5; ++i)
    xyz.insert(xyz.end(), {double(i), 0.0, 0.0});
  const std::vector<int> p = partition_rcb(xyz, std::vector<int64_t>(5, 1), 2);
  const int left = static_cast<int>(std::count(p.begin(), p.end(), 0));
  EXPECT_TRUE(left == 2 || left == 3);
  // All points on one plane: the cut steps inside it (ordered by the other coordinates).
  std::vector<double> plane;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      plane.insert(plane.end(), {0.0, double(i), double(j)});
  const std::vector<int> q = partition_rcb(plane, std::vector<int64_t>(16, 1), 4);
  for (int k = 0; k < 4; ++k)
    EXPECT_EQ(std::count(q.begin(), q.end(), k), 4);
  // Zero weights: split by count; fewer points than parts: some parts stay empty.
  const std::vector<int> z = partition_rcb(xyz, std::vector<int64_t>(5, 0), 5);
  EXPECT_EQ(std::set<int>(z.begin(), z.end()).size(), 5u);
  const std::vector<int> few = partition_rcb({0, 0, 0, 1, 0, 0}, {1, 1}, 4);
  EXPECT_NE(few[0], few[1]);
  EXPECT_TRUE(partition_rcb({}, {}, 4).empty());
  EXPECT_THROW(partition_rcb({0, 0}, {1}, 2), std::invalid_argument);
  EXPECT_THROW(partition_rcb({0, 0, 0}, {1}, 0), std::invalid_argument);
}

TEST(CompactPartition, SmoothingCutsNoMoreAndAddsNoPartnerPair)
{
  const CellScene s = cell_scene(12, 12, 12, [](int64_t, int64_t, int64_t) { return 10; });
  const int nparts = 6;
  // A noisy strip partition: random boundary cells swapped to the neighbouring strip.
  std::vector<int> part(s.g.num_vertices());
  std::mt19937 rng(3);
  for (int64_t v = 0; v < s.g.num_vertices(); ++v) {
    int64_t c[3];
    s.grid.coords(v, c);
    part[v] = static_cast<int>(c[2] / 2);
    if (c[2] % 2 == 1 && c[2] < 11 && rng() % 3 == 0) part[v] += 1;
  }
  const std::set<std::pair<int, int>> pairs_before = part_pairs(s.g, part);
  const int64_t cut_before = edge_cut(s.g, part);
  const double b_before = load_imbalance(s.g, part, nparts);
  std::vector<int> smoothed = part;
  const int64_t moved = smooth_partition(s.g, smoothed, nparts, 1.05);
  EXPECT_GT(moved, 0);
  EXPECT_LT(edge_cut(s.g, smoothed), cut_before);
  const std::set<std::pair<int, int>> pairs_after = part_pairs(s.g, smoothed);
  EXPECT_TRUE(std::includes(pairs_before.begin(), pairs_before.end(), pairs_after.begin(),
                            pairs_after.end()))
      << "no new pair of adjacent parts";
  EXPECT_LE(load_imbalance(s.g, smoothed, nparts), b_before + 1e-12);
  // A partition without steps stays as it is.
  std::vector<int> slabs(s.g.num_vertices());
  for (int64_t v = 0; v < s.g.num_vertices(); ++v) {
    int64_t c[3];
    s.grid.coords(v, c);
    slabs[v] = static_cast<int>(c[2] / 2);
  }
  std::vector<int> same = slabs;
  EXPECT_EQ(smooth_partition(s.g, same, nparts, 1.02), 0);
  EXPECT_EQ(same, slabs);
  EXPECT_THROW(smooth_partition(s.g, same, 2, 1.02), std::invalid_argument); // parts >= nparts
}

// The claim behind `partitioner rcb`: on a grid graph shaped like the settling bed (dense bed under
// a dilute cloud, x/y periodic), its parts touch no more other parts than RCB's and fewer than
// METIS k-way's, and are balanced within the tolerance, which plain RCB of cells is not always.
TEST(CompactPartition, FewerPartnersThanMetisAndNoMoreThanRcbWithinTolerance)
{
  const CellScene s = cell_scene(12, 12, 24, bed_weight);
  for (int nparts : {4, 8, 16}) {
    const std::vector<int> rcb = partition_rcb(s.xyz, s.g.vwgt, nparts);
    const std::vector<int> compact = partition_compact(s.g, s.xyz, nparts, 1.02);
    const std::vector<int> metis = partition_kway(s.g, nparts, 1.02);
    const std::vector<int> pc = part_partners(s.g, compact, nparts),
                           pr = part_partners(s.g, rcb, nparts),
                           pm = part_partners(s.g, metis, nparts);
    EXPECT_LE(load_imbalance(s.g, compact, nparts), 1.02 + 1e-9) << nparts << " parts";
    EXPECT_LE(mean(pc), mean(pr) + 1e-9) << nparts << " parts";
    EXPECT_LE(*std::max_element(pc.begin(), pc.end()), *std::max_element(pr.begin(), pr.end()))
        << nparts << " parts";
    EXPECT_LT(mean(pc), mean(pm)) << nparts << " parts";
    RecordProperty("partners_" + std::to_string(nparts), std::to_string(mean(pc)) + " compact, " +
                                                             std::to_string(mean(pr)) + " rcb, " +
                                                             std::to_string(mean(pm)) + " metis");
    std::printf("%2d parts: partners avg (max) compact %.2f (%d), rcb %.2f (%d), metis %.2f (%d); "
                "B compact %.4f rcb %.4f metis %.4f\n",
                nparts, mean(pc), *std::max_element(pc.begin(), pc.end()), mean(pr),
                *std::max_element(pr.begin(), pr.end()), mean(pm),
                *std::max_element(pm.begin(), pm.end()), load_imbalance(s.g, compact, nparts),
                load_imbalance(s.g, rcb, nparts), load_imbalance(s.g, metis, nparts));
  }
}

TEST(CompactPartition, PartnersCountAndInputChecks)
{
  const Graph g = fracdem_test::grid_graph(4, 1); // a path of 4 vertices
  EXPECT_EQ(part_partners(g, {0, 0, 1, 2}, 3), (std::vector<int>{1, 2, 1}));
  EXPECT_EQ(part_partners(g, {0, 0, 0, 0}, 2), (std::vector<int>{0, 0}));
  EXPECT_THROW(part_partners(g, {0, 0, 1}, 3), std::invalid_argument);
  EXPECT_THROW(part_partners(g, {0, 0, 1, 3}, 3), std::invalid_argument);
  EXPECT_THROW(partition_compact(g, {0, 0, 0}, 2), std::invalid_argument);
  EXPECT_EQ(partition_compact(g, std::vector<double>(12, 0.0), 1), std::vector<int>(4, 0));
}
