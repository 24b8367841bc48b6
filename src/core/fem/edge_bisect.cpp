// Conforming edge bisection of tri3 / quad4 / tet4 meshes (the mesh half of element cuts).
#include "fem/edge_bisect.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>

namespace fracdem
{

std::vector<int> elements_on_edge(const NodeStars& stars, int u, int w)
{
  std::vector<int> both;
  std::set_intersection(stars.begin(u), stars.end(u), stars.begin(w), stars.end(w),
                        std::back_inserter(both));
  return both;
}

namespace
{
// Where edge uw starts in quad e's node cycle (uw or wu at positions i, i + 1), or -1.
int quad_edge_start(const std::array<int, 4>& c, int u, int w)
{
  for (int i = 0; i < 4; ++i) {
    const int a = c[i], b = c[(i + 1) % 4];
    if ((a == u && b == w) || (a == w && b == u)) return i;
  }
  return -1;
}
} // namespace

bool edge_bisectable(const Mesh& mesh, const NodeStars& stars, int u, int w)
{
  if (u == w || u < 0 || w < 0 || u >= stars.num_nodes() || w >= stars.num_nodes()) return false;
  const std::vector<int> around = elements_on_edge(stars, u, w);
  if (around.empty()) return false;
  // A tri3 holds each of its three node pairs as an edge, a tet4 each of its six; a quad4 only
  // the pairs next to each other in its cycle.
  return std::none_of(around.begin(), around.end(), [&](int e) {
    return mesh.etype[e] == ElemType::Quad4 && quad_edge_start(mesh.conn[e], u, w) < 0;
  });
}

bool quad_children(const Mesh& mesh, int e, int u, int w, int p, int join, std::array<int, 4>& tri,
                   std::array<int, 4>& quad)
{
  if (mesh.etype[e] != ElemType::Quad4) return false;
  const std::array<int, 4>& c = mesh.conn[e];
  const int i = quad_edge_start(c, u, w);
  if (i < 0) return false;
  const int a = c[i], b = c[(i + 1) % 4], cc = c[(i + 2) % 4], d = c[(i + 3) % 4];
  if (join == cc) {
    tri = {p, b, cc, -1};
    quad = {a, p, cc, d};
  } else if (join == d) {
    tri = {a, p, d, -1};
    quad = {p, b, cc, d};
  } else {
    return false;
  }
  return true;
}

QuadSplitShape quad_split_shape(const Mesh& mesh, int e, int u, int w, double t, int join)
{
  QuadSplitShape shape;
  const int p = mesh.num_nodes(); // P's index to be
  std::array<int, 4> tri, quad;
  if (!quad_children(mesh, e, u, w, p, join, tri, quad)) return shape;
  double xp[2];
  for (int d = 0; d < 2; ++d)
    xp[d] = mesh.X[3 * u + d] + t * (mesh.X[3 * w + d] - mesh.X[3 * u + d]);
  auto at = [&](int n, int d) { return n == p ? xp[d] : mesh.X[3 * n + d]; };
  auto turn = [&](int a, int b, int c) { // twice the signed area of a, b, c
    return (at(b, 0) - at(a, 0)) * (at(c, 1) - at(a, 1)) -
           (at(b, 1) - at(a, 1)) * (at(c, 0) - at(a, 0));
  };
  const double whole = signed_measure(mesh, e);
  shape.tri_fraction = 0.5 * turn(tri[0], tri[1], tri[2]) / whole;
  // Strictly convex, with a margin against a corner of nearly 180 degrees (a vanishing Jacobian
  // there): every corner's turn above 1e-9 of the parent's area.
  shape.convex = true;
  for (int k = 0; k < 4; ++k)
    if (!(turn(quad[k], quad[(k + 1) % 4], quad[(k + 2) % 4]) > 2e-9 * whole)) shape.convex = false;
  return shape;
}

namespace
{
// Adds the new element `child` to every element set that holds `parent` (appended indices are
// the largest, so the sets stay sorted).
void join_parent_sets(Mesh& mesh, int parent, int child)
{
  for (auto& entry : mesh.elem_sets) {
    std::vector<int>& set = entry.second;
    if (std::binary_search(set.begin(), set.end(), parent)) set.push_back(child);
  }
}

int join_of(const std::vector<QuadJoin>& joins, int e)
{
  for (const QuadJoin& j : joins)
    if (j.elem == e) return j.node;
  return -1;
}
} // namespace

int bisect_edge(Mesh& mesh, const NodeStars& stars, int u, int w, double t,
                std::vector<int>& parents, const std::vector<QuadJoin>& joins)
{
  if (!(t > 0 && t < 1))
    throw std::invalid_argument("bisect_edge: ratio t = " + std::to_string(t) + " outside (0, 1)");
  if (!edge_bisectable(mesh, stars, u, w))
    throw std::invalid_argument("bisect_edge: edge " + std::to_string(u) + "-" + std::to_string(w) +
                                " is not an edge of every active element that holds both nodes");
  const std::vector<int> around = elements_on_edge(stars, u, w);
  const int p = mesh.num_nodes();
  // Every quad's children first, so that a bad join throws before the mesh changes.
  std::vector<std::array<int, 4>> tris(around.size()), quads(around.size());
  for (size_t i = 0; i < around.size(); ++i)
    if (mesh.etype[around[i]] == ElemType::Quad4 &&
        !quad_children(mesh, around[i], u, w, p, join_of(joins, around[i]), tris[i], quads[i]))
      throw std::invalid_argument("bisect_edge: quad4 " + std::to_string(around[i]) +
                                  " around edge " + std::to_string(u) + "-" + std::to_string(w) +
                                  " has no join to a node off the edge");
  double xp[3];
  for (int d = 0; d < 3; ++d)
    xp[d] = mesh.X[3 * u + d] + t * (mesh.X[3 * w + d] - mesh.X[3 * u + d]);
  mesh.X.insert(mesh.X.end(), xp, xp + 3);
  parents.clear();
  for (size_t i = 0; i < around.size(); ++i) {
    const int e = around[i], child = mesh.num_elems();
    std::array<int, 4> c = mesh.conn[e];
    ElemType type = mesh.etype[e];
    if (type == ElemType::Quad4) {
      mesh.conn[e] = quads[i];
      c = tris[i];
      type = ElemType::Tri3;
    } else {
      for (int& a : c)
        if (a == u) a = p; // the child with w
      for (int& a : mesh.conn[e])
        if (a == w) a = p; // the slot keeps the child with u
    }
    mesh.conn.push_back(c);
    mesh.etype.push_back(type);
    mesh.active.push_back(1);
    if (static_cast<int>(mesh.region.size()) == child) mesh.region.push_back(mesh.region[e]);
    join_parent_sets(mesh, e, child);
    parents.push_back(e);
  }
  return p;
}

} // namespace fracdem
