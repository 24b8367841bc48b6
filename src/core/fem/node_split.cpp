// Nodal fracture topology: element stars, plane-based split plans made face-connected, splitting.
#include "fem/node_split.h"

#include <algorithm>
#include <array>
#include <iterator>
#include <stdexcept>
#include <string>
#include <utility>

namespace fracdem
{

void facets_through(const Mesh& mesh, int e, int node, std::vector<std::array<int, 2>>& others)
{
  const auto& c = mesh.conn[e];
  const int k = nodes_per_elem(mesh.etype[e]);
  int s = 0;
  while (c[s] != node)
    ++s;
  if (mesh.etype[e] == ElemType::Tet4) {
    int o[3], m = 0;
    for (int a = 0; a < 4; ++a)
      if (a != s) o[m++] = c[a];
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j)
        others.push_back({o[i], o[j]});
  } else { // tri3 / quad4: only the two cyclic neighbours span an edge with the node
    others.push_back({c[(s + 1) % k], -1});
    others.push_back({c[(s + k - 1) % k], -1});
  }
}

namespace
{

using Adjacency = std::vector<std::vector<int>>; // local star index -> face-neighbours in the star

// Keys of the facets of element e that contain `node`, named by their other nodes so that two
// elements share a facet through the node exactly when they share a key. 2D: the far node of each
// edge at the node (second = -1); 3D: the sorted pair of the other two nodes of each triangle.
void facet_keys(const Mesh& mesh, int e, int node, std::vector<std::pair<int, int>>& keys)
{
  std::vector<std::array<int, 2>> others;
  facets_through(mesh, e, node, others);
  for (const auto& o : others)
    keys.push_back(o[1] < 0 ? std::make_pair(o[0], -1)
                            : std::pair<int, int>(std::minmax(o[0], o[1])));
}

// Face-adjacency inside the star, by sorting facet keys (no hashing, so the result is
// deterministic). Non-manifold facets shared by more than two elements connect all of them.
Adjacency star_adjacency(const Mesh& mesh, int node, const std::vector<int>& star)
{
  std::vector<std::pair<std::pair<int, int>, int>> entries; // (key, local index)
  std::vector<std::pair<int, int>> keys;
  for (int i = 0; i < static_cast<int>(star.size()); ++i) {
    keys.clear();
    facet_keys(mesh, star[i], node, keys);
    for (const auto& k : keys)
      entries.push_back({k, i});
  }
  std::sort(entries.begin(), entries.end());
  Adjacency adj(star.size());
  for (size_t g = 0; g < entries.size();) {
    size_t h = g + 1;
    while (h < entries.size() && entries[h].first == entries[g].first)
      ++h;
    for (size_t p = g; p < h; ++p)
      for (size_t q = p + 1; q < h; ++q) {
        adj[entries[p].second].push_back(entries[q].second);
        adj[entries[q].second].push_back(entries[p].second);
      }
    g = h;
  }
  for (auto& a : adj) {
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
  }
  return adj;
}

// Face-connected components of the star elements on side s. The largest one wins ties by its
// lowest element, so that the choice does not depend on anything but the input.
struct SideComponents {
  int count = 0, largest = -1;
  std::vector<int> id; // component per local element, -1 on the other side
};

SideComponents side_components(const Adjacency& adj, const std::vector<char>& side, char s)
{
  SideComponents sc;
  sc.id.assign(adj.size(), -1);
  std::vector<int> size, queue;
  for (int i = 0; i < static_cast<int>(adj.size()); ++i) {
    if (side[i] != s || sc.id[i] >= 0) continue;
    const int c = sc.count++;
    size.push_back(0);
    sc.id[i] = c;
    queue.assign(1, i);
    for (size_t h = 0; h < queue.size(); ++h) {
      ++size[c];
      for (int v : adj[queue[h]])
        if (side[v] == s && sc.id[v] < 0) {
          sc.id[v] = c;
          queue.push_back(v);
        }
    }
    if (sc.largest < 0 || size[c] > size[sc.largest]) sc.largest = c;
  }
  return sc;
}

// Moves stray elements (outside their side's largest component) to the other side when they touch
// its largest component. A move takes nothing from a largest component and joins one, so the sum
// of the two largest sizes grows with every move: the loop ends after at most star-size moves.
// Returns whether both sides ended connected.
bool connect_sides(const Adjacency& adj, std::vector<char>& side)
{
  for (bool moved = true; moved;) {
    moved = false;
    for (char s = 0; s < 2; ++s) {
      const SideComponents own = side_components(adj, side, s);
      if (own.count <= 1) continue;
      const SideComponents other = side_components(adj, side, char(1 - s));
      std::vector<int> go;
      for (int i = 0; i < static_cast<int>(adj.size()); ++i) {
        if (side[i] != s || own.id[i] == own.largest) continue;
        for (int v : adj[i])
          if (other.id[v] == other.largest) {
            go.push_back(i);
            break;
          }
      }
      for (int i : go)
        side[i] = char(1 - s);
      moved = moved || !go.empty();
    }
  }
  return side_components(adj, side, 0).count <= 1 && side_components(adj, side, 1).count <= 1;
}

// Throws unless the plan splits the node's current star into two non-empty sorted sides: a plan
// made before another split changed this star would otherwise silently orphan elements.
void check_plan(const Mesh& mesh, const NodeStars& stars, const SplitPlan& plan)
{
  if (stars.num_nodes() != mesh.num_nodes())
    throw std::invalid_argument("split_node: NodeStars is not current for this mesh");
  if (plan.node < 0 || plan.node >= mesh.num_nodes())
    throw std::invalid_argument("split_node: node " + std::to_string(plan.node) + " out of range");
  if (!plan.splittable())
    throw std::invalid_argument("split_node: plan for node " + std::to_string(plan.node) +
                                " has an empty side");
  std::vector<int> both;
  std::merge(plan.side_a.begin(), plan.side_a.end(), plan.side_b.begin(), plan.side_b.end(),
             std::back_inserter(both));
  // Equality with the sorted star also proves both sides sorted and disjoint.
  if (!std::equal(both.begin(), both.end(), stars.begin(plan.node), stars.end(plan.node)))
    throw std::invalid_argument("split_node: plan sides of node " + std::to_string(plan.node) +
                                " are not a partition of its current star");
}

} // namespace

void NodeStars::build(const Mesh& mesh)
{
  const int nn = mesh.num_nodes();
  offset.assign(nn + 1, 0);
  for (int e = 0; e < mesh.num_elems(); ++e) {
    if (!mesh.active[e]) continue;
    for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
      ++offset[mesh.conn[e][a] + 1];
  }
  for (int n = 0; n < nn; ++n)
    offset[n + 1] += offset[n];
  elems.resize(offset[nn]);
  std::vector<int> fill(offset.begin(), offset.end() - 1);
  for (int e = 0; e < mesh.num_elems(); ++e) { // ascending e: every star comes out sorted
    if (!mesh.active[e]) continue;
    for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
      elems[fill[mesh.conn[e][a]]++] = e;
  }
}

void NodeStars::apply_split(int parent, int copy, const std::vector<int>& moved)
{
  if (copy != num_nodes())
    throw std::invalid_argument("NodeStars::apply_split: the copy must be the next node index");
  const auto first = elems.begin() + offset[parent], last = elems.begin() + offset[parent + 1];
  const auto kept = std::remove_if(
      first, last, [&](int e) { return std::binary_search(moved.begin(), moved.end(), e); });
  const int removed = static_cast<int>(last - kept);
  elems.erase(kept, last);
  for (size_t n = parent + 1; n < offset.size(); ++n)
    offset[n] -= removed;
  elems.insert(elems.end(), moved.begin(), moved.end());
  offset.push_back(static_cast<int>(elems.size()));
}

SplitPlan plan_node_split(const Mesh& mesh, const NodeStars& stars, const double* x, int node,
                          const double n[3])
{
  if (node < 0 || node >= stars.num_nodes())
    throw std::invalid_argument("plan_node_split: node " + std::to_string(node) + " out of range");
  SplitPlan plan;
  plan.node = node;
  const std::vector<int> star(stars.begin(node), stars.end(node));
  const double* p = x + 3 * node;
  std::vector<char> side(star.size());
  bool any[2] = {false, false};
  for (size_t i = 0; i < star.size(); ++i) {
    const auto& c = mesh.conn[star[i]];
    const int k = nodes_per_elem(mesh.etype[star[i]]);
    double d = 0; // centroid offset from the plane, summed relative to p to avoid cancellation
    for (int a = 0; a < k; ++a)
      for (int j = 0; j < 3; ++j)
        d += (x[3 * c[a] + j] - p[j]) * n[j];
    side[i] = d > 0 ? 1 : 0;
    any[d > 0] = true;
  }
  if (any[0] && any[1] && connect_sides(star_adjacency(mesh, node, star), side)) {
    for (size_t i = 0; i < star.size(); ++i)
      (side[i] ? plan.side_b : plan.side_a).push_back(star[i]);
  } else {
    plan.side_a = star;
  }
  return plan;
}

SplitPlan plan_star_separation(const Mesh& mesh, const NodeStars& stars, int node)
{
  SplitPlan plan;
  plan.node = node;
  const std::vector<int> star(stars.begin(node), stars.end(node));
  const std::vector<char> side(star.size(), 0);
  const SideComponents sc = side_components(star_adjacency(mesh, node, star), side, 0);
  for (size_t i = 0; i < star.size(); ++i)
    (sc.count > 1 && sc.id[i] != sc.largest ? plan.side_b : plan.side_a).push_back(star[i]);
  return plan;
}

int split_node(Mesh& mesh, NodeStars& stars, const SplitPlan& plan)
{
  check_plan(mesh, stars, plan);
  const int parent = plan.node, copy = mesh.num_nodes();
  // Copy first: appending from mesh.X itself could read a reallocated buffer.
  const double X0[3] = {mesh.X[3 * parent], mesh.X[3 * parent + 1], mesh.X[3 * parent + 2]};
  mesh.X.insert(mesh.X.end(), X0, X0 + 3);
  for (int e : plan.side_b)
    for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
      if (mesh.conn[e][a] == parent) mesh.conn[e][a] = copy;
  // Boundary conditions and loads named on the parent's set must apply to both halves.
  for (auto& entry : mesh.node_sets) {
    auto& set = entry.second;
    if (std::binary_search(set.begin(), set.end(), parent))
      set.insert(std::lower_bound(set.begin(), set.end(), copy), copy);
  }
  stars.apply_split(parent, copy, plan.side_b);
  return copy;
}

int element_components(const Mesh& mesh, std::vector<int>& comp)
{
  NodeStars stars; // inactive elements are in no star, so the search never reaches them
  stars.build(mesh);
  comp.assign(mesh.num_elems(), -1);
  int count = 0;
  std::vector<int> queue;
  for (int e = 0; e < mesh.num_elems(); ++e) {
    if (!mesh.active[e] || comp[e] >= 0) continue;
    comp[e] = count;
    queue.assign(1, e);
    for (size_t h = 0; h < queue.size(); ++h) {
      const int u = queue[h];
      for (int a = 0; a < nodes_per_elem(mesh.etype[u]); ++a)
        for (const int* f = stars.begin(mesh.conn[u][a]); f != stars.end(mesh.conn[u][a]); ++f)
          if (comp[*f] < 0) {
            comp[*f] = count;
            queue.push_back(*f);
          }
    }
    ++count;
  }
  return count;
}

} // namespace fracdem
