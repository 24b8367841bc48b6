// Element partitions of a distributed body: the element dual graph, one part per rank (METIS),
// each part's own mesh, and the sum of nodal vectors over the parts that share a node.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "balance/graph_partition.h"
#include "fem/mesh.h"

namespace fracdem
{

// Elements that share a facet (a tet's triangle, a 2D element's edge) are neighbours; eroded
// elements take no part (no edges). Vertex weights: element_weight (one per element, >= 1), or
// each element's integration points when empty (a quad4 costs about four tri3).
balance::Graph element_dual_graph(const Mesh& mesh,
                                  const std::vector<int64_t>& element_weight = {});

// One part per rank: METIS k-way on the dual graph (fixed seed, so every rank computes the same
// parts from the same mesh). nparts == 1 gives all zeros. Eroded elements get part -1.
std::vector<int> partition_elements(const Mesh& mesh, int nparts,
                                    const std::vector<int64_t>& element_weight = {});

// The nodes a part shares with one neighbouring part, as local indices in ascending global node
// number: both sides list the same nodes in the same order, so a message needs no node ids.
struct PartNeighbour {
  int part = -1;
  std::vector<int> nodes;
};

// A part of a body: its elements (ascending global number) and the nodes they use (ascending
// global number), renumbered locally; node and element sets restricted to them.
struct MeshPart {
  int part = 0, nparts = 1;
  Mesh mesh;
  std::vector<int> global_node, global_elem; // local -> global
  std::vector<PartNeighbour> neighbours;     // ascending part number
  // Parts that use each local node, ascending (CSR: sharers[sharer_start[n] .. [n + 1])); a node
  // used by this part only has one sharer, this part.
  std::vector<int> sharer_start, sharers;

  int num_nodes() const { return static_cast<int>(global_node.size()); }
  bool shared(int n) const { return sharer_start[n + 1] - sharer_start[n] > 1; }
  // The lowest sharing part owns a node: it alone counts the node in sums over the body (mass,
  // momentum, kinetic energy), so that a shared node is counted once.
  bool owns(int n) const { return sharers[sharer_start[n]] == part; }
  int num_shared_nodes() const;
};

// The local index of each global number in [0, size) (-1: not among `global`, a part's local ->
// global list such as MeshPart::global_node or global_elem).
std::vector<int> local_of_global(const std::vector<int>& global, int size);

// Part `part` of `mesh` under the element partition elem_part (partition_elements).
MeshPart extract_part(const Mesh& mesh, const std::vector<int>& elem_part, int part);

// A part as doubles (its integers are exact in a double), appended to out: the message in which
// rank 0, which alone reads the mesh, sends a rank its part (parallel distributed set-up).
void pack_part(const MeshPart& part, std::vector<double>& out);
// The part packed at in[at..]; at moves past it. Throws std::runtime_error on a short message.
MeshPart unpack_part(const std::vector<double>& in, std::size_t& at);

// Sums per-node vectors (`width` doubles per node: 3 for forces, 1 for masses) over the parts
// that share each node, in ascending part order, so that every sharer holds the same bits and the
// sum does not depend on which rank computes it. Each neighbour gets `width` doubles per node the
// two parts share, nothing else.
class InterfaceSum
{
public:
  explicit InterfaceSum(const MeshPart& part);
  // This part's contributions at the nodes shared with neighbour k (index into
  // MeshPart::neighbours), in the neighbour's order: the message to that part.
  void pack(int k, const double* field, int width, std::vector<double>& message) const;
  // field: this part's own contributions; received[k]: neighbour k's message. Afterwards the
  // shared nodes hold the sum over all sharers in ascending part order.
  void combine(double* field, int width, const std::vector<std::vector<double>>& received) const;
  // Doubles sent to neighbour k per communication.
  std::size_t message_size(int k, int width) const { return width * nodes_[k].size(); }
  int num_neighbours() const { return static_cast<int>(nodes_.size()); }

private:
  // Per shared node: its local index and, in ascending part order, where each contribution is
  // found (neighbour index, position in that neighbour's message; -1 for this part's own).
  struct Slot {
    int neighbour, position;
  };
  std::vector<std::vector<int>> nodes_; // per neighbour: local nodes in message order
  std::vector<int> shared_node_, slot_start_;
  std::vector<Slot> slots_;
};

} // namespace fracdem
