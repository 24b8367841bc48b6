// Unit tests of the contact between the pieces of a body's surface (crack faces, fragments).
#include <gtest/gtest.h>

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
  std::vector<double> v(3 * nn, 0.0), mass(nn, 1.0), f(3 * nn, 0.0);
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
  std::vector<double> v(3 * nn, 0.0), mass(nn, 1.0), f(3 * nn, 0.0);
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
  std::vector<double> v1(3 * one.num_nodes(), 0.0), m1(one.num_nodes(), 1.0),
      f1(3 * one.num_nodes(), 0.0);
  self_contact(one, 0.0, v1, m1, f1);
  const Mesh a = make_rect_mesh(2, 2, 1.0, 1.0, {0, 0}, ElemType::Tri3);
  const Mesh b = make_rect_mesh(2, 2, 1.0, 1.0, {1.0 - delta, 0}, ElemType::Tri3);
  ContactSurface sa, sb;
  sa.build(a, boundary_facets(a));
  sb.build(b, boundary_facets(b));
  const int n = a.num_nodes();
  std::vector<double> v(3 * n, 0.0), m(n, 1.0), fa(3 * n, 0.0), fb(3 * n, 0.0);
  const ContactBodyState st_a{a.X.data(), v.data(), m.data(), fa.data()};
  const ContactBodyState st_b{b.X.data(), v.data(), m.data(), fb.data()};
  SurfaceContact ab, ba;
  ab.configure(options(0.0));
  ba.configure(options(0.0));
  const int c =
      ab.evaluate(sa, st_a, sb, st_b, false, 1e-6) + ba.evaluate(sb, st_b, sa, st_a, false, 1e-6);
  EXPECT_EQ(c, 6);
  for (int k = 0; k < 3 * n; ++k) {
    EXPECT_NEAR(fa[k], f1[k], 1e-9);
    EXPECT_NEAR(fb[k], f1[3 * n + k], 1e-9);
  }
}
