// Reduces one sphere's facet hits to unique physical contacts using the surface's Voronoi regions.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "contact/geometry.h"
#include "fem/mesh.h"

namespace fracdem
{

struct FacetHit {
  int facet;
  ClosestPoint cp;
  int nodes[3]; // global node ids of the facet
  int nn;       // 3 triangle, 2 segment
};

// Adjacency of the boundary surface, rebuilt whenever the facets change (fracture, erosion).
struct SurfaceTopology {
  std::vector<std::vector<int>> node_neighbors; // nodes joined by a facet edge
  std::unordered_map<std::uint64_t, std::vector<int>>
      edge_apex; // edge -> opposite node per triangle
  void build(const std::vector<Facet>& facets, int nnodes);
};

// A sphere on a flat triangulated surface is within reach of many facets, but over the interior
// of only one: the others see it at an edge or vertex. An edge (vertex) hit is a real contact only
// when the sphere centre q lies in that feature's Voronoi region of the surface: beyond the edge
// as seen from every adjacent triangle (beyond the vertex along every surface edge leaving it).
// Face hits are always kept; edge/vertex hits must also be distinct and not covered by a kept hit.
// Result: one contact on flat surfaces whatever the mesh, one edge contact on a convex ridge.
std::vector<FacetHit> resolve_sphere_hits(std::vector<FacetHit> hits, const double q[3],
                                          const double* x, const SurfaceTopology& topo);

// Key of the touched feature from its sorted global node ids, stable under facet renumbering.
std::uint64_t feature_key(const FacetHit& hit);

} // namespace fracdem

namespace fracdem
{

// Groups one sphere's kept hits into physical contacts. A sphere pressed into a finely meshed
// body touches many facets of one dimple: applying a point law per facet would count the
// sphere's own compliance once per facet and make the contact stiffer with every refinement.
// Hits whose normals lie within `max_angle_cos` of the deepest hit's normal form one contact,
// evaluated once at the deepest overlap; separate contacts (a sphere in a groove) stay separate.
// Hits on different pieces (pieces[k], e.g. the surface's connected components: fragments of a
// broken body) never share a contact, whatever their normals; nullptr: one piece.
// normals: 3 per hit; overlaps: per hit. Returns clusters of hit indices, deepest first.
std::vector<std::vector<int>> cluster_hits(const double* normals, const double* overlaps, int nhits,
                                           const int* pieces = nullptr,
                                           double max_angle_cos = 0.866);

} // namespace fracdem
