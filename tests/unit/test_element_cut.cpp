// Unit tests of cracks through elements: conforming edge bisection (tri3, quad4, tet4), the body's
// bookkeeping of a cut (mass, momentum, force, strain, material state, restart) and the cut
// decision with its minimum-size guard.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <stdexcept>
#include <vector>

#include "fem/body.h"
#include "fem/edge_bisect.h"
#include "fracture/element_cut.h"
#include "io/mesh_generators.h"
#include "test_support.h"

using namespace fracdem;

namespace
{

double measure(const Mesh& m, int e)
{
  return m.etype[e] == ElemType::Tet4 ? fracdem_test::tet_volume(m, e)
                                      : fracdem_test::signed_area(m, e);
}

double total_measure(const Mesh& m)
{
  double s = 0;
  for (int e = 0; e < m.num_elems(); ++e)
    if (m.active[e]) s += measure(m, e);
  return s;
}

// Conformity: no facet (edge in 2D, triangle in 3D) is shared by more than two active elements.
// Returns the number of boundary facets (held by one element).
int check_conforming(const Mesh& m)
{
  std::map<std::array<int, 3>, int> count;
  for (int e = 0; e < m.num_elems(); ++e) {
    if (!m.active[e]) continue;
    std::array<int, 3> keys[4];
    const int k = element_facet_keys(m, e, keys);
    for (int f = 0; f < k; ++f)
      ++count[keys[f]];
  }
  int boundary = 0;
  for (const auto& kv : count) {
    EXPECT_LE(kv.second, 2) << "facet shared by more than two elements";
    boundary += kv.second == 1;
  }
  return boundary;
}

double boundary_measure(const Mesh& m)
{
  double s = 0;
  for (const Facet& f : boundary_facets(m))
    s += facet_measure(m.X.data(), f);
  return s;
}

// The node with the largest star and the other node of its first element (an interior edge).
std::pair<int, int> interior_edge(const Mesh& m, const NodeStars& stars)
{
  int u = 0;
  for (int n = 0; n < stars.num_nodes(); ++n)
    if (stars.end(n) - stars.begin(n) > stars.end(u) - stars.begin(u)) u = n;
  const int e = *stars.begin(u);
  for (int a = 0; a < nodes_per_elem(m.etype[e]); ++a)
    if (m.conn[e][a] != u) return {u, m.conn[e][a]};
  return {u, -1};
}

void expect_bisection(Mesh m, int u, int w, double t)
{
  NodeStars stars;
  stars.build(m);
  const int ne = m.num_elems(), nn = m.num_nodes();
  const double total = total_measure(m), bmeasure = boundary_measure(m);
  const int boundary = check_conforming(m);
  const std::vector<int> around = elements_on_edge(stars, u, w);
  std::vector<double> before;
  for (int e : around)
    before.push_back(measure(m, e));
  std::vector<int> parents;
  const int p = bisect_edge(m, stars, u, w, t, parents);
  EXPECT_EQ(p, nn);
  EXPECT_EQ(parents, around);
  ASSERT_EQ(m.num_elems(), ne + static_cast<int>(around.size()));
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(m.X[3 * p + d], m.X[3 * u + d] + t * (m.X[3 * w + d] - m.X[3 * u + d]), 1e-15);
  for (size_t i = 0; i < around.size(); ++i) { // children: t and 1 - t of the parent, same sign
    EXPECT_NEAR(measure(m, around[i]), t * before[i], 1e-13 * before[i]);
    EXPECT_NEAR(measure(m, ne + static_cast<int>(i)), (1 - t) * before[i], 1e-13 * before[i]);
    EXPECT_EQ(m.etype[ne + static_cast<int>(i)], m.etype[around[i]]);
  }
  EXPECT_NEAR(total_measure(m), total, 1e-13 * total);
  EXPECT_NEAR(boundary_measure(m), bmeasure, 1e-13 * bmeasure);
  // An interior edge leaves the boundary as it was; a boundary edge's facets split in two.
  const int after = check_conforming(m);
  EXPECT_TRUE(after == boundary || after == boundary + (m.dim == 2 ? 1 : 2))
      << boundary << " -> " << after;
  NodeStars rebuilt;
  rebuilt.build(m);
  EXPECT_TRUE(elements_on_edge(rebuilt, u, w).empty()); // the edge is gone
}

Material weak_rankine()
{
  Material m = fracdem_test::steel();
  m.model = MaterialModel::Rankine;
  m.ft = 1e6; // far below the shaken body's stresses: every point has cracked state to copy
  m.gf = 100;
  return m;
}

// A Rankine body, deformed by a random velocity field over a long drift, forces evaluated.
Body deformed_body(ElemType type)
{
  Body b;
  Mesh m = type == ElemType::Tet4 ? make_box_tet_mesh(3, 2, 2, 0.3, 0.2, 0.2)
                                  : make_rect_mesh(4, 3, 0.4, 0.3, {0, 0}, type);
  b.build(std::move(m), weak_rankine(), false);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> r(-1, 1);
  for (int n = 0; n < b.num_nodes(); ++n) {
    const double v[3] = {r(rng), r(rng), type == ElemType::Tet4 ? r(rng) : 0.0};
    b.set_velocity({n}, v);
  }
  // Two long steps: displacements ~5e-5 over 0.1 m elements (strains ~1e-3), and a second
  // evaluation, at which the cracking points dissipate.
  const double g[3] = {0, 0, 0};
  for (int k = 0; k < 2; ++k) {
    b.half_kick_drift(2.5e-5);
    b.begin_forces();
    int inv = -1;
    b.finish_forces(b.add_internal_forces(&inv), g, 2.5e-5, true);
    EXPECT_LT(inv, 0);
  }
  return b;
}

struct Sums {
  double m = 0, p[3] = {0, 0, 0}, f[3] = {0, 0, 0}, ke = 0, strain = 0;
};
Sums sums(const Body& b)
{
  Sums s;
  for (int n = 0; n < b.num_nodes(); ++n) {
    const double m = b.masses()[n];
    s.m += m;
    for (int d = 0; d < 3; ++d) {
      const double v = b.velocities()[3 * n + d];
      s.p[d] += m * v;
      s.f[d] += b.forces()[3 * n + d];
      s.ke += 0.5 * m * v * v;
    }
  }
  std::vector<double> energy;
  b.element_energies(energy);
  for (double en : energy)
    s.strain += en;
  return s;
}

double max_abs(const std::vector<double>& v)
{
  double m = 0;
  for (double x : v)
    m = std::max(m, std::fabs(x));
  return m;
}

} // namespace

TEST(EdgeBisect, Tri3InteriorAndBoundaryEdges)
{
  const Mesh m = make_rect_mesh(3, 3, 3.0, 3.0, {0, 0}, ElemType::Tri3);
  expect_bisection(m, 5, 10, 0.3); // the diagonal of square (1, 1): two triangles
  expect_bisection(m, 0, 1, 0.6);  // a boundary edge: one triangle
}

TEST(EdgeBisect, Tet4EdgeSplitsEveryTetAroundIt)
{
  const Mesh m = make_box_tet_mesh(2, 2, 2, 2.0, 2.0, 2.0);
  NodeStars stars;
  stars.build(m);
  const auto [u, w] = interior_edge(m, stars);
  EXPECT_GE(elements_on_edge(stars, u, w).size(), 3u); // a ring of tets
  expect_bisection(m, u, w, 0.4);
  expect_bisection(m, 0, 1, 0.25); // a boundary edge
}

TEST(EdgeBisect, QuadDiagonalsAndMissingJoinsAreRefused)
{
  Mesh m = make_rect_mesh(2, 2, 2.0, 2.0, {0, 0}, ElemType::Quad4);
  NodeStars stars;
  stars.build(m);
  EXPECT_TRUE(edge_bisectable(m, stars, 0, 1));
  EXPECT_FALSE(edge_bisectable(m, stars, 0, 4)); // a diagonal of quad 0, not an edge
  std::vector<int> parents;
  EXPECT_THROW(bisect_edge(m, stars, 0, 1, 0.5, parents), std::invalid_argument); // no join
  EXPECT_THROW(bisect_edge(m, stars, 0, 1, 0.5, parents, {{0, 1}}), std::invalid_argument);
  EXPECT_EQ(m.num_nodes(), 9); // nothing changed
  Mesh t = make_rect_mesh(2, 2, 2.0, 2.0, {0, 0}, ElemType::Tri3);
  stars.build(t);
  EXPECT_FALSE(edge_bisectable(t, stars, 0, 8)); // no element holds both
  EXPECT_THROW(bisect_edge(t, stars, 0, 1, 1.0, parents), std::invalid_argument);
}

namespace
{
// Whether quad e of m is strictly convex (every corner turns left).
bool convex_quad(const Mesh& m, int e)
{
  const auto& c = m.conn[e];
  for (int k = 0; k < 4; ++k) {
    const double* a = &m.X[3 * c[k]];
    const double* b = &m.X[3 * c[(k + 1) % 4]];
    const double* d = &m.X[3 * c[(k + 2) % 4]];
    if (!((b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]) > 0)) return false;
  }
  return true;
}
} // namespace

// An interior edge between two unit squares: each splits into a tri3 (new element) and a convex
// quad4 (its slot), areas as the joins give them, conforming, boundary unchanged.
TEST(EdgeBisect, Quad4SplitsIntoATriAndAConvexQuadOnBothSides)
{
  Mesh m = make_rect_mesh(2, 2, 2.0, 2.0, {0, 0}, ElemType::Quad4);
  NodeStars stars;
  stars.build(m);
  const double total = total_measure(m), bmeasure = boundary_measure(m);
  const int boundary = check_conforming(m);
  const double t = 0.3; // P = (1, 0.3) on edge 1-4
  // quad 0 (0, 1, 4, 3): P joined to 0 leaves tri (1, P, 0) of area t / 2; quad 1 (1, 2, 5, 4):
  // P joined to 5 leaves tri (4, P, 5) of area (1 - t) / 2.
  EXPECT_NEAR(quad_split_shape(m, 0, 1, 4, t, 0).tri_fraction, t / 2, 1e-15);
  EXPECT_NEAR(quad_split_shape(m, 1, 1, 4, t, 5).tri_fraction, (1 - t) / 2, 1e-15);
  EXPECT_TRUE(quad_split_shape(m, 1, 1, 4, t, 5).convex);
  EXPECT_LT(quad_split_shape(m, 1, 1, 4, t, 0).tri_fraction, 0); // 0 is not a node of quad 1
  std::vector<int> parents;
  const int p = bisect_edge(m, stars, 1, 4, t, parents, {{0, 0}, {1, 5}});
  EXPECT_EQ(p, 9);
  EXPECT_EQ(parents, (std::vector<int>{0, 1}));
  ASSERT_EQ(m.num_elems(), 6);
  EXPECT_EQ(m.etype[0], ElemType::Quad4);
  EXPECT_EQ(m.etype[1], ElemType::Quad4);
  EXPECT_EQ(m.etype[4], ElemType::Tri3);
  EXPECT_EQ(m.etype[5], ElemType::Tri3);
  EXPECT_NEAR(measure(m, 4), t / 2, 1e-15);
  EXPECT_NEAR(measure(m, 0), 1 - t / 2, 1e-15);
  EXPECT_NEAR(measure(m, 5), (1 - t) / 2, 1e-15);
  EXPECT_NEAR(measure(m, 1), 1 - (1 - t) / 2, 1e-15);
  EXPECT_TRUE(convex_quad(m, 0));
  EXPECT_TRUE(convex_quad(m, 1));
  EXPECT_NEAR(total_measure(m), total, 1e-14 * total);
  EXPECT_NEAR(boundary_measure(m), bmeasure, 1e-14 * bmeasure);
  EXPECT_EQ(check_conforming(m), boundary); // an interior edge: the boundary as it was
  // The new edges: P-0 and P-5 are shared by a tri and a quad each, 1-P and P-4 by the pieces.
  stars.build(m);
  EXPECT_TRUE(elements_on_edge(stars, 1, 4).empty());
  EXPECT_EQ(elements_on_edge(stars, p, 0).size(), 2u);
  EXPECT_EQ(elements_on_edge(stars, p, 5).size(), 2u);
  // A tri3 neighbour splits in two tri3 as before (mixed mesh: quads beside tris).
  Mesh mixed = make_rect_mesh(2, 1, 2.0, 1.0, {0, 0}, ElemType::Quad4);
  mixed.conn[1] = {1, 2, 5, -1};
  mixed.etype[1] = ElemType::Tri3;
  mixed.conn.push_back({1, 5, 4, -1});
  mixed.etype.push_back(ElemType::Tri3);
  mixed.active.push_back(1);
  mixed.region.push_back(0);
  stars.build(mixed);
  const double mixed_total = total_measure(mixed);
  bisect_edge(mixed, stars, 1, 4, 0.5, parents, {{0, 3}});
  EXPECT_EQ(parents, (std::vector<int>{0, 2}));
  EXPECT_EQ(mixed.etype[3], ElemType::Tri3);
  EXPECT_EQ(mixed.etype[4], ElemType::Tri3);
  EXPECT_NEAR(measure(mixed, 2), 0.25, 1e-15); // the tri (1, 5, P)
  EXPECT_NEAR(measure(mixed, 4), 0.25, 1e-15);
  EXPECT_NEAR(total_measure(mixed), mixed_total, 1e-14);
  check_conforming(mixed);
}

class BodyCut : public ::testing::TestWithParam<ElemType>
{
};

TEST_P(BodyCut, ConservesMassMomentumForceStrainAndState)
{
  Body b = deformed_body(GetParam());
  const auto [u, w] = interior_edge(b.mesh(), b.stars());
  const std::vector<int> around = elements_on_edge(b.stars(), u, w);
  const double t = 0.35;
  const Sums s0 = sums(b);
  const double dissipated = b.dissipated_energy();
  ASSERT_GT(dissipated, 0.0); // the Rankine points cracked: there is material state to copy
  std::vector<std::vector<double>> stress0, state0;
  std::vector<double> measure0;
  const int per = kRankineStateSize * 1; // one point per tri3 / tet4
  for (int e : around) {
    std::vector<double> sig(6);
    b.element_stress(e, sig.data());
    stress0.push_back(sig);
    const double* st = &b.material_state()[b.space().state_offset(e)];
    state0.emplace_back(st, st + per);
    measure0.push_back(b.space().reference_measure(e));
  }
  const double vu[3] = {b.velocities()[3 * u], b.velocities()[3 * u + 1],
                        b.velocities()[3 * u + 2]};
  const double vw[3] = {b.velocities()[3 * w], b.velocities()[3 * w + 1],
                        b.velocities()[3 * w + 2]};
  const int ne = b.mesh().num_elems();
  std::vector<int> added;
  const int p = b.bisect_edge(u, w, t, &added);
  ASSERT_EQ(added.size(), around.size());
  const Sums s1 = sums(b);
  EXPECT_NEAR(s1.m, s0.m, 1e-14 * s0.m);
  const double pscale = s0.m * max_abs(b.velocities());
  for (int d = 0; d < 3; ++d) {
    EXPECT_NEAR(s1.p[d], s0.p[d], 1e-14 * pscale);
    EXPECT_NEAR(s1.f[d], s0.f[d], 1e-12 * max_abs(b.forces()));
  }
  EXPECT_LE(s1.ke, s0.ke * (1 + 1e-14)); // P moves at the mean of what it took: KE never grows
  EXPECT_NEAR(s1.strain, s0.strain, 1e-10 * s0.strain);
  EXPECT_NEAR(b.dissipated_energy(), dissipated, 1e-12 * dissipated);
  // Equal lumped shares (plane tri3, tet4): P moves at the interpolated velocity exactly.
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(b.velocities()[3 * p + d], (1 - t) * vu[d] + t * vw[d], 1e-13);
  for (size_t i = 0; i < around.size(); ++i) {
    const int e = around[i], c = ne + static_cast<int>(i);
    EXPECT_EQ(added[i], c);
    EXPECT_EQ(b.element_parent(c), e);
    EXPECT_NEAR(b.space().reference_measure(e), t * measure0[i], 1e-13 * measure0[i]);
    EXPECT_NEAR(b.space().reference_measure(c), (1 - t) * measure0[i], 1e-13 * measure0[i]);
    EXPECT_NEAR(b.piece_fraction(e), t, 1e-13); // of the mesh element
    EXPECT_NEAR(b.piece_fraction(c), 1 - t, 1e-13);
    const double* sc = &b.material_state()[b.space().state_offset(c)];
    EXPECT_EQ(std::vector<double>(sc, sc + per), state0[i]); // the parent's state, bit for bit
    const double scale = max_abs(stress0[i]);
    for (int child : {e, c}) { // the parent's strain, hence its stress
      double sig[6];
      b.element_stress(child, sig);
      for (int k = 0; k < 6; ++k)
        EXPECT_NEAR(sig[k], stress0[i][k], 1e-8 * scale) << "element " << child;
    }
  }
  EXPECT_EQ(b.mesh_elements(), ne);
  EXPECT_EQ(b.cut_nodes(), (std::vector<int>{p, u, w}));
  // The stars hold the grown mesh.
  NodeStars fresh;
  fresh.build(b.mesh());
  EXPECT_EQ(fresh.elems, b.stars().elems);
  EXPECT_EQ(fresh.offset, b.stars().offset);
}

INSTANTIATE_TEST_SUITE_P(Elements, BodyCut, ::testing::Values(ElemType::Tri3, ElemType::Tet4));

namespace
{
// A Rankine quad4 body (4 x 3 squares of 0.1 m) after two steps of a velocity field: affine
// (a homogeneous strain: every point in the same state) or random.
Body quad_body(bool affine, const Material& mat = weak_rankine())
{
  Body b;
  b.build(make_rect_mesh(4, 3, 0.4, 0.3, {0, 0}, ElemType::Quad4), mat, false);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> r(-1, 1);
  for (int n = 0; n < b.num_nodes(); ++n) {
    const double x = b.mesh().X[3 * n], y = b.mesh().X[3 * n + 1];
    const double v[3] = {affine ? 8 * x + 3 * y + 1 : r(rng), affine ? -2 * x + 5 * y - 2 : r(rng),
                         0.0};
    b.set_velocity({n}, v);
  }
  const double g[3] = {0, 0, 0};
  for (int k = 0; k < 2; ++k) {
    if (affine && k == 1) { // no kick from the first forces: the second drift stays affine
      b.begin_forces();
      for (int n = 0; n < b.num_nodes(); ++n) {
        const double x = b.mesh().X[3 * n], y = b.mesh().X[3 * n + 1];
        const double v[3] = {8 * x + 3 * y + 1, -2 * x + 5 * y - 2, 0.0};
        b.set_velocity({n}, v);
      }
    }
    b.half_kick_drift(2.5e-5);
    b.begin_forces();
    int inv = -1;
    b.finish_forces(b.add_internal_forces(&inv), g, 2.5e-5, true);
    EXPECT_LT(inv, 0);
  }
  return b;
}

// The quad4 formulations a cut must serve: plane strain, plane stress, axisymmetric (r-weighted
// lumped masses, hoop strain), corotational.
enum class QuadVariant { PlaneStrain, PlaneStress, Axisymmetric, Corotational };
Material quad_material(QuadVariant v)
{
  Material m = weak_rankine();
  if (v == QuadVariant::PlaneStress) m.plane = PlaneMode::PlaneStress;
  if (v == QuadVariant::Axisymmetric) m.plane = PlaneMode::Axisymmetric;
  if (v == QuadVariant::Corotational) m.kinematics = Kinematics::Corotational;
  return m;
}
} // namespace

class QuadCut : public ::testing::TestWithParam<QuadVariant>
{
};

// A quad4 cut (edge 7-12 between quads 5 and 6 at t = 0.35, joins to 6 and 8): mass, momentum
// and force sums unchanged to round-off and no kinetic energy made (random field); under a
// homogeneous strain the strain and dissipated energies unchanged and every piece in the
// parent's stress and state (affine field; not axisymmetric, whose hoop strain u_r / r is not
// uniform under it).
TEST_P(QuadCut, ConservesMassMomentumForceStrainAndState)
{
  const double t = 0.35;
  const std::vector<QuadJoin> joins{{5, 6}, {6, 8}};
  const QuadVariant variant = GetParam();
  for (bool affine : {false, true}) {
    if (affine && variant == QuadVariant::Axisymmetric) continue;
    SCOPED_TRACE(affine ? "affine" : "random");
    Body b = quad_body(affine, quad_material(variant));
    ASSERT_EQ(elements_on_edge(b.stars(), 7, 12), (std::vector<int>{5, 6}));
    std::vector<double>
        areas0; // plain areas: the reference measure is r-weighted when axisymmetric
    for (int e : {5, 6})
      areas0.push_back(measure(b.mesh(), e));
    const Sums s0 = sums(b);
    const double dissipated = b.dissipated_energy();
    ASSERT_GT(dissipated, 0.0);
    std::vector<std::vector<double>> stress0;
    for (int e : {5, 6}) {
      std::vector<double> sig(6);
      b.element_stress(e, sig.data());
      stress0.push_back(sig);
    }
    const std::vector<double> parent_state(b.material_state().begin() + b.space().state_offset(5),
                                           b.material_state().begin() + b.space().state_offset(6));
    const double area = b.space().reference_measure(5);
    std::vector<int> added;
    const int p = b.bisect_edge(7, 12, t, &added, joins);
    ASSERT_EQ(added, (std::vector<int>{12, 13}));
    EXPECT_EQ(b.mesh().etype[12], ElemType::Tri3);
    EXPECT_EQ(b.mesh().etype[5], ElemType::Quad4);
    const Sums s1 = sums(b);
    EXPECT_NEAR(s1.m, s0.m, 1e-14 * s0.m);
    const double pscale = s0.m * max_abs(b.velocities());
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(s1.p[d], s0.p[d], 1e-14 * pscale);
      EXPECT_NEAR(s1.f[d], s0.f[d], 1e-12 * max_abs(b.forces()));
    }
    EXPECT_LE(s1.ke, s0.ke * (1 + 1e-14));
    EXPECT_GT(b.masses()[p], 0.0);
    // quad 5 (6, 7, 12, 11), P joined to 6: tri (7, P, 6) of t / 2 of it, quad (P, 12, 11, 6);
    // quad 6 (7, 8, 13, 12), P joined to 8: tri (P, 7, 8), t / 2, quad (12, P, 8, 13).
    EXPECT_NEAR(measure(b.mesh(), 12), t / 2 * areas0[0], 1e-13 * areas0[0]);
    EXPECT_NEAR(measure(b.mesh(), 5), (1 - t / 2) * areas0[0], 1e-13 * areas0[0]);
    EXPECT_NEAR(measure(b.mesh(), 13), t / 2 * areas0[1], 1e-13 * areas0[1]);
    EXPECT_NEAR(b.space().reference_measure(5) + b.space().reference_measure(12), area,
                1e-13 * area);
    if (variant != QuadVariant::Axisymmetric) {
      EXPECT_NEAR(b.piece_fraction(12), t / 2, 1e-13);
      EXPECT_NEAR(b.piece_fraction(13), t / 2, 1e-13);
    }
    EXPECT_EQ(b.mesh().conn[5], (std::array<int, 4>{p, 12, 11, 6}));
    EXPECT_EQ(b.mesh().conn[6], (std::array<int, 4>{12, p, 8, 13}));
    if (!affine) continue;
    EXPECT_NEAR(s1.strain, s0.strain, 1e-10 * s0.strain);
    EXPECT_NEAR(b.dissipated_energy(), dissipated, 1e-12 * dissipated);
    // Uniform state (to round-off): every piece's points hold the parent's first point's state.
    const int per = kRankineStateSize;
    for (int e : {5, 6, 12, 13})
      for (int q = 0; q < points_per_elem(b.mesh().etype[e]); ++q) {
        const double* st = &b.material_state()[b.space().state_offset(e) + per * q];
        for (int k = 0; k < per; ++k)
          EXPECT_NEAR(st[k], parent_state[k], 1e-10 * (1 + std::fabs(parent_state[k])));
      }
    for (int e : {5, 6, 12, 13}) {
      double sig[6];
      b.element_stress(e, sig);
      const std::vector<double>& ref = stress0[e == 6 || e == 13 ? 1 : 0];
      for (int k = 0; k < 6; ++k)
        EXPECT_NEAR(sig[k], ref[k], 1e-8 * max_abs(ref)) << "element " << e;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Formulations, QuadCut,
                         ::testing::Values(QuadVariant::PlaneStrain, QuadVariant::PlaneStress,
                                           QuadVariant::Axisymmetric, QuadVariant::Corotational));

TEST(BodyCut, Quad4RestartRecordCarriesTheMixedMeshExactly)
{
  Body a = quad_body(false);
  a.bisect_edge(7, 12, 0.4, nullptr, {{5, 6}, {6, 8}});
  a.bisect_edge(0, 1, 0.3, nullptr, {{0, 6}}); // a boundary edge of quad 0 (0, 1, 6, 5)
  std::vector<double> buf;
  a.pack_state(buf);
  Body b;
  b.build(make_rect_mesh(4, 3, 0.4, 0.3, {0, 0}, ElemType::Quad4), weak_rankine(), false);
  b.unpack_state(buf.data());
  EXPECT_EQ(b.mesh().conn, a.mesh().conn);
  EXPECT_EQ(b.mesh().etype, a.mesh().etype);
  EXPECT_EQ(b.masses(), a.masses());
  EXPECT_EQ(b.material_state(), a.material_state());
  for (int e = 0; e < a.mesh().num_elems(); ++e)
    EXPECT_EQ(b.space().reference_measure(e), a.space().reference_measure(e));
  const double g[3] = {0, 0, 0};
  for (Body* x : {&a, &b})
    for (int k = 0; k < 2; ++k) {
      if (k == 1) x->half_kick_drift(1e-6);
      x->begin_forces();
      int inv = -1;
      x->finish_forces(x->add_internal_forces(&inv), g, 1e-6, true);
    }
  EXPECT_EQ(a.forces(), b.forces());
}

TEST(BodyCut, HeldEdgeGivesItsHoldToTheNewNodeOnlyWhenBothEndsHoldIt)
{
  Body b;
  b.build(make_rect_mesh(2, 2, 0.2, 0.2, {0, 0}, ElemType::Tri3), fracdem_test::steel(), false);
  b.set_fixed({0, 1}, 2, 0); // y held at the first two bottom nodes
  b.set_fixed({2}, 1, 1);    // x held at the third
  const int p01 = b.bisect_edge(0, 1, 0.5);
  const int p12 = b.bisect_edge(1, 2, 0.5);
  EXPECT_EQ(b.conditions()[p01], NodeBc::Partial);
  EXPECT_EQ(b.conditions()[p12], NodeBc::Free); // its ends hold different components
}

TEST(BodyCut, RestartRecordCarriesTheGrownMeshExactly)
{
  Body a = deformed_body(ElemType::Tri3);
  const auto [u, w] = interior_edge(a.mesh(), a.stars());
  a.bisect_edge(u, w, 0.4);
  a.bisect_edge(0, 1, 0.3); // a boundary edge too
  std::vector<double> buf;
  a.pack_state(buf);
  EXPECT_EQ(buf[0], 5.0);
  Body b;
  b.build(make_rect_mesh(4, 3, 0.4, 0.3, {0, 0}, ElemType::Tri3), weak_rankine(), false);
  b.unpack_state(buf.data());
  EXPECT_EQ(b.mesh().conn, a.mesh().conn);
  EXPECT_EQ(b.mesh().etype, a.mesh().etype);
  EXPECT_EQ(b.mesh().X, a.mesh().X);
  EXPECT_EQ(b.positions(), a.positions());
  EXPECT_EQ(b.masses(), a.masses());
  EXPECT_EQ(b.material_state(), a.material_state());
  EXPECT_EQ(b.cut_nodes(), a.cut_nodes());
  for (int e = 0; e < a.mesh().num_elems(); ++e) {
    EXPECT_EQ(b.element_parent(e), a.element_parent(e));
    EXPECT_EQ(b.space().reference_measure(e), a.space().reference_measure(e));
    EXPECT_EQ(b.piece_fraction(e), a.piece_fraction(e)); // the same cut decisions follow
  }
  // Both continue alike (forces taken first, as a run's set-up does): one more step gives the
  // same forces, bit for bit.
  const double g[3] = {0, 0, 0};
  for (Body* x : {&a, &b})
    for (int k = 0; k < 2; ++k) {
      if (k == 1) x->half_kick_drift(1e-6);
      x->begin_forces();
      int inv = -1;
      x->finish_forces(x->add_internal_forces(&inv), g, 1e-6, true);
    }
  EXPECT_EQ(a.forces(), b.forces());
  EXPECT_EQ(a.material_state(), b.material_state());
}

/* ---------------- the cut decision ---------------- */

namespace
{
// Unit normal of a line through the origin at angle theta (degrees) from x.
std::array<double, 3> line_normal(double theta)
{
  const double r = theta * M_PI / 180;
  return {std::sin(r), -std::cos(r), 0};
}
} // namespace

TEST(ElementCut, Tri3CutOnlyWhereTheLineBeatsTheEdgesAndBothPiecesAreLargeEnough)
{
  // 2 x 2 unit squares with (i,j)-(i+1,j+1) diagonals; the centre node 4 has edges at 0, 45,
  // 90, 180, 225 and 270 degrees.
  const Mesh m = make_rect_mesh(2, 2, 2.0, 2.0, {0, 0}, ElemType::Tri3);
  NodeStars stars;
  stars.build(m);
  const double* x = m.X.data();
  // A line along existing edges (vertical) is never cut: the boundary is in the plane.
  EXPECT_FALSE(find_element_cut(m, stars, x, 4, line_normal(90).data(), 0.1).found());
  EXPECT_FALSE(find_element_cut(m, stars, x, 4, line_normal(45).data(), 0.1).found());
  // At 67.5 degrees the line leaves the centre between the 45 and 90 degree edges (22.5 degrees
  // off each) and meets the opposite edge cot(67.5) = 0.414 of its length from one end.
  const auto n = line_normal(67.5);
  const ElementCut cut = find_element_cut(m, stars, x, 4, n.data(), 0.4);
  ASSERT_TRUE(cut.found());
  EXPECT_DOUBLE_EQ(cut.alignment, 1.0);
  EXPECT_NEAR(cut.boundary, std::cos(22.5 * M_PI / 180), 1e-12);
  EXPECT_NEAR(std::min(cut.t, 1 - cut.t), 1 / std::tan(67.5 * M_PI / 180), 1e-12);
  // A piece below min_size: no cut (the crack keeps to the boundary).
  EXPECT_FALSE(find_element_cut(m, stars, x, 4, n.data(), 0.45).found());
  // At 85 degrees the pieces would be 0.087 and 0.913 of the element.
  EXPECT_FALSE(find_element_cut(m, stars, x, 4, line_normal(85).data(), 0.1).found());
  const ElementCut thin = find_element_cut(m, stars, x, 4, line_normal(85).data(), 0.05);
  ASSERT_TRUE(thin.found());
  EXPECT_NEAR(std::min(thin.t, 1 - thin.t), 1 / std::tan(85 * M_PI / 180), 1e-12);
  // No min_size, no cut.
  EXPECT_FALSE(find_element_cut(m, stars, x, 4, n.data(), 0.0).found());
  // The guard holds against the mesh element: halves of earlier cuts (fraction 0.5) would give
  // pieces of 0.207 of their mesh element.
  EXPECT_TRUE(find_element_cut(m, stars, x, 4, n.data(), 0.3).found());
  EXPECT_FALSE(find_element_cut(m, stars, x, 4, n.data(), 0.3, [](int) { return 0.5; }).found());
}

TEST(ElementCut, Tri3CutThenSplitPutsTheCrackOnTheLine)
{
  Mesh m = make_rect_mesh(2, 2, 2.0, 2.0, {0, 0}, ElemType::Tri3);
  NodeStars stars;
  stars.build(m);
  const auto n = line_normal(67.5);
  int cuts = 0;
  for (ElementCut c; (c = find_element_cut(m, stars, m.X.data(), 4, n.data(), 0.3)).found();) {
    std::vector<int> parents;
    bisect_edge(m, stars, c.u, c.w, c.t, parents);
    stars.build(m);
    ASSERT_LE(++cuts, 2); // one per half of the line
  }
  EXPECT_EQ(cuts, 2);
  // Both new nodes lie on the line through the centre.
  for (int p = 9; p < 11; ++p)
    EXPECT_NEAR((m.X[3 * p] - 1) * n[0] + (m.X[3 * p + 1] - 1) * n[1], 0.0, 1e-14);
  // The split along the plane now has every star element strictly on one side.
  const SplitPlan plan = plan_node_split(m, stars, m.X.data(), 4, n.data());
  ASSERT_TRUE(plan.splittable());
  EXPECT_EQ(plan.side_a.size() + plan.side_b.size(), 8u);
}

TEST(ElementCut, Quad4CutJoinsTheCrackPointAndChoosesTheNeighboursJoin)
{
  // 3 x 3 unit squares; node 4 = (0, 1) on the left side. The line through it at 30 degrees
  // leaves quad 3 (4, 5, 9, 8) through its edge 5-9 at P = (1, 1.577) (t = tan 30 from 5):
  // beside the edges 4-5 (30 degrees off, |cos| of the normals 0.866) and 4-8 (60 degrees).
  Mesh m = make_rect_mesh(3, 3, 3.0, 3.0, {0, 0}, ElemType::Quad4);
  NodeStars stars;
  stars.build(m);
  const auto n = line_normal(30);
  EXPECT_FALSE(find_element_cut(m, stars, m.X.data(), 4, line_normal(0).data(), 0.1).found());
  const ElementCut cut = find_element_cut(m, stars, m.X.data(), 4, n.data(), 0.25);
  ASSERT_TRUE(cut.found());
  EXPECT_EQ(cut.elem, 3);
  EXPECT_EQ(std::min(cut.u, cut.w), 5);
  EXPECT_EQ(std::max(cut.u, cut.w), 9);
  const double tan30 = std::tan(M_PI / 6);
  EXPECT_NEAR(cut.u == 5 ? cut.t : 1 - cut.t, tan30, 1e-12);
  EXPECT_NEAR(cut.boundary, std::cos(M_PI / 6), 1e-12);
  // The cut's quad joins P to the crack point (tri (5, P, 4), tan30 / 2 = 0.289 of it); its
  // neighbour quad 4 (5, 6, 10, 9) joins P to 6 (tri (P, 5, 6), 0.289) rather than to 10
  // (tri (9, P, 10), 0.211: below min_size 0.25).
  ASSERT_EQ(cut.joins.size(), 2u);
  EXPECT_EQ(cut.joins[0].elem, 3);
  EXPECT_EQ(cut.joins[0].node, 4);
  EXPECT_EQ(cut.joins[1].elem, 4);
  EXPECT_EQ(cut.joins[1].node, 6);
  // With min_size 0.2 both joins of quad 4 are valid: P-10 (7 degrees off the line, against
  // P-6 at 60) is taken, so that the crack can go on along it.
  const ElementCut aligned = find_element_cut(m, stars, m.X.data(), 4, n.data(), 0.2);
  ASSERT_EQ(aligned.joins.size(), 2u);
  EXPECT_EQ(aligned.joins[1].node, 10);
  // Both pieces of the cut's quad must stay above min_size: 0.289 < 0.3, no cut.
  EXPECT_FALSE(find_element_cut(m, stars, m.X.data(), 4, n.data(), 0.3).found());
  // Against the mesh element: halves of earlier pieces would fall below.
  EXPECT_FALSE(
      find_element_cut(m, stars, m.X.data(), 4, n.data(), 0.2, [](int) { return 0.5; }).found());
  std::vector<int> parents;
  const int p = bisect_edge(m, stars, cut.u, cut.w, cut.t, parents, cut.joins);
  EXPECT_NEAR(m.X[3 * p + 1], 1 + tan30, 1e-14);
  for (int e : {3, 4})
    EXPECT_TRUE(convex_quad(m, e));
  EXPECT_NEAR(measure(m, 9), tan30 / 2, 1e-14); // tri (5, P, 4)
  EXPECT_NEAR(measure(m, 10), tan30 / 2, 1e-14);
  stars.build(m);
  // The crack point's star now has the edge 4-P on the line: every element on one side.
  EXPECT_EQ(elements_on_edge(stars, 4, p).size(), 2u);
  const SplitPlan plan = plan_node_split(m, stars, m.X.data(), 4, n.data());
  ASSERT_TRUE(plan.splittable());
  EXPECT_EQ(plan.side_a.size() + plan.side_b.size(), 3u);
  // Another cut from 4 along the same line finds nothing better aligned than 4-P.
  EXPECT_FALSE(find_element_cut(m, stars, m.X.data(), 4, n.data(), 0.1).found());
}

// Through the centre of 2 x 2 squares at 67.5 degrees the line leaves quad 0 through its bottom
// edge at 1 - tan 22.5 = 0.586: tri (P, 1, 4) of 0.207 of it, a boundary edge (no neighbour).
TEST(ElementCut, Quad4CutAtTheBoundaryKeepsTheMinimumSize)
{
  const Mesh m = make_rect_mesh(2, 2, 2.0, 2.0, {0, 0}, ElemType::Quad4);
  NodeStars stars;
  stars.build(m);
  const auto n = line_normal(67.5);
  const ElementCut cut = find_element_cut(m, stars, m.X.data(), 4, n.data(), 0.2);
  ASSERT_TRUE(cut.found());
  EXPECT_EQ(cut.elem, 0); // the lowest of two equally aligned cuts
  ASSERT_EQ(cut.joins.size(), 1u);
  const QuadSplitShape shape = quad_split_shape(m, 0, cut.u, cut.w, cut.t, 4);
  EXPECT_NEAR(shape.tri_fraction, std::tan(M_PI / 8) / 2, 1e-12);
  EXPECT_TRUE(shape.convex);
  EXPECT_FALSE(find_element_cut(m, stars, m.X.data(), 4, n.data(), 0.21).found());
}

TEST(ElementCut, Tet4CutsWhereTheBestFaceIsWorseAligned)
{
  const Mesh m = make_box_tet_mesh(2, 2, 2, 2.0, 2.0, 2.0);
  NodeStars stars;
  stars.build(m);
  int centre = -1;
  for (int n = 0; n < m.num_nodes(); ++n)
    if (m.X[3 * n] == 1 && m.X[3 * n + 1] == 1 && m.X[3 * n + 2] == 1) centre = n;
  ASSERT_GE(centre, 0);
  // The plane z = 1 holds faces of the centre's tets: no cut.
  const double flat[3] = {0, 0, 1};
  EXPECT_FALSE(find_element_cut(m, stars, m.X.data(), centre, flat, 0.1).found());
  // Tilted by 16.7 degrees about y: the best face is 16.7 degrees off; a cut through an edge
  // along y lies in the plane.
  const double l = std::sqrt(1.09);
  const double tilted[3] = {0.3 / l, 0, 1 / l};
  const ElementCut cut = find_element_cut(m, stars, m.X.data(), centre, tilted, 0.1);
  ASSERT_TRUE(cut.found());
  EXPECT_NEAR(cut.boundary, 1 / l, 1e-12);
  EXPECT_GT(cut.alignment, cut.boundary);
  EXPECT_GE(std::min(cut.t, 1 - cut.t), 0.1);
}
