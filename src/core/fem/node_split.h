// Nodal fracture topology: element stars, split plans along a failure plane, node splitting.
#pragma once

#include <array>
#include <vector>

#include "fem/mesh.h"

namespace fracdem
{

// The facets of element e that contain `node`, each by its other nodes in connectivity order:
// 3D (tet4) the three triangles' other two nodes; 2D the far node of the two edges at the node
// (second -1).
void facets_through(const Mesh& mesh, int e, int node, std::vector<std::array<int, 2>>& others);

// Active elements around each node (the node's element star), sorted ascending. Built once, then
// kept current by split_node, so that a fracture step never pays for a full rebuild.
struct NodeStars {
  std::vector<int> offset, elems; // CSR: elems[offset[n] .. offset[n+1])

  void build(const Mesh& mesh);
  int num_nodes() const { return offset.empty() ? 0 : static_cast<int>(offset.size()) - 1; }
  const int* begin(int n) const { return elems.data() + offset[n]; }
  const int* end(int n) const { return elems.data() + offset[n + 1]; }

  // Incremental update after split_node: the sorted elements `moved` leave `parent`'s star and
  // form the star of the new node `copy`, which must be num_nodes() (nodes are only appended).
  void apply_split(int parent, int copy, const std::vector<int>& moved);
};

struct SplitPlan {
  int node = -1;                   // node to split
  std::vector<int> side_a, side_b; // star elements keeping the node / getting the copy (sorted)

  bool splittable() const { return !side_a.empty() && !side_b.empty(); }
};

// Partition node `node`'s element star by the side of the plane (through the node's current
// position x[3*node..], normal n) on which each element's current centroid lies (centroid on the
// plane -> side a), then make both sides face-connected within the star (2D: sharing an edge that
// contains the node; 3D: sharing a triangle that contains the node). An element outside the
// largest component of its side moves to the other side when it is face-connected to that side's
// largest component; repeated until stable. When no split is possible (star on one side, or a side
// that cannot be made connected) the plan holds the whole star in side_a and side_b is empty.
// x: current coordinates, 3 per node. Deterministic.
SplitPlan plan_node_split(const Mesh& mesh, const NodeStars& stars, const double* x, int node,
                          const double n[3]);

// Applies the plan: appends a copy of the node (its reference coordinates to mesh.X; the caller
// extends its own per-node arrays using the returned index), rewrites conn of the side_b elements
// to the copy, adds the copy to every node set that holds the parent (sets stay sorted) and
// updates `stars`. Returns the new node's index (== old num_nodes()). Throws
// std::invalid_argument on an empty side or a plan whose sides are not the node's current star.
int split_node(Mesh& mesh, NodeStars& stars, const SplitPlan& plan);

// A node whose star falls into pieces that touch only at the node (a "bow-tie" left by cracks
// around it) holds those pieces together by itself. The plan keeps the largest face-connected
// piece (lowest element among equals) on side a and gives every other piece to side b (empty
// when the star is face-connected); repeat on the copy until its star is connected too.
SplitPlan plan_star_separation(const Mesh& mesh, const NodeStars& stars, int node);

// Connected components of the active mesh (elements joined through shared nodes), one id per
// element (-1 for inactive), ids numbered 0.. in order of their lowest element. Returns the count.
int element_components(const Mesh& mesh, std::vector<int>& comp);

} // namespace fracdem
