// Particle graph (CSR), imbalance metrics, METIS partitioning and migration-minimal relabelling.
#ifndef FRACDEM_BALANCE_GRAPH_PARTITION_H
#define FRACDEM_BALANCE_GRAPH_PARTITION_H

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace fracdem::balance
{

// Undirected weighted graph in CSR form (each edge stored in both directions), ready for METIS.
struct Graph {
  std::vector<int64_t> xadj;   // size n+1
  std::vector<int64_t> adjncy; // neighbours
  std::vector<int64_t> vwgt;   // vertex weights (>= 1)
  std::vector<int64_t> adjwgt; // edge weights, parallel to adjncy (>= 1)
  int64_t num_vertices() const { return xadj.empty() ? 0 : static_cast<int64_t>(xadj.size()) - 1; }
  int64_t num_edges() const { return static_cast<int64_t>(adjncy.size()) / 2; }
};

// Fills a Graph's CSR rows in order, one row at a time: a neighbour added twice to the same row
// gets the sum of its weights (O(1) per entry: a mark per vertex says where it sits in the row).
class GraphRowWriter
{
public:
  GraphRowWriter(Graph& g, int64_t n, std::size_t entries_hint);
  void add(int64_t v, int64_t u, int64_t w); // entry u of row v; v is the row being written
  void end_row(int64_t v) { g_.xadj[v + 1] = static_cast<int64_t>(g_.adjncy.size()); }

private:
  Graph& g_;
  std::vector<int64_t> slot_row_, slot_;
};

struct WeightedPair {
  int64_t i, j;
  int64_t w;
};

// Both directions of every pair (i, j, w), i != j, by source vertex: row v is
// entries[start[v] .. start[v + 1]) of (neighbour, max(1, w)), in ascending neighbour order
// (duplicates kept), whatever the order of `pairs`. Ends must lie in [0, n).
struct RowEntries {
  std::vector<int64_t> start;
  std::vector<std::pair<int64_t, int64_t>> entries;
};
RowEntries sorted_rows(int64_t n, const std::vector<WeightedPair>& pairs);

// Neighbours in each row: in order of first appearance in the pairs, or ascending (the graph,
// and a partition of it, then does not depend on the order of the pairs).
enum class RowOrder { FirstSeen, Ascending };

// Merges duplicate pairs (i,j)/(j,i) by summing weights, drops self loops, symmetrises; weights
// are clamped to >= 1. Throws std::invalid_argument on out-of-range ids or a weight vector of the
// wrong size.
Graph build_graph(int64_t n, const std::vector<int64_t>& vertex_weight,
                  const std::vector<WeightedPair>& pairs, RowOrder order = RowOrder::FirstSeen);

// max/avg of per-part work; 1 when the total is zero. Throws std::invalid_argument on empty input.
double imbalance(const std::vector<double>& work_per_part);

// Sum of vertex loads per part.
std::vector<double> part_loads(const std::vector<double>& vertex_load, const std::vector<int>& part,
                               int nparts);

// Sum of the weights of edges whose ends lie in different parts. Throws std::invalid_argument
// unless part has one entry per vertex.
int64_t edge_cut(const Graph& g, const std::vector<int>& part);

// METIS k-way (recursive bisection if k-way fails) with a fixed seed: deterministic. nparts == 1
// gives all zeros without calling METIS. ubfactor 1.02 allows 2 % imbalance of vertex weights.
// Weights whose sum passes ~2^30 are divided by a common factor (each kept >= 1). Throws
// std::invalid_argument for nparts < 1 or inconsistent arrays, std::runtime_error with METIS's
// status if METIS fails, std::overflow_error if the graph does not fit idx_t.
std::vector<int> partition_kway(const Graph& g, int nparts, double ubfactor = 1.02);

// Diffusive repartitioning from the current assignment: moves boundary vertices from parts above
// ubfactor * average load to lighter adjacent parts, best edge-cut gain first, pass after pass,
// until balanced or no move helps. Far less migration than a partition from scratch when the
// imbalance is moderate; parts keep their shape. Returns the number of passes used (> max_passes
// means balance was not reached; the partition is still improved).
int refine_partition(const Graph& g, std::vector<int>& part, int nparts, double ubfactor = 1.02,
                     int max_passes = 64);

// Permutes the labels of new_part so that the migration weight (vertices whose label differs
// from old_owner) is minimal: an exact assignment problem, solved by the Hungarian algorithm.
// old_owner values outside [0, nparts) mean "no current owner".
std::vector<int> relabel_max_overlap(const std::vector<int>& new_part,
                                     const std::vector<int>& old_owner,
                                     const std::vector<double>& vertex_migration_weight,
                                     int nparts);

// The labels of relabel_max_overlap from the overlap table alone: overlap[a * nparts + b] is the
// weight of the vertices of new part a that live on rank b now; label[a] is the rank new part a
// goes to. Lets ranks that hold only their own vertices agree on the labels.
std::vector<int> max_overlap_labels(std::vector<double> overlap, int nparts);

// Total weight of the vertices whose assignment differs.
double migration_weight(const std::vector<int>& from, const std::vector<int>& to,
                        const std::vector<double>& vertex_migration_weight);

// All pairs i<j of spheres whose centres are closer than r_i + r_j + skin, minimum image in the
// periodic dimensions: O(n^2) reference for tests. Throws std::invalid_argument unless
// xyz.size() == 3 * radius.size().
std::vector<std::pair<int64_t, int64_t>>
brute_force_pairs(const std::vector<double>& xyz, const std::vector<double>& radius, double skin,
                  const double box_lo[3], const double box_hi[3], const bool periodic[3]);

// The same set from cell bins at least 2 max(r) + skin wide (27-cell stencil, periodic wrap; atoms
// a little outside the box are wrapped or clamped), sorted: O(n) for a bounded density.
std::vector<std::pair<int64_t, int64_t>>
binned_pairs(const std::vector<double>& xyz, const std::vector<double>& radius, double skin,
             const double box_lo[3], const double box_hi[3], const bool periodic[3]);

} // namespace fracdem::balance

#endif
