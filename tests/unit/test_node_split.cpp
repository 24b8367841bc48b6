// Unit tests of nodal fracture topology: split plans, node splitting, stars and mesh components.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include "fem/node_split.h"
#include "test_support.h"

using namespace fracdem;

namespace
{

void add_node(Mesh& m, double x, double y, double z = 0)
{
  m.X.insert(m.X.end(), {x, y, z});
}

void add_elem(Mesh& m, ElemType t, std::array<int, 4> c)
{
  m.etype.push_back(t);
  m.conn.push_back(c);
  m.active.push_back(1);
  m.region.push_back(0);
}

int gid(int nx, int i, int j)
{
  return j * (nx + 1) + i;
}

// nx x ny unit squares, each cut by its (i,j)-(i+1,j+1) diagonal into two CCW triangles: the
// lower one first, so element 2*(j*nx+i) lies right of the diagonal.
Mesh tri_grid(int nx, int ny)
{
  Mesh m;
  m.dim = 2;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      add_node(m, i, j);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = gid(nx, i, j), b = gid(nx, i + 1, j), c = gid(nx, i + 1, j + 1),
                d = gid(nx, i, j + 1);
      add_elem(m, ElemType::Tri3, {a, b, c, -1});
      add_elem(m, ElemType::Tri3, {a, c, d, -1});
    }
  return m;
}

Mesh quad_grid(int nx, int ny)
{
  Mesh m;
  m.dim = 2;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      add_node(m, i, j);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      add_elem(m, ElemType::Quad4,
               {gid(nx, i, j), gid(nx, i + 1, j), gid(nx, i + 1, j + 1), gid(nx, i, j + 1)});
  return m;
}

// n^3 unit cubes, each cut into the 6 Kuhn tets around its (0,0,0)-(1,1,1) diagonal (conforming
// across cubes because every cube uses the same diagonal direction), positively oriented.
Mesh tet_box(int n)
{
  Mesh m;
  m.dim = 3;
  auto id = [n](int i, int j, int k) { return (k * (n + 1) + j) * (n + 1) + i; };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        add_node(m, i, j, k);
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const auto& p : perms) {
          int v[3] = {i, j, k};
          std::array<int, 4> c;
          c[0] = id(v[0], v[1], v[2]);
          ++v[p[0]];
          c[1] = id(v[0], v[1], v[2]);
          ++v[p[1]];
          c[2] = id(v[0], v[1], v[2]);
          ++v[p[2]];
          c[3] = id(v[0], v[1], v[2]);
          add_elem(m, ElemType::Tet4, c);
          if (fracdem_test::tet_volume(m, m.num_elems() - 1) < 0)
            std::swap(m.conn.back()[2], m.conn.back()[3]);
        }
  return m;
}

// Brute-force star (active elements holding the node), independent of NodeStars.
std::vector<int> brute_star(const Mesh& m, int node)
{
  std::vector<int> s;
  for (int e = 0; e < m.num_elems(); ++e)
    if (m.active[e] &&
        std::count(m.conn[e].begin(), m.conn[e].begin() + nodes_per_elem(m.etype[e]), node))
      s.push_back(e);
  return s;
}

// Lumped mass of a node: measure / nodes-per-element from each element of its star.
double node_mass(const Mesh& m, int node)
{
  double s = 0;
  for (int e : brute_star(m, node))
    s += std::fabs(signed_measure(m, e)) / nodes_per_elem(m.etype[e]);
  return s;
}

int shared_nodes(const Mesh& m, int e, int f)
{
  int s = 0;
  for (int a = 0; a < nodes_per_elem(m.etype[e]); ++a)
    for (int b = 0; b < nodes_per_elem(m.etype[f]); ++b)
      s += m.conn[e][a] == m.conn[f][b] ? 1 : 0;
  return s;
}

// Oracle for face-connectivity of a set of elements around one node: in the simplex meshes used
// here two elements of a star share a facet through the node exactly when they share dim nodes.
bool star_side_connected(const Mesh& m, const std::vector<int>& side)
{
  if (side.empty()) return true;
  std::vector<char> seen(side.size(), 0);
  std::vector<size_t> queue = {0};
  seen[0] = 1;
  for (size_t h = 0; h < queue.size(); ++h)
    for (size_t j = 0; j < side.size(); ++j)
      if (!seen[j] && shared_nodes(m, side[queue[h]], side[j]) >= m.dim) {
        seen[j] = 1;
        queue.push_back(j);
      }
  return queue.size() == side.size();
}

std::vector<int> current_star(const NodeStars& s, int n)
{
  return std::vector<int>(s.begin(n), s.end(n));
}

// Boundary facets touching `node`, named by their other node (2D meshes).
std::multiset<int> boundary_neighbours(const Mesh& m, int node)
{
  std::multiset<int> out;
  for (const Facet& f : boundary_facets(m))
    if (f.n[0] == node || f.n[1] == node) out.insert(f.n[0] == node ? f.n[1] : f.n[0]);
  return out;
}

// Splits, one after the other, every node whose reference coordinate `axis` equals `at`, with the
// plane normal along that axis; every plan must be splittable.
void split_plane(Mesh& m, NodeStars& stars, int axis, double at)
{
  const int nn = m.num_nodes();
  double n[3] = {0, 0, 0};
  n[axis] = 1;
  for (int node = 0; node < nn; ++node) {
    if (m.X[3 * node + axis] != at) continue;
    const std::vector<double> x = m.X; // current = reference; X grows with every split
    const SplitPlan plan = plan_node_split(m, stars, x.data(), node, n);
    ASSERT_TRUE(plan.splittable()) << "node " << node;
    split_node(m, stars, plan);
  }
}

const double kX[3] = {1, 0, 0};

} // namespace

// An interior node of a tri3 strip split by the vertical line through it: the three triangles
// left of x = 2 keep the node, the three right of it get the copy, and the two edges the halves
// shared through the node, (2,0)-(2,1) and (2,1)-(2,2), become four boundary edges.
TEST(NodeSplit, Tri3InteriorNodeSplitsLeftFromRight)
{
  Mesh m = tri_grid(4, 2);
  NodeStars stars;
  stars.build(m);
  const int node = gid(4, 2, 1);
  const SplitPlan plan = plan_node_split(m, stars, m.X.data(), node, kX);
  ASSERT_EQ(plan.side_a.size(), 3u);
  ASSERT_EQ(plan.side_b.size(), 3u);
  for (int e : plan.side_a) // reference centroid left of the line
    EXPECT_LT(m.X[3 * m.conn[e][0]] + m.X[3 * m.conn[e][1]] + m.X[3 * m.conn[e][2]], 6.0);
  for (int e : plan.side_b)
    EXPECT_GT(m.X[3 * m.conn[e][0]] + m.X[3 * m.conn[e][1]] + m.X[3 * m.conn[e][2]], 6.0);

  // Crack edges counted independently: pairs (a, b) that share an edge through the node.
  int crack = 0;
  for (int a : plan.side_a)
    for (int b : plan.side_b)
      crack += shared_nodes(m, a, b) == 2 ? 1 : 0;
  EXPECT_EQ(crack, 2);
  const size_t before = boundary_facets(m).size();
  EXPECT_EQ(before, 12u); // perimeter of the 4 x 2 strip
  const int copy = split_node(m, stars, plan);
  EXPECT_EQ(copy, 15);
  EXPECT_EQ(m.num_nodes(), 16);
  EXPECT_EQ(boundary_facets(m).size(), before + 2u * crack);
  for (int j = 0; j < 3; ++j)
    EXPECT_EQ(m.X[3 * copy + j], m.X[3 * node + j]);
  for (int e : plan.side_b) { // the copy replaced the parent, nothing else changed
    EXPECT_EQ(std::count(m.conn[e].begin(), m.conn[e].begin() + 3, copy), 1);
    EXPECT_EQ(std::count(m.conn[e].begin(), m.conn[e].begin() + 3, node), 0);
  }
  // Both crack faces run from the node's lower neighbour (2,0) and to its upper one (2,2).
  const std::multiset<int> expect = {gid(4, 2, 0), gid(4, 2, 2)};
  EXPECT_EQ(boundary_neighbours(m, node), expect);
  EXPECT_EQ(boundary_neighbours(m, copy), expect);
}

// Splitting every node of the line x = 2 separates the body; before the last split one node still
// holds the halves together, so the count must jump from 1 to 2 exactly at the end.
TEST(NodeSplit, ColumnSplitSeparatesTri3AndQuad4)
{
  for (bool quads : {false, true}) {
    Mesh m = quads ? quad_grid(4, 3) : tri_grid(4, 3);
    NodeStars stars;
    stars.build(m);
    const double n[3] = {1, 0, 0};
    std::vector<int> comp;
    for (int j = 0; j <= 3; ++j) {
      ASSERT_EQ(element_components(m, comp), 1) << "quads " << quads << " j " << j;
      const std::vector<double> x = m.X;
      const SplitPlan plan = plan_node_split(m, stars, x.data(), gid(4, 2, j), n);
      ASSERT_TRUE(plan.splittable());
      split_node(m, stars, plan);
    }
    ASSERT_EQ(element_components(m, comp), 2);
    const int per_side = quads ? 6 : 12; // 2 x 3 squares per side, 2 triangles each
    EXPECT_EQ(std::count(comp.begin(), comp.end(), 0), per_side);
    EXPECT_EQ(std::count(comp.begin(), comp.end(), 1), per_side);
    for (int e = 0; e < m.num_elems(); ++e) { // component 0 holds element 0, i.e. the left half
      double cx = 0;
      const int k = nodes_per_elem(m.etype[e]);
      for (int a = 0; a < k; ++a)
        cx += m.X[3 * m.conn[e][a]] / k;
      EXPECT_EQ(comp[e], cx < 2 ? 0 : 1) << "element " << e;
    }
  }
}

// tet4 box [0,2]^3 cut at x = 1 node by node: two components of volume 4 each, and the 8 mid-plane
// triangles become 16 new boundary facets.
TEST(NodeSplit, Tet4MidPlaneSplitHalvesTheBox)
{
  Mesh m = tet_box(2);
  ASSERT_EQ(m.num_elems(), 48);
  NodeStars stars;
  stars.build(m);
  const size_t boundary_before = boundary_facets(m).size();
  EXPECT_EQ(boundary_before, 48u);
  split_plane(m, stars, 0, 1.0);
  EXPECT_EQ(m.num_nodes(), 27 + 9);
  std::vector<int> comp;
  ASSERT_EQ(element_components(m, comp), 2);
  double vol[2] = {0, 0};
  for (int e = 0; e < m.num_elems(); ++e)
    vol[comp[e]] += signed_measure(m, e);
  EXPECT_NEAR(vol[0], 4.0, 1e-12);
  EXPECT_NEAR(vol[1], 4.0, 1e-12);
  EXPECT_EQ(boundary_facets(m).size(), boundary_before + 16u);
}

// The star is partitioned, never duplicated or dropped, so the lumped masses of parent + copy add
// up to the parent's mass before. Distorted meshes and an oblique plane make the sides uneven.
TEST(NodeSplit, LumpedMassIsConserved)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  Mesh tri = tri_grid(4, 3), tet = tet_box(2);
  for (Mesh* m : {&tri, &tet})
    for (int node = 0; node < m->num_nodes(); ++node)
      for (int j = 0; j < m->dim; ++j)
        m->X[3 * node + j] += jitter(rng);
  struct Case {
    Mesh* m;
    int node;
    double n[3];
  };
  const Case cases[] = {{&tri, gid(4, 2, 1), {1, 0.4, 0}},
                        {&tri, gid(4, 1, 2), {-0.3, 1, 0}},
                        {&tet, 13, {1, 0.2, -0.5}},
                        {&tet, 4, {0.1, 1, 0.3}}};
  for (const Case& c : cases) {
    NodeStars stars;
    stars.build(*c.m);
    const double before = node_mass(*c.m, c.node);
    const SplitPlan plan = plan_node_split(*c.m, stars, c.m->X.data(), c.node, c.n);
    ASSERT_TRUE(plan.splittable()) << "node " << c.node;
    const int copy = split_node(*c.m, stars, plan);
    const double a = node_mass(*c.m, c.node), b = node_mass(*c.m, copy);
    EXPECT_GT(a, 0);
    EXPECT_GT(b, 0);
    EXPECT_NEAR(a + b, before, 1e-14 * before) << "node " << c.node;
  }
}

// A fan of 8 triangles around node 0, ring nodes at 45-degree steps. In the current configuration
// the ring node at 180 degrees has been pushed to (3, 0), so the centroids of the two triangles
// beside it cross x = 0: the raw partition is b b a b b a b b (in fan order), and side a = {2, 5}
// is disconnected. Exactly one of 2 and 5 has to change side to make both sides connected.
TEST(NodeSplit, SidesAreMadeFaceConnected)
{
  Mesh m;
  m.dim = 2;
  add_node(m, 0, 0);
  const double quarter_pi = std::atan(1.0);
  for (int k = 0; k < 8; ++k)
    add_node(m, std::cos(k * quarter_pi), std::sin(k * quarter_pi));
  for (int k = 0; k < 8; ++k)
    add_elem(m, ElemType::Tri3, {0, 1 + k, 1 + (k + 1) % 8, -1});
  std::vector<double> x = m.X;
  x[3 * 5] = 3.0;
  x[3 * 5 + 1] = 0.0;
  NodeStars stars;
  stars.build(m);
  std::vector<int> raw_a, raw_b;
  for (int e = 0; e < 8; ++e) {
    const double cx = x[3 * m.conn[e][0]] + x[3 * m.conn[e][1]] + x[3 * m.conn[e][2]];
    (cx > 0 ? raw_b : raw_a).push_back(e);
  }
  ASSERT_EQ(raw_a, (std::vector<int>{2, 5}));
  ASSERT_FALSE(star_side_connected(m, raw_a)); // the case really needs the repair

  const SplitPlan plan = plan_node_split(m, stars, x.data(), 0, kX);
  ASSERT_TRUE(plan.splittable());
  EXPECT_TRUE(star_side_connected(m, plan.side_a));
  EXPECT_TRUE(star_side_connected(m, plan.side_b));
  EXPECT_EQ(plan.side_a.size(), 1u);
  EXPECT_TRUE(plan.side_a[0] == 2 || plan.side_a[0] == 5);

  // A bow-tie node: two lobes that touch only at node 0, each cut by x = 0. Side a holds one
  // triangle of each lobe and no move can join them, so no split is planned.
  Mesh bow;
  bow.dim = 2;
  add_node(bow, 0, 0);
  add_node(bow, 1, 1);
  add_node(bow, 0, 1.5);
  add_node(bow, -1, 1);
  add_node(bow, -1, -1);
  add_node(bow, 0, -1.5);
  add_node(bow, 1, -1);
  add_elem(bow, ElemType::Tri3, {0, 1, 2, -1});
  add_elem(bow, ElemType::Tri3, {0, 2, 3, -1});
  add_elem(bow, ElemType::Tri3, {0, 4, 5, -1});
  add_elem(bow, ElemType::Tri3, {0, 5, 6, -1});
  stars.build(bow);
  const SplitPlan none = plan_node_split(bow, stars, bow.X.data(), 0, kX);
  EXPECT_FALSE(none.splittable());
  EXPECT_TRUE(none.side_b.empty());
}

// A bottom-edge node cut by the boundary's own tangent plane has its whole star on one side, so
// there is nothing to split; split_node must refuse such a plan and leave the mesh untouched.
// A plan that no longer matches the star (already applied) is refused as well.
TEST(NodeSplit, NoSplitWhenStarIsOnOneSide)
{
  Mesh m = tri_grid(4, 2);
  NodeStars stars;
  stars.build(m);
  const int node = gid(4, 2, 0);
  for (double ny : {1.0, -1.0}) {
    const double n[3] = {0, ny, 0};
    const SplitPlan plan = plan_node_split(m, stars, m.X.data(), node, n);
    EXPECT_FALSE(plan.splittable());
    EXPECT_TRUE(plan.side_a.empty() || plan.side_b.empty());
    const Mesh before = m;
    EXPECT_THROW(split_node(m, stars, plan), std::invalid_argument);
    EXPECT_EQ(m.X, before.X);
    EXPECT_EQ(m.conn, before.conn);
  }
  const SplitPlan plan = plan_node_split(m, stars, m.X.data(), node, kX);
  ASSERT_TRUE(plan.splittable());
  split_node(m, stars, plan);
  EXPECT_THROW(split_node(m, stars, plan), std::invalid_argument);
}

// Sets naming the parent gain the copy (appended in sorted position); other sets are untouched.
TEST(NodeSplit, NodeSetsFollowTheCopy)
{
  Mesh m = tri_grid(4, 2);
  m.node_sets["column"] = {gid(4, 2, 0), gid(4, 2, 1), gid(4, 2, 2)};
  m.node_sets["left"] = {0, 5, 10};
  m.node_sets["mixed"] = {gid(4, 2, 1), 14};
  NodeStars stars;
  stars.build(m);
  const int c1 = split_node(m, stars, plan_node_split(m, stars, m.X.data(), gid(4, 2, 1), kX));
  const int c2 = split_node(m, stars, plan_node_split(m, stars, m.X.data(), gid(4, 2, 0), kX));
  EXPECT_EQ(m.node_sets["column"], (std::vector<int>{2, 7, 12, c1, c2}));
  EXPECT_EQ(m.node_sets["left"], (std::vector<int>{0, 5, 10}));
  EXPECT_EQ(m.node_sets["mixed"], (std::vector<int>{7, 14, c1}));
  for (const auto& s : m.node_sets)
    EXPECT_TRUE(std::is_sorted(s.second.begin(), s.second.end())) << s.first;
}

// The incremental star update must give exactly what a rebuild gives (offsets and element order),
// also with an eroded element (in no star) next to the crack, and for every element family.
TEST(NodeSplit, IncrementalStarsMatchRebuild)
{
  Mesh tri = tri_grid(4, 3), quad = quad_grid(4, 3), tet = tet_box(2);
  // Eroded elements touching the crack line, chosen so that every side stays connected.
  tri.active[2 * (4 * 0 + 2)] = 0; // lower triangle of square (2,0), right of the line
  quad.active[4 * 1 + 1] = 0;      // square (1,1), left of it
  for (Mesh* m : {&tri, &quad, &tet}) {
    NodeStars stars;
    stars.build(*m);
    EXPECT_EQ(current_star(stars, 3), brute_star(*m, 3));
    split_plane(*m, stars, 0, m->dim == 3 ? 1.0 : 2.0);
    NodeStars fresh;
    fresh.build(*m);
    EXPECT_EQ(stars.offset, fresh.offset);
    EXPECT_EQ(stars.elems, fresh.elems);
    for (int n = 0; n < m->num_nodes(); ++n)
      ASSERT_EQ(current_star(stars, n), brute_star(*m, n)) << "node " << n;
  }
}

// Same input -> identical plan, also from an independent copy of the mesh and stars.
TEST(NodeSplit, PlanIsDeterministic)
{
  Mesh m = tet_box(2);
  const double n[3] = {0.3, -1, 0.7};
  NodeStars s1, s2;
  s1.build(m);
  const Mesh copy = m;
  s2.build(copy);
  for (int node = 0; node < m.num_nodes(); ++node) {
    const SplitPlan p1 = plan_node_split(m, s1, m.X.data(), node, n);
    const SplitPlan p2 = plan_node_split(m, s1, m.X.data(), node, n);
    const SplitPlan p3 = plan_node_split(copy, s2, copy.X.data(), node, n);
    EXPECT_EQ(p1.node, p2.node);
    EXPECT_EQ(p1.side_a, p2.side_a);
    EXPECT_EQ(p1.side_b, p2.side_b);
    EXPECT_EQ(p1.side_a, p3.side_a);
    EXPECT_EQ(p1.side_b, p3.side_b);
  }
}

// Components skip eroded elements (id -1) and are numbered by their lowest element: eroding the
// column of squares i = 2 of a 4 x 2 strip leaves squares i < 2 and i = 3 without a common node.
TEST(NodeSplit, ComponentsSkipInactiveElements)
{
  Mesh m = tri_grid(4, 2);
  for (int j = 0; j < 2; ++j)
    for (int t = 0; t < 2; ++t)
      m.active[2 * (4 * j + 2) + t] = 0;
  std::vector<int> comp;
  ASSERT_EQ(element_components(m, comp), 2);
  for (int e = 0; e < m.num_elems(); ++e) {
    const int i = (e / 2) % 4;
    EXPECT_EQ(comp[e], i < 2 ? 0 : i == 3 ? 1 : -1) << "element " << e;
  }
}

// Quads around an interior node have centroids at (+-0.5, +-0.5) from it; with normal (1,1,0) the
// upper-left and lower-right ones lie exactly on the plane and must stay with the parent, so only
// the upper-right quad, square (2,1), gets the copy.
TEST(NodeSplit, CentroidOnThePlaneStaysOnSideA)
{
  Mesh m = quad_grid(4, 2);
  NodeStars stars;
  stars.build(m);
  const double n[3] = {1, 1, 0};
  const SplitPlan plan = plan_node_split(m, stars, m.X.data(), gid(4, 2, 1), n);
  EXPECT_EQ(plan.side_a, (std::vector<int>{1, 2, 5}));
  EXPECT_EQ(plan.side_b, (std::vector<int>{6}));
}
