// Unit tests of the load-balance kernels (graph, METIS, relabelling, pair search, cells, costs).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <stdexcept>

#include "contact/cost_calibration.h"
#include "balance/cell_grid.h"
#include "balance/graph_partition.h"
#include "test_support.h"

using namespace fracdem::balance;
using fracdem_test::grid_graph;

TEST(BalanceKernels, BuildGraphMergesSymmetrisesAndDropsSelfLoops)
{
  const Graph g = build_graph(3, {1, 0, 5}, {{0, 1, 2}, {1, 0, 3}, {2, 2, 7}, {1, 2, 1}});
  EXPECT_EQ(g.num_vertices(), 3);
  EXPECT_EQ(g.num_edges(), 2);
  EXPECT_EQ(g.vwgt[1], 1); // zero weight clamped for METIS
  // Every directed entry has its mirror with the same weight; (0,1) carries 2 + 3.
  for (int64_t v = 0; v < 3; ++v)
    for (int64_t k = g.xadj[v]; k < g.xadj[v + 1]; ++k) {
      const int64_t u = g.adjncy[k];
      EXPECT_NE(u, v);
      bool mirrored = false;
      for (int64_t m = g.xadj[u]; m < g.xadj[u + 1]; ++m)
        if (g.adjncy[m] == v && g.adjwgt[m] == g.adjwgt[k]) mirrored = true;
      EXPECT_TRUE(mirrored);
      if ((v == 0 && u == 1) || (v == 1 && u == 0)) EXPECT_EQ(g.adjwgt[k], 5);
    }
  int64_t total = 0;
  for (int64_t w : g.adjwgt)
    total += w;
  EXPECT_EQ(total, 2 * (2 + 3 + 1)); // every merged weight, counted from both ends
  EXPECT_THROW(build_graph(2, {1, 1}, {{0, 2, 1}}), std::invalid_argument);
  EXPECT_THROW(build_graph(2, {1, 1}, {{-1, 0, 1}}), std::invalid_argument);
  EXPECT_THROW(build_graph(2, {1}, {}), std::invalid_argument);
  const Graph lonely = build_graph(2, {3, 4}, {{1, 1, 9}});
  EXPECT_EQ(lonely.num_edges(), 0);
  EXPECT_EQ(lonely.xadj, (std::vector<int64_t>{0, 0, 0}));
}

// The graph does not depend on the order of its pairs (a restarted run lists its particles, and
// so its edges, in another order): rows in ascending neighbour order, for particle and cell graphs.
TEST(BalanceKernels, GraphsDoNotDependOnTheOrderOfTheirPairs)
{
  std::mt19937 rng(5);
  const int64_t n = 40;
  std::uniform_int_distribution<int64_t> vertex(0, n - 1), weight(1, 9);
  std::vector<WeightedPair> pairs;
  for (int k = 0; k < 500; ++k)
    pairs.push_back({vertex(rng), vertex(rng), weight(rng)});
  std::vector<WeightedPair> shuffled = pairs;
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  const std::vector<int64_t> vw(n, 1);
  const Graph a = build_graph(n, vw, pairs, RowOrder::Ascending),
              b = build_graph(n, vw, shuffled, RowOrder::Ascending);
  EXPECT_EQ(a.xadj, b.xadj);
  EXPECT_EQ(a.adjncy, b.adjncy);
  EXPECT_EQ(a.adjwgt, b.adjwgt);
  for (int64_t v = 0; v < n; ++v)
    EXPECT_TRUE(std::is_sorted(a.adjncy.begin() + a.xadj[v], a.adjncy.begin() + a.xadj[v + 1]));
  // The default keeps the order of first appearance: the same graph up to the order in a row.
  const Graph listed = build_graph(n, vw, shuffled);
  EXPECT_EQ(listed.xadj, a.xadj);
  EXPECT_NE(listed.adjncy, a.adjncy);

  // Cell graph: a 5 x 4 x 3 grid, every cell occupied, contact triples in two orders.
  const double lo[3] = {0, 0, 0}, hi[3] = {5, 4, 3};
  const bool periodic[3] = {false, false, false};
  const CellGrid grid = make_cell_grid(lo, hi, 1.0, 3, periodic);
  std::vector<int64_t> cells(grid.total()), vertex_of_cell(grid.total());
  for (int64_t c = 0; c < grid.total(); ++c)
    cells[c] = vertex_of_cell[c] = c;
  std::uniform_int_distribution<int64_t> cell(0, grid.total() - 1);
  std::vector<std::array<int64_t, 3>> triples;
  for (int k = 0; k < 300; ++k)
    triples.push_back({cell(rng), cell(rng), weight(rng)});
  const auto flat = [](const std::vector<std::array<int64_t, 3>>& t) {
    std::vector<int64_t> out;
    for (const auto& e : t)
      out.insert(out.end(), e.begin(), e.end());
    return out;
  };
  const Graph ca = build_cell_graph(grid, cells, vertex_of_cell, cells, flat(triples));
  std::shuffle(triples.begin(), triples.end(), rng);
  const Graph cb = build_cell_graph(grid, cells, vertex_of_cell, cells, flat(triples));
  EXPECT_EQ(ca.adjncy, cb.adjncy);
  EXPECT_EQ(ca.adjwgt, cb.adjwgt);
}

// Random pairs with many repeats in both directions against an ordered-map reference: each row
// holds every neighbour once, with the sum of the weights of all its copies.
TEST(BalanceKernels, BuildGraphMatchesMapReferenceOnRandomPairs)
{
  std::mt19937 rng(11);
  const int64_t n = 60;
  std::uniform_int_distribution<int64_t> vertex(0, n - 1), weight(-2, 9);
  std::vector<WeightedPair> pairs;
  std::map<std::pair<int64_t, int64_t>, int64_t> expected;
  for (int k = 0; k < 2000; ++k) {
    const WeightedPair p{vertex(rng), vertex(rng), weight(rng)};
    pairs.push_back(p);
    if (p.i == p.j) continue;
    const int64_t w = std::max<int64_t>(1, p.w);
    expected[{p.i, p.j}] += w;
    expected[{p.j, p.i}] += w;
  }
  const Graph g = build_graph(n, std::vector<int64_t>(n, 1), pairs);
  std::map<std::pair<int64_t, int64_t>, int64_t> got;
  for (int64_t v = 0; v < n; ++v)
    for (int64_t k = g.xadj[v]; k < g.xadj[v + 1]; ++k) {
      const bool fresh = got.emplace(std::make_pair(v, g.adjncy[k]), g.adjwgt[k]).second;
      EXPECT_TRUE(fresh) << "neighbour " << g.adjncy[k] << " twice in row " << v;
    }
  EXPECT_EQ(got, expected);
}

TEST(BalanceKernels, ImbalanceAnalytic)
{
  EXPECT_DOUBLE_EQ(imbalance({4, 0, 0, 0}), 4.0);
  EXPECT_DOUBLE_EQ(imbalance({2, 2, 2}), 1.0);
  EXPECT_DOUBLE_EQ(imbalance({0, 0}), 1.0);
  EXPECT_DOUBLE_EQ(imbalance({3, 1}), 1.5);
  EXPECT_THROW(imbalance({}), std::invalid_argument);
  const auto loads = part_loads({1, 2, 3, 4}, {0, 1, 1, 0}, 2);
  EXPECT_DOUBLE_EQ(loads[0], 5);
  EXPECT_DOUBLE_EQ(loads[1], 5);
}

TEST(BalanceKernels, EdgeCutOfGridHalves)
{
  const int n = 10;
  const Graph g = grid_graph(n, n);
  std::vector<int> part(n * n);
  for (int v = 0; v < n * n; ++v)
    part[v] = (v % n) < n / 2 ? 0 : 1; // vertical cut line
  EXPECT_EQ(edge_cut(g, part), n);
  for (int v = 0; v < n * n; ++v)
    part[v] = (v % n < n / 2) + 2 * (v / n < n / 2); // quadrants: two full lines
  EXPECT_EQ(edge_cut(g, part), 2 * n);

  // Weighted path 0-1-...-6 with edge (k,k+1) of weight k+1, split after vertex 2 and 4.
  std::vector<WeightedPair> path;
  for (int k = 0; k < 6; ++k)
    path.push_back({k, k + 1, k + 1});
  const Graph p = build_graph(7, std::vector<int64_t>(7, 1), path);
  EXPECT_EQ(edge_cut(p, {0, 0, 0, 1, 1, 2, 2}), 3 + 5);
  EXPECT_EQ(edge_cut(p, std::vector<int>(7, 4)), 0);
  EXPECT_THROW(edge_cut(p, {0, 1}), std::invalid_argument);
}

TEST(BalanceKernels, MetisPartitionsGridEvenlyWithShortCuts)
{
  const int n = 40;
  const Graph g = grid_graph(n, n);
  for (int nparts : {2, 4, 6}) {
    const auto part = partition_kway(g, nparts, 1.02);
    ASSERT_EQ(static_cast<int>(part.size()), n * n);
    std::vector<double> load(nparts, 0);
    for (int p : part) {
      ASSERT_GE(p, 0);
      ASSERT_LT(p, nparts);
      load[p] += 1;
    }
    EXPECT_LE(imbalance(load), 1.03) << nparts << " parts";
    // Straight cuts: 2 parts n, 4 parts 2n; 6 parts about 3n. Allow twice that.
    const double ideal = nparts == 2 ? n : nparts == 4 ? 2 * n : 3 * n;
    EXPECT_LE(edge_cut(g, part), 2 * ideal) << nparts << " parts";
    EXPECT_EQ(part, partition_kway(g, nparts, 1.02)) << "deterministic";
  }
  EXPECT_EQ(partition_kway(g, 1), std::vector<int>(n * n, 0));
  EXPECT_TRUE(partition_kway(Graph{{0}, {}, {}, {}}, 4).empty());
  EXPECT_THROW(partition_kway(g, 0), std::invalid_argument);
}

TEST(BalanceKernels, MetisScalesHugeWeightsAndSplitsEdgelessGraphs)
{
  // Weights far beyond 32-bit idx_t (left half twice the right): scaled by a common factor, so
  // the balance in the original weights still holds.
  const int n = 40;
  const Graph unit = grid_graph(n, n);
  Graph g = unit;
  for (int v = 0; v < n * n; ++v)
    g.vwgt[v] = (v % n < n / 2 ? 2 : 1) * (int64_t(1) << 36);
  const auto part = partition_kway(g, 4, 1.02);
  std::vector<double> vload(g.vwgt.begin(), g.vwgt.end());
  const double max_vertex = *std::max_element(vload.begin(), vload.end());
  const auto load = part_loads(vload, part, 4);
  const double avg = std::accumulate(load.begin(), load.end(), 0.0) / 4;
  EXPECT_LE(*std::max_element(load.begin(), load.end()), 1.02 * avg + max_vertex);
  EXPECT_EQ(part, partition_kway(g, 4, 1.02));

  // No edges at all: METIS still has to balance the vertex weights.
  const int m = 101;
  std::vector<int64_t> w(m);
  for (int v = 0; v < m; ++v)
    w[v] = 1 + v % 3;
  const Graph loose = build_graph(m, w, {});
  const auto lp = partition_kway(loose, 4, 1.02);
  ASSERT_EQ(static_cast<int>(lp.size()), m);
  const auto ll = part_loads(std::vector<double>(w.begin(), w.end()), lp, 4);
  const double lavg = std::accumulate(ll.begin(), ll.end(), 0.0) / 4;
  EXPECT_LE(*std::max_element(ll.begin(), ll.end()), 1.02 * lavg + 3);
  EXPECT_EQ(edge_cut(loose, lp), 0);
}

TEST(BalanceKernels, RelabelRecoversAPermutationWithoutMigration)
{
  std::mt19937 rng(3);
  std::vector<int> owner(200);
  for (auto& o : owner)
    o = static_cast<int>(rng() % 5);
  const std::vector<int> perm = {3, 0, 4, 1, 2};
  std::vector<int> fresh(owner.size());
  for (size_t v = 0; v < owner.size(); ++v)
    fresh[v] = perm[owner[v]];
  const std::vector<double> w(owner.size(), 1.0);
  const auto relabelled = relabel_max_overlap(fresh, owner, w, 5);
  EXPECT_EQ(relabelled, owner);
  EXPECT_DOUBLE_EQ(migration_weight(owner, relabelled, w), 0.0);
}

TEST(BalanceKernels, RelabelMatchesBruteForceOptimum)
{
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const int nparts = 2 + trial % 4; // 2..5
    std::vector<int> owner(300), fresh(300);
    std::vector<double> w(300);
    for (int v = 0; v < 300; ++v) {
      // About one in ten vertices has no current owner (-1 or nparts): it overlaps nothing.
      const int r = static_cast<int>(rng() % (10 * nparts));
      owner[v] = r < 9 * nparts ? r % nparts : (r % 2 ? -1 : nparts);
      fresh[v] = static_cast<int>(rng() % nparts);
      w[v] = 1.0 + (rng() % 7);
    }
    std::vector<int> perm(nparts);
    std::iota(perm.begin(), perm.end(), 0);
    double best = 1e300;
    do {
      std::vector<int> relabelled(300);
      for (int v = 0; v < 300; ++v)
        relabelled[v] = perm[fresh[v]];
      best = std::min(best, migration_weight(owner, relabelled, w));
    } while (std::next_permutation(perm.begin(), perm.end()));
    const auto hung = relabel_max_overlap(fresh, owner, w, nparts);
    EXPECT_DOUBLE_EQ(migration_weight(owner, hung, w), best) << "trial " << trial;
    // The relabelled partition is the same partition (a bijection of labels).
    std::set<std::pair<int, int>> map;
    for (int v = 0; v < 300; ++v)
      map.insert({fresh[v], hung[v]});
    EXPECT_EQ(static_cast<int>(map.size()), nparts);
  }
}

TEST(BalanceKernels, BinnedPairsMatchBruteForce)
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  struct Case {
    double hi[3];
    bool periodic[3];
    double outside; // how far atoms may stray beyond the box (periodic images between rebuilds)
  };
  // Many bins, every periodicity pattern; then a box of only 2 bins in the periodic x and y, where
  // the stencil folds onto itself.
  const std::vector<Case> cases = {{{1.0, 0.8, 0.6}, {false, false, false}, 0.0},
                                   {{1.0, 0.8, 0.6}, {true, false, false}, 0.0},
                                   {{1.0, 0.8, 0.6}, {false, true, false}, 0.02},
                                   {{1.0, 0.8, 0.6}, {true, true, true}, 0.05},
                                   {{0.15, 0.15, 1.0}, {true, true, false}, 0.02},
                                   {{0.15, 0.15, 1.0}, {false, true, true}, 0.0}};
  const double lo[3] = {0, 0, 0};
  for (size_t c = 0; c < cases.size(); ++c) {
    const Case& k = cases[c];
    std::vector<double> xyz(3 * 500), rad(500);
    for (int i = 0; i < 500; ++i) {
      for (int d = 0; d < 3; ++d)
        xyz[3 * i + d] = -k.outside + (k.hi[d] + 2 * k.outside) * u(rng);
      rad[i] = 0.01 + 0.02 * u(rng);
    }
    const auto ref = brute_force_pairs(xyz, rad, 0.01, lo, k.hi, k.periodic);
    const auto got = binned_pairs(xyz, rad, 0.01, lo, k.hi, k.periodic);
    EXPECT_GT(ref.size(), 100u) << "case " << c;
    EXPECT_EQ(got, ref) << "case " << c;
  }

  // Reach tiny against the box: far more bins fit than atoms, so the bins are coarsened. Atoms
  // come in close couples (some within reach, some not), scattered through a periodic box.
  const double hi[3] = {1, 1, 1};
  const bool per[3] = {true, true, true};
  std::vector<double> xyz(3 * 400), rad(400);
  for (int i = 0; i < 400; i += 2) {
    for (int d = 0; d < 3; ++d) {
      xyz[3 * i + d] = u(rng);
      xyz[3 * (i + 1) + d] = xyz[3 * i + d] + 0.003 * u(rng);
    }
    rad[i] = 0.001 + 0.001 * u(rng);
    rad[i + 1] = 0.001 + 0.001 * u(rng);
  }
  const auto ref = brute_force_pairs(xyz, rad, 0.001, lo, hi, per);
  EXPECT_GT(ref.size(), 50u);
  EXPECT_LT(ref.size(), 200u);
  EXPECT_EQ(binned_pairs(xyz, rad, 0.001, lo, hi, per), ref);
  EXPECT_TRUE(binned_pairs({}, {}, 0.1, lo, hi, per).empty());
  EXPECT_THROW(binned_pairs({0, 0}, {1}, 0.1, lo, hi, per), std::invalid_argument);
}

TEST(BalanceKernels, CalibratedCostsAreNormalisedPositiveAndFinite)
{
  // The calibration times kernels, so which costs more depends on the machine and its load (a
  // loaded CI machine once measured a contact below a check); what it guarantees is the unit
  // (a pair check is 1) and costs that a partitioner can use: finite, at least the floor 0.05.
  const InteractionCosts c = fracdem::calibrate_costs(0.02);
  EXPECT_DOUBLE_EQ(c.pair_check, 1.0);
  for (double cost : {c.particle, c.sphere_contact, c.facet_check, c.facet_contact, c.wall_check,
                      c.wall_contact, c.bridge}) {
    EXPECT_TRUE(std::isfinite(cost));
    EXPECT_GE(cost, 0.05);
  }
}

TEST(BalanceKernels, RefinementBalancesWithLittleMigration)
{
  const int n = 40;
  const Graph g = grid_graph(n, n);
  // Four column strips, the first twice as wide as it should be: loads 0.4, 0.2, 0.2, 0.2.
  std::vector<int> part(n * n);
  for (int v = 0; v < n * n; ++v) {
    const int col = v % n;
    part[v] = col < 16 ? 0 : col < 24 ? 1 : col < 32 ? 2 : 3;
  }
  const std::vector<int> before = part;
  const int passes = refine_partition(g, part, 4, 1.02, 200);
  EXPECT_LE(passes, 200) << "reached balance";
  std::vector<double> load(4, 0);
  for (int p : part)
    load[p] += 1;
  EXPECT_LE(imbalance(load), 1.02 + 1e-9);
  // The excess of part 0 is 0.15 of all vertices; diffusion moves it one strip at a time, so
  // migration is a few times that, far below a partition from scratch.
  const std::vector<double> w(n * n, 1.0);
  const double migrated = migration_weight(before, part, w);
  EXPECT_LE(migrated, 0.5 * n * n);
  const auto scratch = relabel_max_overlap(partition_kway(g, 4, 1.02), before, w, 4);
  EXPECT_LT(migrated, migration_weight(before, scratch, w) + 1e-9);
  // Balanced input stays untouched.
  std::vector<int> even(n * n);
  for (int v = 0; v < n * n; ++v)
    even[v] = (v % n) / 10;
  const std::vector<int> even_before = even;
  EXPECT_EQ(refine_partition(g, even, 4, 1.02), 0);
  EXPECT_EQ(even, even_before);
}

TEST(BalanceKernels, CellGridMapsPointsAndFillsOwnersByDistance)
{
  const double lo[3] = {0, 0, 0}, hi[3] = {1.0, 0.5, 0.25};
  const bool per[3] = {true, false, false};
  const CellGrid g = make_cell_grid(lo, hi, 0.1, 3, per);
  EXPECT_EQ(g.n[0], 10);
  EXPECT_EQ(g.n[1], 5);
  EXPECT_EQ(g.n[2], 2);
  const double inside[3] = {0.55, 0.12, 0.2}, wrapped[3] = {-0.05, 0.12, 0.2},
               beyond[3] = {0.5, 9.0, -1};
  int64_t c[3];
  g.coords(g.cell_of(inside), c);
  EXPECT_EQ(c[0], 5);
  EXPECT_EQ(c[1], 1);
  EXPECT_EQ(c[2], 1);
  g.coords(g.cell_of(wrapped), c);
  EXPECT_EQ(c[0], 9); // periodic x wraps
  g.coords(g.cell_of(beyond), c);
  EXPECT_EQ(c[1], 4); // non-periodic clamps
  EXPECT_EQ(c[2], 0);

  // Two seeds at x = 1 and x = 6 (y = z = 0): every cell takes the seed nearer in grid steps
  // (face-neighbour distance), periodic in x. Check against that brute-force rule.
  const std::vector<int64_t> seeds = {g.id(1, 0, 0), g.id(6, 0, 0)};
  const auto owner = fill_cell_owners(g, seeds, {0, 1});
  for (int64_t cell = 0; cell < g.total(); ++cell) {
    g.coords(cell, c);
    auto dist = [&](int64_t sx) {
      const int64_t dx = std::abs(c[0] - sx);
      return std::min(dx, g.n[0] - dx) + c[1] + c[2];
    };
    const int64_t d0 = dist(1), d1 = dist(6);
    if (d0 < d1) EXPECT_EQ(owner[cell], 0) << cell;
    if (d1 < d0) EXPECT_EQ(owner[cell], 1) << cell;
    EXPECT_GE(owner[cell], 0);
  }
}

// The cell graph against a brute-force rule: between two occupied cells, one unit per offset in
// {-1,0,1}^dim that leads from one to the other (periodic wrap, nothing across a wall), plus the
// clamped weights of the contact triples naming both. Grids with a periodic dimension of 2 cells
// (two offsets reach the same neighbour), of 1 cell, and a 2D grid.
TEST(BalanceKernels, CellGraphMatchesBruteForceTouchingAndContactWeights)
{
  struct Case {
    int64_t n[3];
    bool periodic[3];
  };
  const Case cases[] = {{{5, 4, 3}, {true, true, false}},
                        {{2, 3, 4}, {true, false, true}},
                        {{1, 5, 3}, {true, true, false}},
                        {{6, 5, 1}, {true, false, false}}};
  std::mt19937 rng(20261123);
  for (const Case& cs : cases) {
    CellGrid grid;
    for (int d = 0; d < 3; ++d)
      grid.n[d] = cs.n[d], grid.periodic[d] = cs.periodic[d];
    const int64_t total = grid.total();
    std::vector<int64_t> cells, vertex_of_cell(total, -1), vwgt;
    for (int64_t c = 0; c < total; ++c)
      if (rng() % 10 < 6) {
        vertex_of_cell[c] = static_cast<int64_t>(cells.size());
        cells.push_back(c), vwgt.push_back(static_cast<int64_t>(rng() % 5)); // 0 is clamped
      }
    const int64_t n = static_cast<int64_t>(cells.size());
    std::vector<int64_t> triples;
    for (int k = 0; k < 60; ++k) // any two cells: unoccupied, equal, far apart, weight 0
      triples.insert(triples.end(),
                     {static_cast<int64_t>(rng() % total), static_cast<int64_t>(rng() % total),
                      static_cast<int64_t>(rng() % 4)});
    triples.insert(triples.end(), {-1, cells[0], 3}); // outside the grid: dropped

    std::vector<std::map<int64_t, int64_t>> expected(n);
    const bool flat = grid.n[2] == 1;
    for (int64_t v = 0; v < n; ++v) {
      int64_t a[3], b[3];
      grid.coords(cells[v], a);
      for (int64_t u = 0; u < n; ++u) {
        if (u == v) continue;
        grid.coords(cells[u], b);
        int64_t units = 0;
        for (int dz = flat ? 0 : -1; dz <= (flat ? 0 : 1); ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int off[3] = {dx, dy, dz};
              bool hit = true;
              for (int d = 0; d < 3; ++d) {
                int64_t m = a[d] + off[d];
                if (m < 0 || m >= grid.n[d]) {
                  if (!grid.periodic[d]) hit = false;
                  m = (m + grid.n[d]) % grid.n[d];
                }
                hit = hit && m == b[d];
              }
              units += hit;
            }
        if (units > 0) expected[v][u] += units;
      }
    }
    for (size_t e = 0; e < triples.size(); e += 3) {
      const int64_t ca = triples[e], cb = triples[e + 1];
      if (ca < 0 || cb < 0 || ca == cb || vertex_of_cell[ca] < 0 || vertex_of_cell[cb] < 0)
        continue;
      const int64_t w = std::max<int64_t>(1, triples[e + 2]);
      expected[vertex_of_cell[ca]][vertex_of_cell[cb]] += w;
      expected[vertex_of_cell[cb]][vertex_of_cell[ca]] += w;
    }

    const Graph g = build_cell_graph(grid, cells, vertex_of_cell, vwgt, triples);
    ASSERT_EQ(g.num_vertices(), n);
    for (int64_t v = 0; v < n; ++v) {
      EXPECT_EQ(g.vwgt[v], std::max<int64_t>(1, vwgt[v]));
      std::map<int64_t, int64_t> row;
      for (int64_t k = g.xadj[v]; k < g.xadj[v + 1]; ++k)
        EXPECT_TRUE(row.emplace(g.adjncy[k], g.adjwgt[k]).second) << "repeated neighbour";
      EXPECT_EQ(row, expected[v]) << "grid " << grid.n[0] << "x" << grid.n[1] << "x" << grid.n[2]
                                  << ", vertex " << v;
    }
  }
}

TEST(BalanceKernels, CellGraphRejectsInconsistentInput)
{
  CellGrid grid;
  grid.n[0] = 3;
  const std::vector<int64_t> cells = {0, 2}, vertex_of_cell = {0, -1, 1};
  EXPECT_THROW(build_cell_graph(grid, cells, {0, -1}, {1, 1}, {}), std::invalid_argument);
  EXPECT_THROW(build_cell_graph(grid, cells, vertex_of_cell, {1}, {}), std::invalid_argument);
  EXPECT_THROW(build_cell_graph(grid, cells, vertex_of_cell, {1, 1}, {0, 2}),
               std::invalid_argument);
  EXPECT_THROW(build_cell_graph(grid, {0, 1}, vertex_of_cell, {1, 1}, {}), std::invalid_argument);
  EXPECT_EQ(build_cell_graph(grid, cells, vertex_of_cell, {1, 1}, {0, 2, 5}).num_edges(), 1);
}
