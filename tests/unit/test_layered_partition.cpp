// Unit tests of the layered partitioner (`partitioner layers`): brick-wall rows of weighted parts,
// partners on the filled cell grid, and the layout rule on periodic and non-periodic grids.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "balance/cell_grid.h"
#include "balance/compact_partition.h"
#include "balance/graph_partition.h"
#include "balance/layered_partition.h"

using namespace fracdem::balance;

namespace
{

// Every cell of an nx x ny x nz grid (x, y periodic where asked) as a vertex of the fix's cell
// graph, weighted by weight(cx, cy, cz).
struct Scene {
  CellGrid grid;
  Graph g;
  std::vector<int64_t> cells;
};

template <typename W> Scene scene(int nx, int ny, int nz, bool periodic_xy, W weight)
{
  Scene s;
  const double lo[3] = {0, 0, 0}, hi[3] = {double(nx), double(ny), double(nz)};
  const bool periodic[3] = {periodic_xy, periodic_xy, false};
  s.grid = make_cell_grid(lo, hi, 1.0, 3, periodic);
  const int64_t n = s.grid.total();
  std::vector<int64_t> vertex_of_cell(n), vwgt(n);
  s.cells.resize(n);
  std::iota(s.cells.begin(), s.cells.end(), int64_t(0));
  std::iota(vertex_of_cell.begin(), vertex_of_cell.end(), int64_t(0));
  for (int64_t v = 0; v < n; ++v) {
    int64_t c[3];
    s.grid.coords(v, c);
    vwgt[v] = weight(c[0], c[1], c[2]);
  }
  s.g = build_cell_graph(s.grid, s.cells, vertex_of_cell, vwgt, {});
  return s;
}

double load_imbalance(const Graph& g, const std::vector<int>& part, int nparts)
{
  return imbalance(part_loads(std::vector<double>(g.vwgt.begin(), g.vwgt.end()), part, nparts));
}

int max_of(const std::vector<int>& v)
{
  return *std::max_element(v.begin(), v.end());
}

int64_t uniform(int64_t, int64_t, int64_t)
{
  return 10;
}

// The large settling bed in cells of two ghost cutoffs (31 x 31 x 16, x and y periodic): a dense
// bed in the 7 lowest layers (weight 100) under a dilute cloud (weight 6).
int64_t bed(int64_t, int64_t, int64_t cz)
{
  return cz < 7 ? 100 : 6;
}

} // namespace

TEST(LayeredPartition, BrickWallRowsTouchTwoPartsOfTheOtherRow)
{
  // 2 rows across y, 4 parts along x, periodic: row 1 starts half a part (2 cells) further on.
  const Scene s = scene(16, 8, 2, true, uniform);
  LayerLayout l;
  l.rows_axis = 1, l.rows = 2, l.parts_axis = 0, l.per_row = 4;
  const std::vector<int> part = layer_partition(s.g, s.grid, s.cells, l);
  EXPECT_DOUBLE_EQ(load_imbalance(s.g, part, 8), 1.0);
  int64_t c[3];
  s.grid.coords(s.cells[0], c);
  for (size_t v = 0; v < part.size(); ++v) {
    s.grid.coords(s.cells[v], c);
    const int row = c[1] < 4 ? 0 : 1;
    const int64_t x = row == 0 ? c[0] : (c[0] + 16 - 2) % 16;
    ASSERT_EQ(part[v], row * 4 + static_cast<int>(x / 4)) << "cell " << v;
  }
  // Two in its row, two in the other (across y = 4 and across the periodic y = 0): 4 each; the
  // aligned 2 x 4 columns give 5 (the diagonal neighbours).
  EXPECT_EQ(grid_partners(s.grid, s.cells, part, 8), std::vector<int>(8, 4));
  const bool aperiodic[3] = {false, false, false};
  CellGrid open = s.grid;
  std::copy(aperiodic, aperiodic + 3, open.periodic);
  const std::vector<int> aligned = layer_partition(s.g, open, s.cells, l);
  EXPECT_DOUBLE_EQ(load_imbalance(s.g, aligned, 8), 1.0);
  s.grid.coords(s.cells[0], c);
  for (size_t v = 0; v < aligned.size(); ++v) {
    s.grid.coords(s.cells[v], c);
    ASSERT_EQ(aligned[v], (c[1] < 4 ? 0 : 4) + static_cast<int>(c[0] / 4)) << "cell " << v;
  }
}

TEST(LayeredPartition, PeriodicGridsGetTwoOrFourPartnersWithinTolerance)
{
  // The brief's goal layouts: 4 strips (2 partners), brick walls of 2 x 4 and 2 x 8 (4 each),
  // against box layouts of 3, 5 and 8 corner-and-face neighbours.
  const Scene grids[] = {scene(32, 32, 6, true, uniform), scene(31, 31, 16, true, bed)};
  for (const Scene& s : grids)
    for (int nparts : {4, 8, 16}) {
      LayerLayout chosen;
      const std::vector<int> part = partition_layers(s.g, s.grid, s.cells, nparts, 1.02, &chosen);
      const std::vector<int> partners = grid_partners(s.grid, s.cells, part, nparts);
      EXPECT_LE(max_of(partners), nparts == 4 ? 2 : 4) << nparts << ": " << chosen.describe();
      EXPECT_EQ(max_of(partners), chosen.partners_max) << nparts;
      EXPECT_LE(load_imbalance(s.g, part, nparts), 1.02 + 1e-9) << nparts;
      EXPECT_FALSE(chosen.rcb) << nparts;
      EXPECT_NE(chosen.parts_axis, 2) << nparts << ": the bed is not cut across its layers";
      // Never more partners than the rcb partition it replaces.
      std::vector<double> xyz(3 * s.cells.size());
      for (size_t v = 0; v < s.cells.size(); ++v) {
        int64_t c[3];
        s.grid.coords(s.cells[v], c);
        for (int a = 0; a < 3; ++a)
          xyz[3 * v + a] = c[a] + 0.5;
      }
      const std::vector<int> rcb = partition_compact(s.g, xyz, nparts);
      EXPECT_LE(max_of(partners), max_of(grid_partners(s.grid, s.cells, rcb, nparts))) << nparts;
    }
}

TEST(LayeredPartition, NonPeriodicGridBalancesAndIsDeterministic)
{
  // Weight rising along x (a ramp) on a closed box: every row's cuts follow its own weights.
  const Scene s = scene(24, 20, 5, false,
                        [](int64_t cx, int64_t cy, int64_t) { return 5 + 3 * cx + (cy % 3); });
  for (int nparts : {4, 6, 8, 16}) {
    LayerLayout chosen;
    const std::vector<int> part = partition_layers(s.g, s.grid, s.cells, nparts, 1.02, &chosen);
    EXPECT_LE(load_imbalance(s.g, part, nparts), 1.02 + 1e-9) << nparts << chosen.describe();
    EXPECT_EQ(part, partition_layers(s.g, s.grid, s.cells, nparts, 1.02)) << nparts;
    // Every part holds cells (no empty rank).
    std::vector<int> count(nparts, 0);
    for (int p : part)
      count[p] += 1;
    EXPECT_GT(*std::min_element(count.begin(), count.end()), 0) << nparts;
  }
}

TEST(LayeredPartition, CoarseCellsFallBackToRcbAndInputChecks)
{
  // 3 x 3 x 3 cells for 16 parts: no layout has a cell per part along its axes.
  const Scene s = scene(3, 3, 3, true, uniform);
  LayerLayout chosen;
  const std::vector<int> part = partition_layers(s.g, s.grid, s.cells, 16, 1.02, &chosen);
  EXPECT_TRUE(chosen.rcb) << chosen.describe();
  EXPECT_EQ(part.size(), s.cells.size());
  EXPECT_EQ(partition_layers(s.g, s.grid, s.cells, 1), std::vector<int>(27, 0));
  EXPECT_THROW(partition_layers(s.g, s.grid, s.cells, 0), std::invalid_argument);
  EXPECT_THROW(partition_layers(s.g, s.grid, {0, 1}, 2), std::invalid_argument);
  LayerLayout bad;
  bad.rows = 2, bad.rows_axis = 0, bad.parts_axis = 0, bad.per_row = 2;
  EXPECT_THROW(layer_partition(s.g, s.grid, s.cells, bad), std::invalid_argument);
  EXPECT_THROW(grid_partners(s.grid, s.cells, {0}, 2), std::invalid_argument);
}

TEST(LayeredPartition, ASettlingBedIsNotCutAcrossItsLayers)
{
  // The small settling bed in cells (7 x 7 x 16): its weighted extent along z is as large as
  // across, but the work is layered along z (dense floor, dilute cloud): z-strips would have
  // fewer partners (1.5 at 4 parts) and are not offered.
  const Scene s = scene(7, 7, 16, true, bed);
  for (int nparts : {2, 4, 8, 16}) {
    LayerLayout chosen;
    const std::vector<int> part = partition_layers(s.g, s.grid, s.cells, nparts, 1.02, &chosen);
    EXPECT_LE(load_imbalance(s.g, part, nparts), 1.02 + 1e-9) << nparts;
    if (!chosen.rcb) {
      EXPECT_NE(chosen.parts_axis, 2) << nparts << ": " << chosen.describe();
      EXPECT_TRUE(chosen.rows == 1 || chosen.rows_axis != 2) << nparts << ": " << chosen.describe();
    }
  }
}

TEST(LayeredPartition, NoLayoutCutsAcrossGravity)
{
  // A uniform 24^3 grid, periodic in x and y: z-layers have the fewest partners (1.5 on average,
  // the closed ends touch one) and are chosen without gravity_axis; with gravity along z (the
  // host's fix gravity) the layout is strips along x or y (2 partners each).
  const Scene s = scene(24, 24, 24, true, uniform);
  LayerLayout free_layout, settled;
  const std::vector<int> free_part = partition_layers(s.g, s.grid, s.cells, 4, 1.02, &free_layout);
  EXPECT_FALSE(free_layout.rcb);
  EXPECT_EQ(free_layout.parts_axis, 2) << free_layout.describe();
  EXPECT_DOUBLE_EQ(free_layout.partners_avg, 1.5);
  const std::vector<int> part =
      partition_layers(s.g, s.grid, s.cells, 4, 1.02, &settled, /*gravity_axis=*/2);
  EXPECT_LE(load_imbalance(s.g, part, 4), 1.02 + 1e-9);
  ASSERT_FALSE(settled.rcb) << settled.describe();
  EXPECT_NE(settled.parts_axis, 2) << settled.describe();
  EXPECT_TRUE(settled.rows == 1 || settled.rows_axis != 2) << settled.describe();
  EXPECT_EQ(max_of(grid_partners(s.grid, s.cells, part, 4)), 2);
}
