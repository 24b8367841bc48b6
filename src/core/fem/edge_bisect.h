// Conforming edge bisection: a new node on an edge and every element around the edge split in
// two children of the same type (cracks through elements, fracture nodal min_size).
#pragma once

#include <vector>

#include "fem/mesh.h"
#include "fem/node_split.h"

namespace fracdem
{

// The active elements that hold both nodes u and w (the elements around edge uw), ascending.
std::vector<int> elements_on_edge(const NodeStars& stars, int u, int w);

// Whether edge uw can be bisected conformingly: it is an edge of at least one active element and
// every active element around it is a tri3 or a tet4 (a quad4 cut in two along one edge would
// leave its neighbour non-conforming, so quads are never cut).
bool edge_bisectable(const Mesh& mesh, const NodeStars& stars, int u, int w);

// Bisects edge uw at P = X_u + t (X_w - X_u), 0 < t < 1: appends P to mesh.X and splits every
// active element around the edge: its slot keeps the child with u (w replaced by P, measure t of
// the parent's), and a new element appended at the end gets the child with w (u replaced by P,
// measure 1 - t). Children keep the parent's type, region and element sets; node orientation,
// hence the sign of the measure, is the parent's. `parents` receives one entry per new element
// (its parent's index), in the order of the new indices. Returns P's index. `stars` is read, not
// updated (NodeStars::build afterwards). Throws std::invalid_argument when the edge is not
// bisectable or t is outside (0, 1).
int bisect_edge(Mesh& mesh, const NodeStars& stars, int u, int w, double t,
                std::vector<int>& parents);

} // namespace fracdem
