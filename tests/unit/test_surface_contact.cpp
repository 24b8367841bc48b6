// Unit tests of the contact between the pieces of a body's surface (crack faces, fragments).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "contact/surface_contact.h"
#include "io/mesh_generators.h"

using namespace fracdem;

namespace
{

// Two n x n tri3 unit squares in one mesh: A at the origin, B shifted by (shift, 0).
Mesh two_squares(int n, double shift)
{
  Mesh a = make_rect_mesh(n, n, 1.0, 1.0, {0, 0}, ElemType::Tri3);
  const Mesh b = make_rect_mesh(n, n, 1.0, 1.0, {shift, 0}, ElemType::Tri3);
  const int na = a.num_nodes();
  a.X.insert(a.X.end(), b.X.begin(), b.X.end());
  for (int e = 0; e < b.num_elems(); ++e) {
    std::array<int, 4> c = b.conn[e];
    for (int k = 0; k < 3; ++k)
      c[k] += na;
    a.conn.push_back(c);
    a.etype.push_back(b.etype[e]);
    a.active.push_back(1);
    a.region.push_back(0);
  }
  return a;
}

// Self contact of the mesh's surface: forces into f, returns the contact count.
int self_contact(const Mesh& m, double mu, const std::vector<double>& v,
                 const std::vector<double>& mass, std::vector<double>& f);

// Velocities of two_squares' nodes with B approaching A at the speed that makes its overlap
// delta within one step of dt (a penetration the step explains, so it is all pushed back).
std::vector<double> approaching(int nn, double delta, double dt)
{
  std::vector<double> v(3 * nn, 0.0);
  for (int n = nn / 2; n < nn; ++n)
    v[3 * n] = -delta / dt;
  return v;
}

SurfaceContactOptions options(double mu)
{
  SurfaceContactOptions o;
  o.youngs = 1e6;
  o.thickness = 0.1;
  o.friction = mu;
  return o;
}

int self_contact(const Mesh& m, double mu, const std::vector<double>& v,
                 const std::vector<double>& mass, std::vector<double>& f)
{
  ContactSurface surface;
  surface.build(m, boundary_facets(m));
  SurfaceContact sc;
  sc.configure(options(mu));
  const ContactBodyState st{m.X.data(), v.data(), mass.data(), f.data()};
  return sc.evaluate(surface, st, surface, st, true, 1e-6);
}

} // namespace

TEST(SurfaceContact, OverlappingPiecesArePushedApartWithBalancedForces)
{
  // B overlaps A's right face by delta: the 3 nodes of each facing side are delta deep in the
  // other square, so each gets k delta (k = E t) along the facet normal: B is pushed +x by
  // 6 k delta, A -x by the same, and the forces sum to zero.
  const double delta = 0.01;
  const Mesh m = two_squares(2, 1.0 - delta);
  const int nn = m.num_nodes();
  std::vector<double> v = approaching(nn, delta, 1e-6), mass(nn, 1.0), f(3 * nn, 0.0);
  const int contacts = self_contact(m, 0.0, v, mass, f);
  EXPECT_EQ(contacts, 6);
  double fa = 0, fb = 0, fy = 0;
  for (int n = 0; n < nn; ++n) {
    (n < nn / 2 ? fa : fb) += f[3 * n];
    fy += f[3 * n + 1];
  }
  const double k = 1e6 * 0.1;
  EXPECT_NEAR(fb, 6 * k * delta, 1e-9 * k * delta);
  EXPECT_NEAR(fa + fb, 0.0, 1e-12 * k * delta);
  EXPECT_NEAR(fy, 0.0, 1e-12 * k * delta);
}

TEST(SurfaceContact, FreeNodesOfErodedElementsStillHitSurfaces)
{
  // B's two triangles eroded: its four nodes fly on as point masses (erosion_mass keep). The two
  // on its left side are delta inside A's right face and approaching: each gets k delta along +x,
  // A the reaction; with their mass removed (erosion_mass remove) nothing is pushed.
  const double delta = 0.01;
  Mesh m = two_squares(1, 1.0 - delta);
  m.active[2] = m.active[3] = 0;
  const int nn = m.num_nodes();
  ContactSurface surface;
  surface.build(m, boundary_facets(m));
  EXPECT_EQ(surface.nodes, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  std::vector<double> v = approaching(nn, delta, 1e-6), mass(nn, 1.0), f(3 * nn, 0.0);
  EXPECT_EQ(self_contact(m, 0.0, v, mass, f), 2);
  const double k = 1e6 * 0.1;
  double fa = 0, fb = 0;
  for (int n = 0; n < nn; ++n)
    (n < nn / 2 ? fa : fb) += f[3 * n];
  EXPECT_NEAR(fb, 2 * k * delta, 1e-9 * k * delta);
  EXPECT_NEAR(fa + fb, 0.0, 1e-12 * k * delta);
  for (int n = nn / 2; n < nn; ++n)
    mass[n] = 0;
  std::fill(f.begin(), f.end(), 0.0);
  EXPECT_EQ(self_contact(m, 0.0, v, mass, f), 0);
  EXPECT_EQ(*std::max_element(f.begin(), f.end()), 0.0);
}

TEST(SurfaceContact, TouchingOrSeparatedPiecesAndAnIntactBodyFeelNothing)
{
  for (double shift : {1.0, 1.05}) { // closed crack (coincident faces), open gap
    const Mesh m = two_squares(3, shift);
    std::vector<double> v(3 * m.num_nodes(), 0.0), mass(m.num_nodes(), 1.0),
        f(3 * m.num_nodes(), 0.0);
    EXPECT_EQ(self_contact(m, 0.5, v, mass, f), 0) << shift;
  }
  // One graded, slightly jiggled body: its corners and neighbouring facets are no contact.
  Mesh m = make_rect_mesh(6, 3, 1.0, 0.2, {0, 0}, ElemType::Quad4);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  for (int n = 0; n < m.num_nodes(); ++n)
    m.X[3 * n + 1] *= 1 + 0.5 * (m.X[3 * n] > 0.5) + u(rng);
  std::vector<double> v(3 * m.num_nodes(), 0.0), mass(m.num_nodes(), 1.0),
      f(3 * m.num_nodes(), 0.0);
  EXPECT_EQ(self_contact(m, 0.5, v, mass, f), 0);
}

TEST(SurfaceContact, FrictionOpposesSlidingAndCannotReverseIt)
{
  // B overlapping A and sliding up at 1 m/s: friction on B points down, at most mu f_n per
  // contact, and not more than stops a node within the step.
  const double delta = 0.01, mu = 0.3;
  const Mesh m = two_squares(2, 1.0 - delta);
  const int nn = m.num_nodes();
  std::vector<double> v = approaching(nn, delta, 1e-6), mass(nn, 1.0), f(3 * nn, 0.0);
  for (int n = nn / 2; n < nn; ++n)
    v[3 * n + 1] = 1.0;
  self_contact(m, mu, v, mass, f);
  double fy_b = 0, fy = 0;
  for (int n = 0; n < nn; ++n) {
    fy += f[3 * n + 1];
    if (n >= nn / 2) fy_b += f[3 * n + 1];
  }
  const double k = 1e6 * 0.1;
  EXPECT_NEAR(fy_b, -mu * 6 * k * delta, 1e-9 * k * delta);
  EXPECT_NEAR(fy, 0.0, 1e-12 * k * delta);
}

TEST(SurfaceContact, TwoBodiesGetTheSameForcesAsOneMeshOfTwoPieces)
{
  // The same two overlapping squares as separate bodies (two meshes, two passes: nodes of A on
  // facets of B and the reverse) give exactly the forces of the one-mesh self contact.
  const double delta = 0.02;
  const Mesh one = two_squares(2, 1.0 - delta);
  std::vector<double> v1 = approaching(one.num_nodes(), delta, 1e-6), m1(one.num_nodes(), 1.0),
                      f1(3 * one.num_nodes(), 0.0);
  self_contact(one, 0.0, v1, m1, f1);
  const Mesh a = make_rect_mesh(2, 2, 1.0, 1.0, {0, 0}, ElemType::Tri3);
  const Mesh b = make_rect_mesh(2, 2, 1.0, 1.0, {1.0 - delta, 0}, ElemType::Tri3);
  ContactSurface sa, sb;
  sa.build(a, boundary_facets(a));
  sb.build(b, boundary_facets(b));
  const int n = a.num_nodes();
  std::vector<double> va(3 * n, 0.0), vb(v1.begin() + 3 * n, v1.end()), m(n, 1.0), fa(3 * n, 0.0),
      fb(3 * n, 0.0);
  const ContactBodyState st_a{a.X.data(), va.data(), m.data(), fa.data()};
  const ContactBodyState st_b{b.X.data(), vb.data(), m.data(), fb.data()};
  SurfaceContact ab, ba;
  ab.configure(options(0.0));
  ba.configure(options(0.0));
  const int c =
      ab.evaluate(sa, st_a, sb, st_b, false, 1e-6) + ba.evaluate(sb, st_b, sa, st_a, false, 1e-6);
  EXPECT_EQ(c, 6);
  EXPECT_GT(std::fabs(f1[3 * n]), 0.0); // the comparison is of real forces
  for (int k = 0; k < 3 * n; ++k) {
    EXPECT_NEAR(fa[k], f1[k], 1e-9);
    EXPECT_NEAR(fb[k], f1[3 * n + k], 1e-9);
  }
}

TEST(SurfaceContact, PenetrationTheStepCannotExplainReleasesNoEnergy)
{
  // The two squares overlap by delta but stand still (as after an erosion exposes a facet, or
  // when pieces are placed overlapping): no force. B then moves in by eps within one step: only
  // eps is pushed back. Moving out, the offset shrinks with the penetration (never a pull), and a
  // contact that ends forgets its offset.
  const double delta = 0.01, eps = 0.001, dt = 1e-6, k = 1e6 * 0.1;
  Mesh m = two_squares(2, 1.0 - delta);
  const int nn = m.num_nodes();
  std::vector<double> v(3 * nn, 0.0), mass(nn, 1.0), f(3 * nn, 0.0);
  ContactSurface surface;
  surface.build(m, boundary_facets(m));
  SurfaceContact sc;
  sc.configure(options(0.0));
  auto step = [&](double shift, double vx) {
    for (int n = nn / 2; n < nn; ++n) {
      m.X[3 * n] += shift;
      v[3 * n] = vx;
    }
    std::fill(f.begin(), f.end(), 0.0);
    const ContactBodyState st{m.X.data(), v.data(), mass.data(), f.data()};
    const int c = sc.evaluate(surface, st, surface, st, true, dt);
    double fb = 0;
    for (int n = nn / 2; n < nn; ++n)
      fb += f[3 * n];
    return std::make_pair(c, fb);
  };
  auto [c0, f0] = step(0.0, 0.0);
  EXPECT_EQ(c0, 6);
  EXPECT_EQ(f0, 0.0);
  auto [c1, f1] = step(-eps, -eps / dt);
  EXPECT_EQ(c1, 6);
  EXPECT_NEAR(f1, 6 * k * eps, 1e-6 * k * eps);
  auto [c2, f2] = step(0.5 * delta + eps, 0.5 * delta / dt); // out to half the first overlap
  EXPECT_EQ(c2, 6);
  EXPECT_EQ(f2, 0.0);
  auto [c3, f3] = step(-0.25 * delta, -0.25 * delta / dt); // back in by a quarter: all pushed
  EXPECT_NEAR(f3, 6 * k * 0.25 * delta, 1e-6 * k * delta);
  step(delta, 0.0); // apart: the contact ends
  // Back in to an overlap of delta / 2 within one step: a fresh contact the step explains.
  auto [c5, f5] = step(-0.75 * delta, -0.75 * delta / dt);
  EXPECT_EQ(c5, 6);
  EXPECT_NEAR(f5, 6 * k * 0.5 * delta, 1e-6 * k * delta);
}

TEST(SurfaceContact, PackedStateContinuesContactsAsTheUninterruptedObject)
{
  // B moves into A over a few steps (penetration the steps explain), then rests overlapping:
  // the uninterrupted contact keeps pushing. A fresh object (a restart without the state) takes
  // the resting overlap for an unexplained one and pushes nothing; one given the packed state
  // gives the uninterrupted forces, bit for bit.
  const double eps = 0.001, dt = 1e-6;
  Mesh m = two_squares(2, 1.0);
  const int nn = m.num_nodes();
  std::vector<double> v(3 * nn, 0.0), mass(nn, 1.0), f(3 * nn, 0.0);
  ContactSurface surface;
  surface.build(m, boundary_facets(m));
  SurfaceContact sc;
  sc.configure(options(0.3));
  auto evaluate = [&](SurfaceContact& c, std::vector<double>& force) {
    force.assign(3 * nn, 0.0);
    const ContactBodyState st{m.X.data(), v.data(), mass.data(), force.data()};
    return c.evaluate(surface, st, surface, st, true, dt);
  };
  for (int s = 0; s < 3; ++s) {
    for (int n = nn / 2; n < nn; ++n) {
      m.X[3 * n] -= eps;
      v[3 * n] = -eps / dt;
    }
    evaluate(sc, f);
  }
  for (int n = nn / 2; n < nn; ++n)
    v[3 * n] = 0.0;
  EXPECT_EQ(evaluate(sc, f), 6); // resting, still pushed
  std::vector<double> state;
  sc.pack_state(state);
  EXPECT_EQ(state.size(), 3u * 6);

  SurfaceContact restored, fresh;
  restored.configure(options(0.3));
  fresh.configure(options(0.3));
  restored.unpack_state(state.data(), state.size());
  std::vector<double> f_sc, f_restored, f_fresh;
  EXPECT_EQ(evaluate(sc, f_sc), 6);
  EXPECT_EQ(evaluate(restored, f_restored), 6);
  EXPECT_EQ(evaluate(fresh, f_fresh), 6);
  double push = 0;
  for (int n = nn / 2; n < nn; ++n)
    push += f_sc[3 * n];
  EXPECT_GT(push, 0.5 * 6 * 1e6 * 0.1 * 3 * eps);
  EXPECT_EQ(f_restored, f_sc); // bitwise
  EXPECT_NE(f_fresh, f_sc);
  for (double x : f_fresh)
    EXPECT_EQ(x, 0.0);
  // A second step continues as well; the packed state of both is the same.
  EXPECT_EQ(evaluate(sc, f_sc), 6);
  EXPECT_EQ(evaluate(restored, f_restored), 6);
  EXPECT_EQ(f_restored, f_sc);
  std::vector<double> s1, s2;
  sc.pack_state(s1);
  restored.pack_state(s2);
  EXPECT_EQ(s1, s2);
  // No state: a fresh object; a corrupt record is refused.
  SurfaceContact empty;
  empty.unpack_state(nullptr, 0);
  EXPECT_EQ(evaluate(empty, f), 6);
  for (double x : f)
    EXPECT_EQ(x, 0.0);
  EXPECT_THROW(empty.unpack_state(state.data(), 4), std::runtime_error);
}

namespace
{

// Two 2 x 2 x 2 tet boxes, A on x in [0, 1] and B on [1, 2], that a crack along x = 1 split:
// the nodes of the interface are split nodes and their copies (bitwise equal positions, so
// one site each). The interface is made rough (x moved by up to 0.08 as a function of y, z,
// the same for both copies), so the facets around a copy are tilted up to about 20 deg off
// the crack plane. Returns the number of nodes on the interface.
int split_boxes(Mesh& m)
{
  m = make_box_tet_mesh(2, 2, 2, 1.0, 1.0, 1.0);
  const Mesh b = make_box_tet_mesh(2, 2, 2, 1.0, 1.0, 1.0);
  const int na = m.num_nodes();
  for (int n = 0; n < b.num_nodes(); ++n)
    for (int d = 0; d < 3; ++d)
      m.X.push_back(b.X[3 * n + d] + (d == 0 ? 1.0 : 0.0));
  for (int e = 0; e < b.num_elems(); ++e) {
    std::array<int, 4> c = b.conn[e];
    for (int k = 0; k < 4; ++k)
      c[k] += na;
    m.conn.push_back(c);
    m.etype.push_back(b.etype[e]);
    m.active.push_back(1);
    m.region.push_back(0);
  }
  int on = 0;
  for (int n = 0; n < m.num_nodes(); ++n)
    if (m.X[3 * n] == 1.0) {
      const double y = m.X[3 * n + 1], z = m.X[3 * n + 2];
      m.X[3 * n] += 0.08 * std::sin(7 * y + 3) * std::cos(5 * z + 1);
      ++on;
    }
  return on / 2;
}

} // namespace

TEST(SurfaceContact, ASplitNodeAndTheFacetsAroundItsCopyOpenOrSlideFreely)
{
  // A split node lies at a corner of every facet around its copy, so for a small relative
  // motion of the twins it projects onto all of them (within the 1 % tolerance) and, for a
  // rough crack, lies behind the plane of some for most directions of opening or sliding: the
  // rule before (node against the deepest such facet) pushed it along that facet's tilted
  // normal, which made energy in test_fracture_cut's torn bar. Against its copy's facets the
  // penetration is the twins' closing along the crack's normal there (the difference of the
  // two vertex normals): opening with sliding up to the opening gives no force; the same
  // surface with its sites ignored (the rule before) takes many contacts.
  Mesh m;
  const int twins = split_boxes(m);
  ASSERT_EQ(twins, 9);
  ContactSurface s;
  s.build(m, boundary_facets(m));
  ContactSurface unsited = s;
  unsited.site.clear();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  const double dt = 1e-6;
  const int na = m.num_nodes() / 2;
  int before = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const double size = std::pow(10.0, -6 + 3 * 0.5 * (u(rng) + 1));
    const double open = size * 0.5 * (u(rng) + 1);
    const double d[3] = {open, open * u(rng) * 0.7, open * u(rng) * 0.7};
    std::vector<double> x = m.X, v(m.X.size(), 0.0), mass(m.num_nodes(), 1.0);
    for (int n = na; n < m.num_nodes(); ++n)
      for (int k = 0; k < 3; ++k) {
        x[3 * n + k] += d[k];
        v[3 * n + k] = d[k] / dt;
      }
    std::vector<double> f(m.X.size(), 0.0), f_old(m.X.size(), 0.0);
    SurfaceContact sc, old_rule;
    sc.configure(options(0.3));
    old_rule.configure(options(0.3));
    const ContactBodyState st{x.data(), v.data(), mass.data(), f.data()};
    const ContactBodyState st_old{x.data(), v.data(), mass.data(), f_old.data()};
    EXPECT_EQ(sc.evaluate(s, st, s, st, true, dt), 0) << trial;
    EXPECT_EQ(*std::max_element(f.begin(), f.end()), 0.0);
    EXPECT_EQ(*std::min_element(f.begin(), f.end()), 0.0);
    before += old_rule.evaluate(unsited, st_old, unsited, st_old, true, dt) > 0;
  }
  EXPECT_GE(before, 30) << "of 300";
}

TEST(SurfaceContact, AClosingCrackIsPushedOpenAtEveryPairOfTwins)
{
  // The same crack closing beyond contact (B moved towards A, within the step): every split
  // node meets the facets around its copy, with the twins' approach as its penetration, and
  // the forces push the pieces apart with zero sum.
  Mesh m;
  const int twins = split_boxes(m);
  ContactSurface s;
  s.build(m, boundary_facets(m));
  const double dt = 1e-6, e = 1e-4;
  const int na = m.num_nodes() / 2;
  std::vector<double> x = m.X, v(m.X.size(), 0.0), mass(m.num_nodes(), 1.0);
  std::vector<double> f(m.X.size(), 0.0);
  for (int n = na; n < m.num_nodes(); ++n) {
    x[3 * n] -= e;
    v[3 * n] = -e / dt;
  }
  SurfaceContact sc;
  sc.configure(options(0));
  const ContactBodyState st{x.data(), v.data(), mass.data(), f.data()};
  EXPECT_EQ(sc.evaluate(s, st, s, st, true, dt), 2 * twins); // each twin on the other's facets
  double fa = 0, sum[3] = {0, 0, 0}, scale = 0;
  for (int n = 0; n < m.num_nodes(); ++n)
    for (int d = 0; d < 3; ++d) {
      sum[d] += f[3 * n + d];
      scale = std::max(scale, std::fabs(f[3 * n + d]));
      if (n < na && d == 0) fa += f[3 * n];
    }
  EXPECT_LT(fa, 0); // A pushed towards -x, away from B
  for (double c : sum)
    EXPECT_LT(std::fabs(c), 1e-12 * scale);
}
