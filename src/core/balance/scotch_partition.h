// Scotch graph repartitioning: a new balanced partition that trades edge cut against migration.
#ifndef FRACDEM_BALANCE_SCOTCH_PARTITION_H
#define FRACDEM_BALANCE_SCOTCH_PARTITION_H

#include <vector>

#include "balance/graph_partition.h"

namespace fracdem::balance
{

// Scotch's SCOTCH_graphRepart: partitions g into nparts parts within ubfactor (1.02 allows 2 %
// imbalance of vertex weights) while minimising edge cut + migration_cost * (weight of the
// vertices whose part differs from old_part). The migration cost of a vertex is its weight (a
// heavy particle or cell costs more to move); migration_cost prices moving one unit of weight
// against cutting one unit of edge weight, and Scotch rounds it to a multiple of 0.01. With a
// cost above zero, part numbers keep their meaning (part p stays where old part p was), so no
// relabelling is needed; at zero the old partition is ignored. Deterministic (fixed seed, in a
// deterministic single-threaded Scotch context). nparts == 1 gives all zeros without calling
// Scotch. Weights are divided by a common factor where their sums would pass the range of
// SCOTCH_Num (32 bit in Debian), each kept >= 1. Throws std::invalid_argument for nparts < 1,
// inconsistent CSR arrays, neighbours out of range, a negative or non-finite migration_cost, or
// an old_part without one entry per vertex in [0, nparts) (every vertex needs a current owner
// here); std::overflow_error if the graph does not fit SCOTCH_Num; std::runtime_error naming the
// Scotch routine and its return code if Scotch fails (Scotch prints its reason to stderr).
// (Scotch is a required dependency: CMake refuses to configure without libscotch-dev.)
std::vector<int> repartition_scotch(const Graph& g, const std::vector<int>& old_part, int nparts,
                                    double migration_cost, double ubfactor = 1.02);

} // namespace fracdem::balance

#endif
