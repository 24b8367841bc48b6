// Compact partitions: recursive coordinate bisection as a geometric seed, graph refinement to the
// load tolerance, and a shape pass that never adds a pair of touching parts.
#ifndef FRACDEM_BALANCE_COMPACT_PARTITION_H
#define FRACDEM_BALANCE_COMPACT_PARTITION_H

#include <cstdint>
#include <vector>

#include "balance/graph_partition.h"

namespace fracdem::balance
{

// Recursive coordinate bisection of weighted points (xyz: 3 coordinates per point): a set of k
// parts is cut across the longest side of its points' bounding box into floor(k/2) and
// ceil(k/2) parts at the weighted split closest to that ratio; points on one coordinate plane are
// ordered by the other two coordinates, so that a cut may step inside a plane of cells (a
// "staircase": a plane with one step) instead of taking the whole plane to one side. Parts are
// boxes (nearly), so each touches few others, as LAMMPS `fix balance rcb` makes them; the load
// error of a part is at most a few point weights. Weights <= 0 count as 0 (a set of zero weight
// is split by point count). Deterministic (ties by index). Throws std::invalid_argument for
// nparts < 1 or xyz.size() != 3 * weight.size().
std::vector<int> partition_rcb(const std::vector<double>& xyz, const std::vector<int64_t>& weight,
                               int nparts);

// Shape pass: a vertex moves to the adjacent part that holds more of its edge weight than its own
// part does (the edge cut falls with every move, so the pass ends), when the receiving part stays
// within ubfactor x the average load and the move makes no new pair of adjacent parts (every part
// adjacent to the vertex is adjacent to the receiving part already). Smooths the steps a seed or a
// diffusion leaves in part boundaries without adding a partner to any part. Returns the number of
// vertices moved. Throws std::invalid_argument unless part has one entry per vertex in
// [0, nparts).
int64_t smooth_partition(const Graph& g, std::vector<int>& part, int nparts, double ubfactor = 1.02,
                         int max_passes = 16);

// The compact partition of `partitioner rcb`: partition_rcb of the vertex coordinates with the
// graph's vertex weights, refine_partition to ubfactor where the seed's granularity leaves a part
// above it, then smooth_partition. Same arguments and exceptions as the three. (On grids too
// coarse for boxes, a few cells per part and dimension, METIS k-way's parts can touch fewer
// others; choosing the one with fewer pairs of adjacent cells was tried and measured worse on the
// settling bed at 16 ranks, 9.1 against 8.5 forward-comm partners: the ghost partners follow the
// owners of empty cells too, which boxes keep compact.)
std::vector<int> partition_compact(const Graph& g, const std::vector<double>& xyz, int nparts,
                                   double ubfactor = 1.02);

// Number of other parts each part shares an edge with (the partners a rank of that part talks to
// when edges join vertices within the ghost cutoff). Throws std::invalid_argument unless part has
// one entry per vertex in [0, nparts).
std::vector<int> part_partners(const Graph& g, const std::vector<int>& part, int nparts);

} // namespace fracdem::balance

#endif
