// Mutable finite-element mesh topology shared by all fracdem core kernels.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace fracdem
{

// Linear element families supported by the kernels. Values are stable (used in
// restart files and VTK cell-type mapping).
enum class ElemType : std::uint8_t { Tri3 = 0, Quad4 = 1, Tet4 = 2 };

inline int nodes_per_elem(ElemType t)
{
  switch (t) {
  case ElemType::Tri3:
    return 3;
  case ElemType::Quad4:
    return 4;
  case ElemType::Tet4:
    return 4;
  }
  return 0;
}

// Integration points of the element kernels (tet4, tri3: one; quad4: 2x2 Gauss).
inline int points_per_elem(ElemType t)
{
  return t == ElemType::Quad4 ? 4 : 1;
}

inline int elem_dim(ElemType t)
{
  return t == ElemType::Tet4 ? 3 : 2;
}

// Plain-data mesh. Topology is deliberately kept mutable: fracture will split
// nodes (append to X, rewrite conn entries), erosion clears `active`, and the
// boundary / contact surface are always re-derived from `conn` + `active`
// rather than stored, so they can never go stale.
struct Mesh {
  int dim = 3;                          // 2 (x-y plane, z = 0) or 3
  std::vector<double> X;                // reference coordinates, 3 per node
  std::vector<ElemType> etype;          // per element
  std::vector<std::array<int, 4>> conn; // node indices, unused slots = -1
  std::vector<std::uint8_t> active;     // 1 = live, 0 = eroded
  std::vector<int> region;              // physical tag of the element (0 = none)

  // Named sets from the mesh file (Gmsh physical groups), node indices sorted.
  std::map<std::string, std::vector<int>> node_sets;
  std::map<std::string, std::vector<int>> elem_sets;

  int num_nodes() const { return static_cast<int>(X.size() / 3); }
  int num_elems() const { return static_cast<int>(conn.size()); }
  int num_active_elems() const
  {
    int n = 0;
    for (auto a : active)
      n += a ? 1 : 0;
    return n;
  }
};

// A boundary entity of the current (active) mesh: a triangle of a tet in 3D
// (nn = 3) or an edge of a 2D element (nn = 2), ordered so that its normal
// (right-hand rule in 3D; (dy, -dx) for an edge p0->p1 in 2D) points out of
// the owning element.
struct Facet {
  std::array<int, 3> n{{-1, -1, -1}};
  int nn = 0;
  int elem = -1;       // owning element
  int local_face = -1; // face/edge index within the owning element
};

// Facets that belong to exactly one active element. Deterministic order
// (sorted by owning element, then local face).
std::vector<Facet> boundary_facets(const Mesh& mesh);
// The facets of element e as sorted node triples (third -1 for a 2D edge), in local-face order:
// two elements share a facet when they share a key. Returns the count (4 for a tet, 3 or 4 in 2D).
int element_facet_keys(const Mesh& mesh, int e, std::array<int, 3>* keys);

// Six times the signed volume of the tet with nodes c (3 coordinates per node in X): positive
// when node 3 lies on the side of face (0, 1, 2) that its right-hand normal points to.
double tet_volume6(const double* X, const std::array<int, 4>& c);

// Signed measure of element e in the reference configuration: tet volume (sign as above), or the
// area of a triangle / quad in the x-y plane (positive when counter-clockwise).
double signed_measure(const Mesh& m, int e);

// Area of a triangle facet, or length of an edge facet (2D facets lie in z = 0), with node
// positions x (3 per node).
double facet_measure(const double* x, const Facet& fc);

// Largest distance between two nodes of element e in the reference configuration: an upper
// bound of the element's width across any direction (crack-band checks).
double element_diameter(const Mesh& m, int e);

// True when element e's reference measure and diameter are finite: false when a coordinate is not
// finite, or when coordinates are so large (~1e154 and up) that the volume or a squared distance
// overflows. Readers and transforms check this so the FE setup never sees inf / NaN geometry.
bool element_geometry_finite(const Mesh& m, int e);

} // namespace fracdem
