// How a repartition finds the new owners: the partitioners by name (one table), the choice
// between diffusion from the current owners and a partition from scratch, and the prediction.
#ifndef FRACDEM_BALANCE_PARTITION_STRATEGY_H
#define FRACDEM_BALANCE_PARTITION_STRATEGY_H

#include <cstdint>
#include <string>
#include <vector>

#include "balance/cell_grid.h"
#include "balance/graph_partition.h"

namespace fracdem::balance
{

enum class Partitioner {
  Metis,
  Scotch,
  Rcb,
  Layers,
  PtScotch,
  ZoltanPhg,
  ZoltanGraph,
  ZoltanRcb,
  ZoltanRib,
  ZoltanHsfc
};
// `repartition`: diffusion from the current owners, a partition from scratch, or by imbalance.
enum class Strategy { Auto, Refine, Scratch };

// One entry of the partitioner table.
struct PartitionerInfo {
  const char* name;
  Partitioner id;
  // Cuts by coordinates. Gathered (rcb, layers): cuts the cell grid, needs cells; `auto` cuts
  // from scratch every time (diffusion from the current owners erodes the boxes) and diffusion
  // is followed by a shape pass. Distributed (zoltan-rcb|rib|hsfc): cuts the particles'
  // positions, weighted by their costs; the graph's edges only measure the cut.
  bool geometric;
  // One call trades edge cut against migration: `repartition` does not apply.
  bool repartitions;
  // Runs on all ranks with the graph left where it is built (particle vertices only): no rank
  // gathers the graph or the partition. The Debian package that provides it.
  bool distributed;
  const char* package;
  // Zoltan's LB_METHOD for the Zoltan partitioners (nullptr for the others).
  const char* zoltan_method;
};

// The partitioner named `name`; else throws std::invalid_argument "keyword 'partitioner':
// expected metis or scotch or rcb or layers or ptscotch or zoltan-phg or zoltan-graph or
// zoltan-rcb or zoltan-rib or zoltan-hsfc, got 'NAME'".
const PartitionerInfo& find_partitioner(const std::string& name);
const PartitionerInfo& partitioner_info(Partitioner p);

// Load tolerance of every partitioner: 2 % above the average vertex weight per part.
constexpr double kPartitionTolerance = 1.02;
// `repartition auto` diffuses from the current owners below this imbalance of the graph weights,
// and partitions from scratch above it (diffusion from a far-off start degrades part shapes).
constexpr double kRefineBelow = 1.5;
constexpr int kRefinePasses = 64;
// partitioner scotch: cost of moving one unit of vertex weight against cutting one unit of edge
// weight. A particle of average cost weighs kWeightResolution and a contact edge a few units, so
// moving a particle costs about as much as cutting the edges of a few neighbours.
constexpr double kScotchMigrationCost = 0.1;
// partitioner ptscotch: the load tolerance given to PT-Scotch's strategy. Its parallel refinement
// is coarser than METIS's, so it is asked for the common tolerance and its result is checked
// against it like the others' (predicted_imbalance).
constexpr double kDistributedTolerance = kPartitionTolerance;

// What the partitioner may use besides the graph: for geometric partitioners the vertices' cells
// (cells[v] of grid) and their centres (3 per vertex, partitioner rcb), and the axis of the host's
// gravity that a layout never cuts (-1: none).
struct PartitionGeometry {
  const CellGrid* grid = nullptr;
  const std::vector<std::int64_t>* cells = nullptr;
  const std::vector<double>* centres = nullptr;
  int gravity_axis = -1;
};

// The new owners and what they predict.
struct PartitionResult {
  std::vector<int> part;
  double predicted_imbalance = 1.0; // max/avg of the vertex weights per part
  double edge_cut = 0;
  std::string layout; // partitioner layers: the layout chosen (LayerLayout::describe)
};

class PartitionStrategy
{
public:
  PartitionStrategy(Partitioner partitioner, Strategy strategy)
      : partitioner_(partitioner_info(partitioner)), strategy_(strategy)
  {
  }
  // Partitions g into nparts from the current owners old_owner (one per vertex in [0, nparts)):
  // partitioner scotch repartitions in one call; otherwise `refine` (or `auto` below
  // kRefineBelow, not for geometric partitioners) diffuses from old_owner, and where that does
  // not reach the tolerance (`auto`) or `scratch` asks, the partitioner cuts from scratch and its
  // parts are relabelled so that most of the weight stays with its owner. Throws what the
  // partitioners throw.
  PartitionResult partition(const Graph& g, const std::vector<int>& old_owner, int nparts,
                            const PartitionGeometry& geometry = {}) const;

private:
  std::vector<int> from_scratch(const Graph& g, int nparts, const PartitionGeometry& geometry,
                                std::string& layout) const;

  const PartitionerInfo& partitioner_;
  Strategy strategy_;
};

} // namespace fracdem::balance

#endif
