// Unit tests of edge-to-edge contact between 3D surfaces (EdgeContact, ContactSurface::edges).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>

#include "contact/edge_contact.h"
#include "io/mesh_generators.h"

using namespace fracdem;

namespace
{

using Vec = std::array<double, 3>;

// Appends a tet4 element with these corners (made positive) to m.
void add_tet(Mesh& m, const std::array<Vec, 4>& p)
{
  const int base = m.num_nodes();
  for (const Vec& q : p)
    m.X.insert(m.X.end(), q.begin(), q.end());
  std::array<int, 4> c{base, base + 1, base + 2, base + 3};
  if (tet_volume6(m.X.data(), c) < 0) std::swap(c[2], c[3]);
  m.conn.push_back(c);
  m.etype.push_back(ElemType::Tet4);
  m.active.push_back(1);
  m.region.push_back(0);
}

Mesh one_tet(const std::array<Vec, 4>& p)
{
  Mesh m;
  m.dim = 3;
  add_tet(m, p);
  return m;
}

// A: ridge a0-a1 along x at height z (its body above), B: ridge along (cos w, sin w, 0) at 0
// (its body below); both ridges centred on the z axis, facets at 90 deg about the ridge.
Mesh ridge_a(double z)
{
  return one_tet({{{-1, 0, z}, {1, 0, z}, {0, -1, z + 1}, {0, 1, z + 1}}});
}
Mesh ridge_b(double w)
{
  const double c = std::cos(w), s = std::sin(w);
  return one_tet({{{-c, -s, 0}, {c, s, 0}, {s, -c, -1}, {-s, c, -1}}});
}

// Rotation about a random axis and a shift, applied to positions in place.
void move_rigidly(std::vector<double>& x, double angle, const Vec& axis, const Vec& shift)
{
  const double l = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  const Vec k{axis[0] / l, axis[1] / l, axis[2] / l};
  const double c = std::cos(angle), s = std::sin(angle);
  for (size_t i = 0; i < x.size(); i += 3) {
    const Vec v{x[i], x[i + 1], x[i + 2]};
    const double kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
    const Vec kx{k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2], k[0] * v[1] - k[1] * v[0]};
    for (int d = 0; d < 3; ++d)
      x[i + d] = v[d] * c + kx[d] * s + k[d] * kv * (1 - c) + shift[d];
  }
}

SurfaceContactOptions options(double mu)
{
  SurfaceContactOptions o;
  o.youngs = 1e6;
  o.friction = mu;
  return o;
}

struct Pair {
  Mesh ma, mb;
  ContactSurface sa, sb;
  std::vector<double> va, vb, mass_a, mass_b, fa, fb;
  Pair(Mesh a, Mesh b) : ma(std::move(a)), mb(std::move(b))
  {
    sa.build(ma, boundary_facets(ma));
    sb.build(mb, boundary_facets(mb));
    va.assign(ma.X.size(), 0.0);
    vb.assign(mb.X.size(), 0.0);
    mass_a.assign(ma.num_nodes(), 1.0);
    mass_b.assign(mb.num_nodes(), 1.0);
  }
  int evaluate(EdgeContact& ec, double dt)
  {
    fa.assign(ma.X.size(), 0.0);
    fb.assign(mb.X.size(), 0.0);
    const ContactBodyState a{ma.X.data(), va.data(), mass_a.data(), fa.data()};
    const ContactBodyState b{mb.X.data(), vb.data(), mass_b.data(), fb.data()};
    return ec.evaluate(sa, a, sb, b, false, dt);
  }
};

// Stiffness of the pair: penalty_scale E times the mean square root of B's edge facets' areas.
double stiffness(const Pair& p, const EdgeTouch& t)
{
  const SurfaceEdge& e = p.sb.edges[t.eb];
  return 1e6 * 0.5 *
         (std::sqrt(facet_measure(p.mb.X.data(), p.sb.facets[e.facet[0]])) +
          std::sqrt(facet_measure(p.mb.X.data(), p.sb.facets[e.facet[1]])));
}

} // namespace

TEST(EdgeContact, SurfaceEdgesOfABoxAreItsTwelveEdgesAsFeatures)
{
  // A 3 x 2 x 2 tet box: every boundary edge has two facets; the feature edges are the box's 12
  // edges (4 x 3 + 4 x 2 + 4 x 2 = 28 segments), the face diagonals and in-face edges are flat.
  const Mesh m = make_box_tet_mesh(3, 2, 2, 3.0, 2.0, 2.0);
  ContactSurface s;
  s.build(m, boundary_facets(m));
  EXPECT_EQ(s.edges.size(), 3 * s.facets.size() / 2); // closed surface
  const long features =
      std::count_if(s.edges.begin(), s.edges.end(), [](const SurfaceEdge& e) { return e.feature; });
  EXPECT_EQ(features, 28);
  for (const SurfaceEdge& e : s.edges) {
    if (!e.feature) continue;
    int on_box_edges = 0; // both nodes on two of the box's faces
    for (int k = 0; k < 2; ++k) {
      const double* x = &m.X[3 * e.n[k]];
      const int faces =
          (x[0] == 0 || x[0] == 3) + (x[1] == 0 || x[1] == 2) + (x[2] == 0 || x[2] == 2);
      on_box_edges += faces >= 2;
    }
    EXPECT_EQ(on_box_edges, 2);
  }
  // 2D surfaces have no edges.
  const Mesh r = make_rect_mesh(2, 2, 1.0, 1.0);
  ContactSurface s2;
  s2.build(r, boundary_facets(r));
  EXPECT_TRUE(s2.edges.empty());
}

TEST(EdgeContact, CrossingEdgesGiveTheAnalyticGapAndForce)
{
  // Ridge A (along x) has come down by g below ridge B (at angle w in the x-y plane) within the
  // step: the closest points are the ridges' midpoints, the gap g, the normal +z (B's outside),
  // and the force k g on A's two nodes by halves, the opposite on B's. The same in a rotated and
  // shifted frame.
  const double g = 0.05, dt = 1e-4;
  for (double w : {M_PI / 2, M_PI / 3, 0.4}) {
    for (int frame = 0; frame < 2; ++frame) {
      Pair p(ridge_a(-g), ridge_b(w));
      Vec n{0, 0, 1};
      for (int n0 = 0; n0 < 4; ++n0)
        p.va[3 * n0 + 2] = -g / dt;
      if (frame == 1) {
        const Vec axis{0.3, -1, 0.7}, shift{5, -2, 11};
        move_rigidly(p.ma.X, 1.1, axis, shift);
        move_rigidly(p.mb.X, 1.1, axis, shift);
        move_rigidly(p.va, 1.1, axis, {0, 0, 0});
        std::vector<double> nv(n.begin(), n.end());
        move_rigidly(nv, 1.1, axis, {0, 0, 0});
        n = {nv[0], nv[1], nv[2]};
      }
      EdgeContact ec;
      ec.configure(options(0.0));
      ASSERT_EQ(p.evaluate(ec, dt), 1) << w;
      const EdgeTouch& t = ec.touches()[0];
      EXPECT_NEAR(t.s, 0.5, 1e-12);
      EXPECT_NEAR(t.t, 0.5, 1e-12);
      EXPECT_NEAR(t.depth, g, 1e-12);
      for (int d = 0; d < 3; ++d)
        EXPECT_NEAR(t.normal[d], n[d], 1e-12);
      const double k = stiffness(p, t);
      const SurfaceEdge& ea = p.sa.edges[t.ea];
      for (int j = 0; j < 2; ++j)
        for (int d = 0; d < 3; ++d)
          EXPECT_NEAR(p.fa[3 * ea.n[j] + d], 0.5 * k * g * n[d], 1e-9 * k * g);
      double sum[3] = {0, 0, 0};
      for (size_t i = 0; i < p.fb.size(); ++i)
        sum[i % 3] += p.fb[i];
      for (int d = 0; d < 3; ++d)
        EXPECT_NEAR(sum[d], -k * g * n[d], 1e-9 * k * g);
    }
  }
}

TEST(EdgeContact, ParallelEndPointSeparatedAndTooDeepPairsGiveNone)
{
  // The rule for the pair of ridges (nodes 0-1 of each tet); the tets' other edges may cross
  // where the tets overlap, so the pair is asked directly.
  auto ridges_touch = [](const Mesh& a, const Mesh& b) {
    ContactSurface sa, sb;
    sa.build(a, boundary_facets(a));
    sb.build(b, boundary_facets(b));
    auto ridge = [](const ContactSurface& s) {
      for (int k = 0; k < static_cast<int>(s.edges.size()); ++k)
        if (s.edges[k].n[0] == 0 && s.edges[k].n[1] == 1) return k;
      return -1;
    };
    EXPECT_TRUE(sa.edges[ridge(sa)].feature && sb.edges[ridge(sb)].feature);
    EdgeTouch t;
    return edge_touch(sa, ridge(sa), a.X.data(), sb, ridge(sb), b.X.data(), t);
  };
  EXPECT_TRUE(ridges_touch(ridge_a(-0.05), ridge_b(M_PI / 2))); // crossing: the reference
  EXPECT_TRUE(ridges_touch(ridge_a(-0.05), ridge_b(0.011)));    // just beyond kParallelSin
  EXPECT_FALSE(ridges_touch(ridge_a(-0.05), ridge_b(0.0)));     // parallel
  EXPECT_FALSE(ridges_touch(ridge_a(-0.05), ridge_b(0.009)));   // within kParallelSin
  EXPECT_FALSE(ridges_touch(ridge_a(0.05), ridge_b(M_PI / 2))); // apart
  EXPECT_FALSE(ridges_touch(ridge_a(-0.9), ridge_b(M_PI / 2))); // beyond the reach
  // B's ridge shifted along A's past A's end (s > 1), and to A's end exactly (s = 1: a node).
  for (double shift : {1.2, 1.0}) {
    Mesh b = ridge_b(M_PI / 2);
    for (int n = 0; n < 4; ++n)
      b.X[3 * n] += shift;
    EXPECT_FALSE(ridges_touch(ridge_a(-0.05), b)) << shift;
  }
  // A's ridge upside down (its body below its edge): its outside does not face B.
  const Mesh flipped = one_tet({{{-1, 0, -0.05}, {1, 0, -0.05}, {0, -1, -1.05}, {0, 1, -1.05}}});
  EXPECT_FALSE(ridges_touch(flipped, ridge_b(M_PI / 2)));
  // Apart, the whole evaluation finds nothing either.
  Pair p(ridge_a(0.05), ridge_b(M_PI / 2));
  EdgeContact ec;
  ec.configure(options(0.3));
  EXPECT_EQ(p.evaluate(ec, 1e-4), 0);
}

TEST(EdgeContact, MomentumAndAngularMomentumAreExactWithFriction)
{
  // A skewed crossing in a rotated frame, the ridges sliding across each other: the nodal
  // forces sum to zero and their moment about any point vanishes, to round-off of the forces.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  const double dt = 1e-4, g = 0.03;
  for (int trial = 0; trial < 20; ++trial) {
    Pair r(ridge_a(-g), ridge_b(0.3 + 1.2 * (u(rng) + 1)));
    for (int n = 0; n < 4; ++n) {
      r.va[3 * n] = 3 + u(rng);
      r.va[3 * n + 1] = u(rng);
      r.va[3 * n + 2] = -g / dt;
      r.mass_a[n] = 1 + 0.5 * u(rng);
      r.mass_b[n] = 1 + 0.5 * u(rng);
    }
    const Vec axis{u(rng), u(rng), u(rng)}, shift{10 * u(rng), 10 * u(rng), 10 * u(rng)};
    const double angle = 3 * u(rng);
    move_rigidly(r.ma.X, angle, axis, shift);
    move_rigidly(r.mb.X, angle, axis, shift);
    move_rigidly(r.va, angle, axis, {0, 0, 0});
    EdgeContact ec;
    ec.configure(options(0.4));
    ASSERT_EQ(r.evaluate(ec, dt), 1);
    double f[3] = {0, 0, 0}, m[3] = {0, 0, 0}, fscale = 0, mscale = 0;
    auto add = [&](const std::vector<double>& x, const std::vector<double>& force) {
      for (size_t i = 0; i < x.size(); i += 3) {
        const double* a = &x[i];
        const double* b = &force[i];
        const double fl = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
        const double xl = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        fscale += fl;
        mscale += fl * xl;
        f[0] += b[0], f[1] += b[1], f[2] += b[2];
        m[0] += a[1] * b[2] - a[2] * b[1];
        m[1] += a[2] * b[0] - a[0] * b[2];
        m[2] += a[0] * b[1] - a[1] * b[0];
      }
    };
    add(r.ma.X, r.fa);
    add(r.mb.X, r.fb);
    // Friction acted: the force on A is not along the normal.
    const EdgeTouch& t = ec.touches()[0];
    double fa[3] = {0, 0, 0};
    for (size_t i = 0; i < r.fa.size(); ++i)
      fa[i % 3] += r.fa[i];
    const double fan = fa[0] * t.normal[0] + fa[1] * t.normal[1] + fa[2] * t.normal[2];
    const double fat =
        std::sqrt(std::max(0.0, fa[0] * fa[0] + fa[1] * fa[1] + fa[2] * fa[2] - fan * fan));
    EXPECT_GT(fat, 0.1 * fan);
    EXPECT_LE(fat, 0.4 * fan * (1 + 1e-12));
    for (int d = 0; d < 3; ++d) {
      EXPECT_LT(std::fabs(f[d]), 1e-14 * fscale) << trial;
      EXPECT_LT(std::fabs(m[d]), 1e-14 * mscale) << trial;
    }
  }
}

namespace
{
// A soup of randomly placed and turned regular tets of edge h in the unit box, as one mesh.
Mesh soup(int count, double h, std::mt19937& rng)
{
  std::uniform_real_distribution<double> u(0, 1);
  Mesh m;
  m.dim = 3;
  const double r = h / std::sqrt(8.0);
  for (int i = 0; i < count; ++i) {
    std::vector<double> x = {r, r, r, r, -r, -r, -r, r, -r, -r, -r, r};
    move_rigidly(x, 2 * M_PI * u(rng), {u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5},
                 {u(rng), u(rng), u(rng)});
    add_tet(m,
            {{{x[0], x[1], x[2]}, {x[3], x[4], x[5]}, {x[6], x[7], x[8]}, {x[9], x[10], x[11]}}});
  }
  return m;
}

// Every pair by the rule, without search (self: i < j, not neighbours).
std::set<std::pair<int, int>> brute_force(const ContactSurface& a, const double* xa,
                                          const ContactSurface& b, const double* xb, bool self)
{
  std::set<std::pair<int, int>> out;
  for (int i = 0; i < static_cast<int>(a.edges.size()); ++i)
    for (int j = 0; j < static_cast<int>(b.edges.size()); ++j) {
      if (!a.edges[i].feature || !b.edges[j].feature) continue;
      if (self && (i >= j || edges_adjacent(a, i, j))) continue;
      EdgeTouch t;
      if (edge_touch(a, i, xa, b, j, xb, t)) out.insert({i, j});
    }
  return out;
}
} // namespace

TEST(EdgeContact, SearchAgreesWithBruteForceOnEdgeSoups)
{
  // Self contact of one soup and contact of two soups, the nodes jiggled over 20 evaluations
  // (the search is rebuilt only when the travel uses up the reach): the contacting pairs are
  // those of the all-pairs rule every time.
  std::mt19937 rng(11);
  std::normal_distribution<double> jig(0, 0.004);
  Mesh ma = soup(100, 0.2, rng), mb = soup(100, 0.2, rng);
  ContactSurface sa, sb;
  sa.build(ma, boundary_facets(ma));
  sb.build(mb, boundary_facets(mb));
  std::vector<double> va(ma.X.size(), 0.0), vb(mb.X.size(), 0.0);
  std::vector<double> mass_a(ma.num_nodes(), 1.0), mass_b(mb.num_nodes(), 1.0);
  std::vector<double> fa(ma.X.size()), fb(mb.X.size());
  EdgeContact self, two;
  self.configure(options(0.2));
  two.configure(options(0.2));
  size_t total_self = 0, total_two = 0;
  for (int step = 0; step < 20; ++step) {
    for (double& x : ma.X)
      x += jig(rng);
    for (double& x : mb.X)
      x += jig(rng);
    const ContactBodyState a{ma.X.data(), va.data(), mass_a.data(), fa.data()};
    const ContactBodyState b{mb.X.data(), vb.data(), mass_b.data(), fb.data()};
    self.evaluate(sa, a, sa, a, true, 1e-3);
    two.evaluate(sa, a, sb, b, false, 1e-3);
    std::set<std::pair<int, int>> got_self, got_two;
    for (const EdgeTouch& t : self.touches())
      got_self.insert({t.ea, t.eb});
    for (const EdgeTouch& t : two.touches())
      got_two.insert({t.ea, t.eb});
    EXPECT_EQ(got_self.size(), self.touches().size()); // each pair once
    EXPECT_EQ(got_self, brute_force(sa, ma.X.data(), sa, ma.X.data(), true)) << step;
    EXPECT_EQ(got_two, brute_force(sa, ma.X.data(), sb, mb.X.data(), false)) << step;
    total_self += got_self.size();
    total_two += got_two.size();
  }
  std::printf("edge soups: %zu self, %zu two-body contacts in 20 evaluations\n", total_self,
              total_two);
  EXPECT_GT(total_self, 30u); // the soups do cross
  EXPECT_GT(total_two, 30u);
}

TEST(EdgeContact, PenetrationTheStepCannotExplainReleasesNoEnergy)
{
  // Ridges placed crossed by g with no approach: no force; approaching further by e within a
  // step: the force of e only; apart: the contact (and its offset) ends.
  const double g = 0.05, e = 0.01, dt = 1e-4;
  Pair p(ridge_a(-g), ridge_b(M_PI / 2));
  EdgeContact ec;
  ec.configure(options(0.0));
  ASSERT_EQ(p.evaluate(ec, dt), 1);
  for (double f : p.fa)
    EXPECT_EQ(f, 0.0);
  for (int n = 0; n < 4; ++n) {
    p.ma.X[3 * n + 2] -= e;
    p.va[3 * n + 2] = -e / dt;
  }
  ASSERT_EQ(p.evaluate(ec, dt), 1);
  const double k = stiffness(p, ec.touches()[0]);
  double fz = 0;
  for (size_t i = 2; i < p.fa.size(); i += 3)
    fz += p.fa[i];
  EXPECT_NEAR(fz, k * e, 1e-9 * k * e);
  EXPECT_NEAR(ec.touches()[0].depth, e, 1e-12);
}

TEST(EdgeContact, PackedStateContinuesContactsAsTheUninterruptedObject)
{
  const double dt = 1e-4, e = 0.01;
  Pair p(ridge_a(0.005), ridge_b(1.0));
  EdgeContact ec, restored, fresh;
  for (EdgeContact* c : {&ec, &restored, &fresh})
    c->configure(options(0.3));
  for (int s = 0; s < 3; ++s) {
    for (int n = 0; n < 4; ++n) {
      p.ma.X[3 * n + 2] -= e;
      p.va[3 * n + 2] = -e / dt;
      p.va[3 * n] = 0.5;
    }
    p.evaluate(ec, dt);
  }
  std::vector<double> state;
  ec.pack_state(state);
  ASSERT_EQ(state.size(), 6u);
  restored.unpack_state(state.data(), state.size());
  ASSERT_EQ(p.evaluate(ec, dt), 1);
  const std::vector<double> f_ec = p.fa;
  ASSERT_EQ(p.evaluate(restored, dt), 1);
  EXPECT_EQ(p.fa, f_ec); // bitwise
  ASSERT_EQ(p.evaluate(fresh, dt), 1);
  EXPECT_NE(p.fa, f_ec);
  EXPECT_THROW(fresh.unpack_state(state.data(), 4), std::runtime_error);
}

TEST(EdgeContact, AnIntactBoxFeelsNothing)
{
  // Self contact of a sheared, jiggled tet box: its own edges never meet.
  Mesh m = make_box_tet_mesh(4, 3, 3, 1.0, 0.6, 0.6);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  for (int n = 0; n < m.num_nodes(); ++n) {
    m.X[3 * n] += 0.2 * m.X[3 * n + 2] + u(rng);
    m.X[3 * n + 1] += u(rng);
  }
  ContactSurface s;
  s.build(m, boundary_facets(m));
  std::vector<double> v(m.X.size(), 0.0), mass(m.num_nodes(), 1.0), f(m.X.size(), 0.0);
  const ContactBodyState st{m.X.data(), v.data(), mass.data(), f.data()};
  EdgeContact ec;
  ec.configure(options(0.3));
  EXPECT_EQ(ec.evaluate(s, st, s, st, true, 1e-4), 0);
}

TEST(EdgeContact, EdgesMeetingAtASplitNodeAndItsCopyNeverTouch)
{
  // Two pieces of one body that a crack separated at one point: A's node 0 and B's node 4 are a
  // split node and its copy (the same reference position). Edges of A and of B ending there
  // meet at that point, so the closest points of their lines stay at it and the "penetration"
  // along n = (edge A) x (edge B) is the twins' relative displacement along n: opening or
  // sliding read as penetration for half the directions (what held test_fracture_cut's torn
  // bar shut). The pieces open in random directions (B away from A, x < 0, with sliding), the
  // motion made within the step: no edge contact, no force. The same surface with its sites
  // ignored (the rule before) takes some of these as contacts.
  Mesh m;
  m.dim = 3;
  add_tet(m, {{{0, 0, 0}, {0, 0, -1}, {0, 1, -1}, {1, 0, -0.5}}});          // A, x >= 0
  add_tet(m, {{{0, 0, 0}, {-0.3, 1, 0}, {-0.5, 0.5, -1}, {-1, 0.2, 0.3}}}); // B, x <= 0
  ContactSurface s;
  s.build(m, boundary_facets(m));
  ASSERT_EQ(s.site_of(4), s.site_of(0));
  ASSERT_NE(s.site_of(5), s.site_of(1));
  ContactSurface unsited = s;
  unsited.site.clear();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  const double dt = 1e-6;
  int before = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    const double size = std::pow(10.0, -6 + 3 * 0.5 * (u(rng) + 1));
    const Vec d{-size * 0.5 * (u(rng) + 1), size * u(rng), size * u(rng)};
    std::vector<double> x = m.X, v(m.X.size(), 0.0), mass(m.num_nodes(), 1.0);
    std::vector<double> f(m.X.size(), 0.0);
    for (int n = 4; n < 8; ++n)
      for (int k = 0; k < 3; ++k) {
        x[3 * n + k] += d[k];
        v[3 * n + k] = d[k] / dt;
      }
    const ContactBodyState st{x.data(), v.data(), mass.data(), f.data()};
    EdgeContact ec, old_rule;
    ec.configure(options(0.3));
    old_rule.configure(options(0.3));
    EXPECT_EQ(ec.evaluate(s, st, s, st, true, dt), 0) << trial;
    EXPECT_EQ(*std::max_element(f.begin(), f.end()), 0.0);
    EXPECT_EQ(*std::min_element(f.begin(), f.end()), 0.0);
    if (old_rule.evaluate(unsited, st, unsited, st, true, dt) > 0) {
      ++before;
      // Each is the twins' separation along n, and the pair meets at the twins (an edge end).
      for (const EdgeTouch& t : old_rule.touches()) {
        EXPECT_NEAR(t.depth, d[0] * t.normal[0] + d[1] * t.normal[1] + d[2] * t.normal[2],
                    1e-9 * size);
        EXPECT_LT(std::min({t.s, 1 - t.s}) + std::min({t.t, 1 - t.t}), 1.0);
      }
    }
  }
  EXPECT_GE(before, 10) << "of 1000";
}
