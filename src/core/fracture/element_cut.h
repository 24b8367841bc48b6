// Cracks through elements (fracture nodal min_size): where the failure plane through a crack
// point crosses an element, the edge to bisect so that the crack can follow the plane.
#pragma once

#include <functional>
#include <vector>

#include "fem/edge_bisect.h"
#include "fem/mesh.h"
#include "fem/node_split.h"

namespace fracdem
{

// A cut: bisect edge uw at P = u + t (w - u) so that a face (edge in 2D) through the crack point
// lies in the cut's plane.
struct ElementCut {
  int elem = -1;               // the element of the crack point's star that the plane crosses
  int u = -1, w = -1;          // the edge to bisect (opposite the crack point in 2D; in 3D the edge
                               // opposite the point's edge most nearly in the failure plane)
  double t = 0;                // children's measures: t and 1 - t of the parent's
  double alignment = 0;        // |cos| of the angle between the failure normal and the cut's plane
  double boundary = 0;         // the same for the best element boundary through the point it beats
  std::vector<QuadJoin> joins; // how each quad4 around the edge is split (fem/edge_bisect.h)
  bool found() const { return elem >= 0; }
};

// The best cut at crack point `node` (current positions x, 3 per node; unit failure normal n),
// or none (elem -1). 2D (tri3): the failure line through the point crosses the edge opposite
// it in a star triangle; the cut's edge lies in the plane (alignment 1) and competes with the
// element edges through the point on the same side (their angle with the line). 2D (quad4, nodes
// A, B, C, D counter-clockwise from the point A): the line leaves through BC or CD, and P joins
// A (the cut's edge AP in the plane); a quad4 neighbour across the cut edge joins P to the one of
// its two far nodes that keeps both its pieces convex and above min_size (the larger smaller
// piece; no cut when neither does). 3D (tet4): in
// a star tet, the point's edge AB most nearly in the plane (least |n . AB| / |AB|), and the
// plane through AB closest to the failure plane (normal n made orthogonal to AB) crossing the
// opposite edge CD; it competes with every face through the point. A cut is taken only when its
// plane is better aligned than its competitors, both children of every element around the edge
// keep at least min_size of their mesh element's measure (no sliver is ever made; for a quad4 its
// tri3 and quad4 pieces, the quad4 convex). Among several, the best aligned (lowest element
// among equals). Deterministic. fraction (optional): element e's measure as a fraction of the mesh
// element it is a piece of (1 for mesh elements, the default). Every element around the cut edge is
// split at the same t, so each must keep min(t, 1 - t) fraction(e) >= min_size (a quad4: its
// smaller piece's share times fraction(e)): the guard holds
// against the MESH element, and pieces of pieces never fall below it.
ElementCut find_element_cut(const Mesh& mesh, const NodeStars& stars, const double* x, int node,
                            const double n[3], double min_size,
                            const std::function<double(int)>& fraction = nullptr);

} // namespace fracdem
