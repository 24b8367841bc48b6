// Conforming edge bisection of tri3 / tet4 meshes (the mesh half of a crack through an element).
#include "fem/edge_bisect.h"

#include <algorithm>
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

bool edge_bisectable(const Mesh& mesh, const NodeStars& stars, int u, int w)
{
  if (u == w || u < 0 || w < 0 || u >= stars.num_nodes() || w >= stars.num_nodes()) return false;
  const std::vector<int> around = elements_on_edge(stars, u, w);
  if (around.empty()) return false;
  // A tri3 holds each of its three node pairs as an edge, a tet4 each of its six.
  return std::none_of(around.begin(), around.end(),
                      [&](int e) { return mesh.etype[e] == ElemType::Quad4; });
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
} // namespace

int bisect_edge(Mesh& mesh, const NodeStars& stars, int u, int w, double t,
                std::vector<int>& parents)
{
  if (!(t > 0 && t < 1))
    throw std::invalid_argument("bisect_edge: ratio t = " + std::to_string(t) + " outside (0, 1)");
  if (!edge_bisectable(mesh, stars, u, w))
    throw std::invalid_argument("bisect_edge: edge " + std::to_string(u) + "-" + std::to_string(w) +
                                " is not an edge of active tri3/tet4 only");
  const std::vector<int> around = elements_on_edge(stars, u, w);
  const int p = mesh.num_nodes();
  double xp[3];
  for (int d = 0; d < 3; ++d)
    xp[d] = mesh.X[3 * u + d] + t * (mesh.X[3 * w + d] - mesh.X[3 * u + d]);
  mesh.X.insert(mesh.X.end(), xp, xp + 3);
  parents.clear();
  for (int e : around) {
    const int child = mesh.num_elems();
    std::array<int, 4> c = mesh.conn[e];
    for (int& a : c)
      if (a == u) a = p; // the child with w
    for (int& a : mesh.conn[e])
      if (a == w) a = p; // the slot keeps the child with u
    mesh.conn.push_back(c);
    mesh.etype.push_back(mesh.etype[e]);
    mesh.active.push_back(1);
    if (static_cast<int>(mesh.region.size()) == child) mesh.region.push_back(mesh.region[e]);
    join_parent_sets(mesh, e, child);
    parents.push_back(e);
  }
  return p;
}

} // namespace fracdem
