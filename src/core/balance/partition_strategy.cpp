// The partitioner table and the repartition strategy: diffusion, from scratch, or Scotch's
// repartitioning, followed by the shape pass of the geometric partitioners.
#include "balance/partition_strategy.h"

#include <stdexcept>

#include "balance/compact_partition.h"
#include "balance/layered_partition.h"
#include "balance/scotch_partition.h"

namespace fracdem::balance
{

namespace
{

// The one table of partitioners, in the documentation's order.
const PartitionerInfo kPartitioners[] = {
    {"metis", Partitioner::Metis, false, false, false, "libmetis-dev", nullptr},
    {"scotch", Partitioner::Scotch, false, true, false, "libscotch-dev", nullptr},
    {"rcb", Partitioner::Rcb, true, false, false, "", nullptr},
    {"layers", Partitioner::Layers, true, false, false, "", nullptr},
    {"ptscotch", Partitioner::PtScotch, false, true, true, "libptscotch-dev", nullptr},
    {"zoltan-phg", Partitioner::ZoltanPhg, false, true, true, "libtrilinos-zoltan-dev",
     "HYPERGRAPH"},
    {"zoltan-graph", Partitioner::ZoltanGraph, false, true, true, "libtrilinos-zoltan-dev",
     "GRAPH"},
    {"zoltan-rcb", Partitioner::ZoltanRcb, true, true, true, "libtrilinos-zoltan-dev", "RCB"},
    {"zoltan-rib", Partitioner::ZoltanRib, true, true, true, "libtrilinos-zoltan-dev", "RIB"},
    {"zoltan-hsfc", Partitioner::ZoltanHsfc, true, true, true, "libtrilinos-zoltan-dev", "HSFC"},
};

} // namespace

const PartitionerInfo& find_partitioner(const std::string& name)
{
  std::string names;
  for (const PartitionerInfo& p : kPartitioners) {
    if (name == p.name) return p;
    names += std::string(names.empty() ? "" : " or ") + p.name; // each a choice of its own
  }
  throw std::invalid_argument("keyword 'partitioner': expected " + names + ", got '" + name + "'");
}

const PartitionerInfo& partitioner_info(Partitioner p)
{
  for (const PartitionerInfo& info : kPartitioners)
    if (info.id == p) return info;
  throw std::invalid_argument("partitioner_info: not in the partitioner table");
}

std::vector<int> PartitionStrategy::from_scratch(const Graph& g, int nparts,
                                                 const PartitionGeometry& geometry,
                                                 std::string& layout) const
{
  if (partitioner_.id == Partitioner::Layers && geometry.cells && geometry.grid) {
    LayerLayout chosen;
    std::vector<int> part = partition_layers(g, *geometry.grid, *geometry.cells, nparts,
                                             kPartitionTolerance, &chosen, geometry.gravity_axis);
    layout = chosen.describe();
    return part;
  }
  if (partitioner_.id == Partitioner::Rcb && geometry.centres)
    return partition_compact(g, *geometry.centres, nparts, kPartitionTolerance);
  return partition_kway(g, nparts, kPartitionTolerance);
}

PartitionResult PartitionStrategy::partition(const Graph& g, const std::vector<int>& old_owner,
                                             int nparts, const PartitionGeometry& geometry) const
{
  if (partitioner_.distributed)
    throw std::invalid_argument(std::string("partitioner ") + partitioner_.name +
                                " runs on all ranks (partition_distributed), not on one graph");
  const std::vector<double> load(g.vwgt.begin(), g.vwgt.end());
  const double current = imbalance(part_loads(load, old_owner, nparts));
  PartitionResult r;
  bool refined = false;
  if (partitioner_.repartitions) {
    // One call does both: a balanced partition that weighs edge cut against migration.
    r.part = repartition_scotch(g, old_owner, nparts, kScotchMigrationCost, kPartitionTolerance);
    refined = true;
  } else if (strategy_ == Strategy::Refine ||
             (strategy_ == Strategy::Auto && current < kRefineBelow && !partitioner_.geometric)) {
    r.part = old_owner;
    refined =
        refine_partition(g, r.part, nparts, kPartitionTolerance, kRefinePasses) <= kRefinePasses;
  }
  if (!refined && strategy_ != Strategy::Refine) {
    // From scratch, then relabelled so that most of the load stays where it is.
    const std::vector<int> fresh = from_scratch(g, nparts, geometry, r.layout);
    r.part = relabel_max_overlap(fresh, old_owner, load, nparts);
  } else if (partitioner_.geometric) {
    // Diffusion leaves steps in the boundaries it moved: smooth them without new partners.
    smooth_partition(g, r.part, nparts, kPartitionTolerance);
  }
  r.predicted_imbalance = imbalance(part_loads(load, r.part, nparts));
  r.edge_cut = static_cast<double>(edge_cut(g, r.part));
  return r;
}

} // namespace fracdem::balance
