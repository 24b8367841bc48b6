// Layered (multi-jagged, brick-wall) partitions of a cell graph: rows of weighted parts whose cuts
// are offset from row to row, chosen among factorisations by predicted partners and ghost volume.
#ifndef FRACDEM_BALANCE_LAYERED_PARTITION_H
#define FRACDEM_BALANCE_LAYERED_PARTITION_H

#include <cstdint>
#include <string>
#include <vector>

#include "balance/cell_grid.h"
#include "balance/graph_partition.h"

namespace fracdem::balance
{

// One layout: `rows` rows cut across rows_axis at the weighted quantiles of the cells, each row
// cut along parts_axis into per_row parts at the quantiles of its own cells (rows == 1: strips).
// In a periodic parts_axis, row r starts its cuts r / rows of a part further along (a brick wall:
// each part then touches two parts of each neighbouring row instead of three), the last part of
// the row wrapping round; in a non-periodic one every row starts at the edge. rcb = true stands
// for partition_compact (the fallback). The predictions are those of the partition made.
struct LayerLayout {
  int rows_axis = 0, rows = 1, parts_axis = 0, per_row = 1;
  bool rcb = false;
  double partners_avg = 0; // predicted partners per part on the filled cell grid
  int partners_max = 0;
  double ghost = 0;     // predicted ghost volume: weight of boundary cells / total weight
  double imbalance = 0; // predicted max/avg of the vertex weights
  std::string describe() const;
};

// The partition of a layout (no refinement): vertex v of g is cell cells[v] of grid, weighted by
// g.vwgt[v] (<= 0 counts as 0; a set of zero weight is cut by cell count). Within a row (and at a
// row boundary) cells of one plane are ordered by the other axes, so a cut may step inside a
// plane ("staircase") and each part's load is within a few cell weights of the target.
// Deterministic. Throws std::invalid_argument for a layout that does not fit nparts =
// rows * per_row, an axis outside [0, 3), or cells.size() != number of vertices.
std::vector<int> layer_partition(const Graph& g, const CellGrid& grid,
                                 const std::vector<int64_t>& cells, const LayerLayout& layout);

// Partners of every part on the filled grid: fill_cell_owners gives every cell of the grid an
// owner, as fix balance/graph does, and two parts are partners where two of their cells touch (26
// neighbours, 8 in 2D, periodic wrap): the ranks a rank exchanges ghosts with when cells are at
// least one ghost cutoff wide. (part_partners on the graph of occupied cells misses the partners
// that empty cells bring, see partition_compact.)
std::vector<int> grid_partners(const CellGrid& grid, const std::vector<int64_t>& cells,
                               const std::vector<int>& part, int nparts);

// `partitioner layers`. Candidates: strips along every cut axis, and rows x per_row for every
// ordered pair of cut axes and every factorisation nparts = rows x per_row with 1 < rows < nparts
// (at least one cell per row and per part along each axis); cut axes are those with at least two
// cells whose weighted standard deviation of the cell centres (length) is at least half the
// largest and whose work is not layered along them: the coefficient of variation of the planes'
// weights (between the first and last occupied plane) at most kLayeredVariation or twice the
// smallest of the axes' (so a bed layered along gravity is not cut across its layers), and
// never gravity_axis (>= 0: the axis of the host's gravity, along which particles settle and
// flow, carrying work across any cut of that axis; measured on the large hopper at 16 ranks:
// 8 rows across z, B 1.10 after 300 steps); and partition_compact.
// A layout above ubfactor is brought back by refine_partition. Rule: among the candidates within
// ubfactor (all, if none is), those whose predicted ghost volume is at most kGhostWindow x the
// smallest; of these the fewest partners (average, then maximum), then the smaller ghost volume,
// then the first enumerated (rcb first). The chosen one is then smoothed (smooth_partition),
// kept unsmoothed if smoothing added a partner on the filled grid. `chosen`, if given, receives
// the layout and its predictions. Deterministic. Same exceptions as layer_partition.
std::vector<int> partition_layers(const Graph& g, const CellGrid& grid,
                                  const std::vector<int64_t>& cells, int nparts,
                                  double ubfactor = 1.02, LayerLayout* chosen = nullptr,
                                  int gravity_axis = -1);

// Ghost window of the rule above: a layout may cost this much more predicted ghost volume than the
// most compact candidate to save partners. On the large settling bed (31 x 31 x 16 cells) the
// brick walls cost 1.06 x (2 x 4 at 8 parts) and 1.36 x (2 x 8 at 16) the rcb candidate's; strips
// 1.54 x (8) and 2.07 x (16), excluded.
constexpr double kGhostWindow = 1.45;

// Plane-to-plane variation of the work below which an axis never counts as layered (across
// gravity a settling bed's planes differ by a few % to ~20 %: lattice aliasing of the cells).
constexpr double kLayeredVariation = 0.3;

} // namespace fracdem::balance

#endif
