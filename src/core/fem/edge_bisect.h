// Conforming edge bisection: a new node on an edge and every element around the edge split in
// two children (cracks through elements, fracture nodal min_size).
#pragma once

#include <array>
#include <vector>

#include "fem/mesh.h"
#include "fem/node_split.h"

namespace fracdem
{

// The active elements that hold both nodes u and w (the elements around edge uw), ascending.
std::vector<int> elements_on_edge(const NodeStars& stars, int u, int w);

// Whether edge uw can be bisected conformingly: it is an edge of at least one active element and
// of every active element that holds both nodes (a quad4 holding them across a diagonal is not
// cut).
bool edge_bisectable(const Mesh& mesh, const NodeStars& stars, int u, int w);

// A quad4 around a bisected edge (its nodes A, B, C, D counter-clockwise, P on AB) is split into
// a tri3 and a quad4 by a line from P to C or to D: (P, B, C) + (A, P, C, D) or (A, P, D) +
// (P, B, C, D). `node` names C or D.
struct QuadJoin {
  int elem = -1;
  int node = -1;
};

// The children of quad e when P (index p) bisects its edge uw and joins `join`: tri (slot 3 = -1)
// and quad, both counter-clockwise like e. False when uw is not an edge of e or join is not one
// of its other two nodes.
bool quad_children(const Mesh& mesh, int e, int u, int w, int p, int join, std::array<int, 4>& tri,
                   std::array<int, 4>& quad);

// The shape of that split in the reference configuration, P = X_u + t (X_w - X_u): the tri
// child's area as a fraction of e's, and whether the quad child is strictly convex (every corner
// turns left: then its bilinear map has a positive Jacobian everywhere, integration points
// included). tri_fraction -1 when the split does not exist.
struct QuadSplitShape {
  double tri_fraction = -1;
  bool convex = false;
};
QuadSplitShape quad_split_shape(const Mesh& mesh, int e, int u, int w, double t, int join);

// Bisects edge uw at P = X_u + t (X_w - X_u), 0 < t < 1: appends P to mesh.X and splits every
// active element around the edge. A tri3 or tet4 keeps in its slot the child with u (w replaced
// by P, measure t of the parent's) and a new element appended at the end gets the child with w
// (u replaced by P, measure 1 - t), of its type. A quad4 is split as `joins` says (an entry per
// quad around the edge): its slot keeps the quad4 child, the new element is the tri3 child.
// Children keep the parent's region and element sets; node orientation, hence the sign of the
// measure, is the parent's. `parents` receives one entry per new element (its parent's index),
// in the order of the new indices. Returns P's index. `stars` is read, not updated
// (NodeStars::build afterwards). Throws std::invalid_argument when the edge is not bisectable,
// t is outside (0, 1) or a quad around the edge has no valid join.
int bisect_edge(Mesh& mesh, const NodeStars& stars, int u, int w, double t,
                std::vector<int>& parents, const std::vector<QuadJoin>& joins = {});

} // namespace fracdem
