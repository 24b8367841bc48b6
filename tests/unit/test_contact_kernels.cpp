// Unit tests of contact kernels: closest points, the LIGGGHTS-convention law, search, resolution.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "contact/contact_resolution.h"
#include "contact/contact_spread.h"
#include "contact/contact_search.h"
#include "contact/geometry.h"
#include "contact/granular_law.h"
#include "contact/particle_facet.h"
#include "io/mesh_generators.h"

using namespace fracdem;

TEST(ContactGeometry, ClosestPointTriangleMatchesDenseSampling)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    double a[3], b[3], c[3], q[3];
    for (int d = 0; d < 3; ++d) {
      a[d] = U(rng);
      b[d] = U(rng);
      c[d] = U(rng);
      q[d] = 2 * U(rng);
    }
    ClosestPoint cp = closest_point_triangle(q, a, b, c);
    double best = 1e300;
    const int N = 300;
    for (int i = 0; i <= N; ++i)
      for (int j = 0; i + j <= N; ++j) {
        const double u = double(i) / N, v = double(j) / N;
        double d2 = 0;
        for (int d = 0; d < 3; ++d) {
          const double p = a[d] + u * (b[d] - a[d]) + v * (c[d] - a[d]);
          d2 += (p - q[d]) * (p - q[d]);
        }
        best = std::min(best, d2);
      }
    EXPECT_LE(cp.dist2, best + 1e-12);
    EXPECT_GE(cp.dist2, best - 0.02 * std::sqrt(best) * 2.0 / N * 4 - 1e-9);
    EXPECT_NEAR(cp.w[0] + cp.w[1] + cp.w[2], 1.0, 1e-12);
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(cp.p[d], cp.w[0] * a[d] + cp.w[1] * b[d] + cp.w[2] * c[d], 1e-12);
  }
  const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
  const double qf[3] = {0.2, 0.2, 1}, qe[3] = {0.5, -1, 0.3}, qv[3] = {-1, -1, 0};
  EXPECT_EQ(closest_point_triangle(qf, a, b, c).kind, Feature::Face);
  ClosestPoint ce = closest_point_triangle(qe, a, b, c);
  EXPECT_EQ(ce.kind, Feature::Edge);
  EXPECT_EQ(ce.local, 0);
  ClosestPoint cv = closest_point_triangle(qv, a, b, c);
  EXPECT_EQ(cv.kind, Feature::Vertex);
  EXPECT_EQ(cv.local, 0);
}

// The culling bound of particle-facet contact must never exceed the exact distance (a facet it
// drops would have been rejected by the closest point), on ordinary triangles, slivers,
// degenerate triangles, segments and far from the origin; and it must be tight enough to cull.
TEST(ContactGeometry, FacetDistanceBoundNeverExceedsTheClosestPoint)
{
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> U(-1, 1), L(-3, 1);
  int tight = 0, far = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const int shape = trial % 5; // 0 any, 1 sliver, 2 degenerate, 3 segment, 4 tiny and far
    const double offset = shape == 4 ? 1e4 : 0.0, size = shape == 4 ? 1e-3 : 1.0;
    double a[3], b[3], c[3], q[3];
    for (int d = 0; d < 3; ++d) {
      a[d] = offset + size * U(rng);
      b[d] = offset + size * U(rng);
      c[d] = offset + size * U(rng);
      q[d] = a[d] + size * U(rng) * std::pow(10.0, L(rng));
    }
    if (shape == 1 || shape == 2) { // c on (or within 1e-9 of) the line ab
      const double t = U(rng), eps = shape == 1 ? 1e-9 : 0.0;
      for (int d = 0; d < 3; ++d)
        c[d] = a[d] + t * (b[d] - a[d]) + eps * U(rng);
    }
    if (shape == 3) a[2] = b[2] = q[2] = 0;
    const FacetBound f = facet_bound(a, b, shape == 3 ? nullptr : c);
    const double exact = std::sqrt(shape == 3 ? closest_point_segment(q, a, b).dist2
                                              : closest_point_triangle(q, a, b, c).dist2);
    const double bound = facet_distance_bound(f, q);
    ASSERT_LE(bound, exact) << "trial " << trial << " shape " << shape;
    if (exact > 4 * f.radius) {
      ++far;
      tight += bound >= exact - 2.5 * f.radius;
    }
  }
  EXPECT_GT(far, 1000);
  EXPECT_EQ(tight, far); // |q - c| - sqrt(2) radius, minus the facet's own extent
}

namespace
{
// Particles (one row each, as a host keeps them) around a curved shell: a tet slab bent into a
// half cylinder of radius about 1, so that every sphere sees many facets at slight angles.
struct Cloud {
  std::vector<std::array<double, 3>> x, v, omega, f, torque;
  std::vector<double*> px, pv, pomega, pf, ptorque;
  std::vector<double> radius, mass;
  std::vector<int> type, mask;
  ParticleArrays arrays()
  {
    const int n = static_cast<int>(x.size());
    px.resize(n), pv.resize(n), pomega.resize(n), pf.resize(n), ptorque.resize(n);
    for (int i = 0; i < n; ++i) {
      px[i] = x[i].data(), pv[i] = v[i].data(), pomega[i] = omega[i].data();
      pf[i] = f[i].data(), ptorque[i] = torque[i].data();
    }
    ParticleArrays p;
    p.n = n;
    p.x = px.data(), p.v = pv.data(), p.omega = pomega.data(), p.f = pf.data();
    p.torque = ptorque.data();
    p.radius = radius.data(), p.rmass = mass.data(), p.type = type.data(), p.mask = mask.data();
    return p;
  }
};

Mesh bent_shell()
{
  Mesh mesh = make_box_tet_mesh(24, 8, 1, 3.0, 1.0, 0.1);
  for (int k = 0; k < mesh.num_nodes(); ++k) {
    double* X = &mesh.X[3 * k];
    const double th = X[0], rad = 1.0 + X[2];
    X[0] = rad * std::cos(th);
    X[2] = rad * std::sin(th);
  }
  return mesh;
}

// Resolved contacts of a sphere with every facet, without search or culling.
int brute_force_contacts(const std::vector<Facet>& facets, const SurfaceTopology& topo,
                         const double* x, const double q[3], double r)
{
  std::vector<FacetHit> hits;
  for (int k = 0; k < static_cast<int>(facets.size()); ++k) {
    const Facet& fc = facets[k];
    FacetHit h;
    h.facet = k;
    h.nn = 3;
    for (int j = 0; j < 3; ++j)
      h.nodes[j] = fc.n[j];
    h.cp = closest_point_triangle(q, &x[3 * fc.n[0]], &x[3 * fc.n[1]], &x[3 * fc.n[2]]);
    if (h.cp.dist2 < r * r) hits.push_back(h);
  }
  return hits.empty() ? 0 : static_cast<int>(resolve_sphere_hits(hits, q, x, topo).size());
}
} // namespace

// The pipeline culls candidates at the search build (r + sqrt(3) buffer) and every step (their
// bounds against r + sphere travel + node travel): on moving spheres and a deforming body it must
// find exactly the contacts of the brute force, and skip most exact tests.
TEST(ContactSearch, CulledContactsEqualBruteForceOnACurvedMovingSurface)
{
  const Mesh mesh = bent_shell();
  const auto facets = boundary_facets(mesh);
  SurfaceTopology topo;
  topo.build(facets, mesh.num_nodes());
  ParticleFacetContact contact;
  ParticleFacetOptions opt;
  opt.buffer = 0.02;
  opt.tangential_history = false;
  contact.configure(opt);
  contact.set_materials({ContactMaterial{},
                         mix_materials(1e7, 0.3, 1e7, 0.3, 0.9, 0.5, 1, NormalModel::Hertz, true)});
  contact.rebuild_surface(mesh);

  std::mt19937 rng(23);
  std::uniform_real_distribution<double> U(-1, 1), R(0.02, 0.08), step(-0.003, 0.003);
  Cloud cloud;
  for (int i = 0; i < 400; ++i) { // within 0.1 of the inner or outer face
    const double th = 1.5 + 1.5 * U(rng), rad = (i % 2 ? 0.95 : 1.15) + 0.1 * U(rng);
    cloud.x.push_back({rad * std::cos(th), 0.5 + 0.55 * U(rng), rad * std::sin(th)});
    cloud.radius.push_back(R(rng));
    cloud.mass.push_back(1.0);
    cloud.type.push_back(1);
    cloud.mask.push_back(1);
  }
  const int n = static_cast<int>(cloud.x.size());
  cloud.v = cloud.omega = cloud.f = cloud.torque = std::vector<std::array<double, 3>>(n);
  std::vector<double> x = mesh.X, v(x.size(), 0.0), fn(x.size(), 0.0);
  long long exact_tests = 0, contacts = 0;
  for (int it = 0; it < 60; ++it) {
    contact.evaluate(cloud.arrays(), mesh.X.data(), x.data(), v.data(), 1e-6, fn.data());
    for (int i = 0; i < n; ++i) {
      const int expect =
          brute_force_contacts(facets, topo, x.data(), cloud.x[i].data(), cloud.radius[i]);
      ASSERT_EQ(contact.contacts()[i], expect) << "particle " << i << " at step " << it;
      contacts += expect;
      exact_tests += contact.checks()[i];
    }
    for (auto& q : cloud.x) // spheres drift; the search rebuilds now and then
      for (double& c : q)
        c += step(rng);
    if (it < 30) // the body deforms, then rests (its facet bounds are kept across builds)
      for (double& c : x)
        c += 0.2 * step(rng);
  }
  EXPECT_GT(contacts, 1000);
  EXPECT_GT(contact.search_rebuilds(), 2);
  EXPECT_LT(contact.search_rebuilds(), 60);
  EXPECT_LT(exact_tests, 60LL * n * static_cast<long long>(facets.size()) / 100);
}

TEST(ContactLaw, HertzNormalForceAndDamping)
{
  ContactMaterial m = mix_materials(1e7, 0.3, 0.0, 0.0, 0.5, 0.4, 1, NormalModel::Hertz, true);
  EXPECT_NEAR(m.Yeff, 1e7 / (1 - 0.09), 1e-6);
  ContactInput in{{0, 0, 1}, 1e-4, 0.01, 0.02, {0, 0, 0}, {0, 0, 0}, 1e-6};
  double shear[3] = {0, 0, 0};
  ContactOutput out = particle_surface_force(m, in, shear);
  EXPECT_NEAR(out.force[2], 4.0 / 3.0 * m.Yeff * std::sqrt(0.01) * std::pow(1e-4, 1.5), 1e-12);
  in.v_rel[2] = -0.5; // approaching: damping adds repulsion
  out = particle_surface_force(m, in, shear);
  const double Sn = 2 * m.Yeff * std::sqrt(0.01 * 1e-4);
  const double le = std::log(0.5), beta = le / std::sqrt(le * le + M_PI * M_PI);
  const double gn = -2 * std::sqrt(5.0 / 6.0) * beta * std::sqrt(Sn * 0.02);
  EXPECT_NEAR(out.force[2], 4.0 / 3.0 * m.Yeff * std::sqrt(0.01) * std::pow(1e-4, 1.5) + gn * 0.5,
              1e-9);
}

TEST(ContactLaw, CoulombCapRescalesHistory)
{
  ContactMaterial m = mix_materials(1e7, 0.3, 1e7, 0.3, 0.9, 0.3, 1, NormalModel::Hertz, true);
  ContactInput in{{0, 0, 1}, 1e-4, 0.01, 0.02, {1.0, 0, 0}, {0, 0, 0}, 1e-3};
  double shear[3] = {0, 0, 0};
  for (int k = 0; k < 20; ++k) {
    ContactOutput out = particle_surface_force(m, in, shear);
    const double ft = std::hypot(out.force[0], out.force[1]);
    EXPECT_LE(ft, 0.3 * std::fabs(out.fn) * (1 + 1e-12));
  }
  const double Kt = 8 * m.Geff * std::sqrt(0.01 * 1e-4);
  EXPECT_NEAR(Kt * std::hypot(shear[0], shear[1]),
              0.3 * 4.0 / 3.0 * m.Yeff * std::sqrt(0.01) * std::pow(1e-4, 1.5), 1e-9);
}

TEST(ContactLaw, SphereOnRigidWallReproducesHertzImpact)
{
  const double E = 1e7, nu = 0.3, R = 0.005, rho = 7800, v0 = 0.3;
  const double mass = rho * 4.0 / 3.0 * M_PI * R * R * R;
  ContactMaterial m = mix_materials(E, nu, 0.0, 0.0, 0.999999, 0.0, 1, NormalModel::Hertz, true);
  HertzImpact ref = hertz_impact(m.Yeff, R, mass, v0);
  double z = R, vz = -v0, fz = 0, peak = 0, t = 0, t_on = -1, t_off = -1;
  const double dt = ref.duration / 20000;
  double shear[3] = {0, 0, 0};
  for (int step = 0; step < 40000; ++step) {
    vz += 0.5 * dt * fz / mass;
    z += dt * vz;
    t += dt;
    fz = 0;
    if (z < R) {
      ContactInput in{{0, 0, 1}, R - z, R, mass, {0, 0, vz}, {0, 0, 0}, dt};
      fz = particle_surface_force(m, in, shear).force[2];
      if (t_on < 0) t_on = t;
      t_off = t;
    }
    peak = std::max(peak, fz);
    vz += 0.5 * dt * fz / mass;
    if (t_off > 0 && z > R + 1e-6) break;
  }
  EXPECT_NEAR(peak, ref.peak_force, 0.005 * ref.peak_force);
  EXPECT_NEAR(t_off - t_on, ref.duration, 0.005 * ref.duration);
  EXPECT_NEAR(vz, v0, 0.01 * v0);
}

TEST(ContactSearch, CandidatesEqualBruteForce)
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0, 1), S(0.001, 0.05);
  std::vector<Aabb> boxes(3000);
  for (Aabb& b : boxes)
    for (int d = 0; d < 3; ++d) {
      b.lo[d] = U(rng);
      b.hi[d] = b.lo[d] + S(rng);
    }
  std::vector<double> sxr(4 * 2000);
  for (int s = 0; s < 2000; ++s) {
    for (int d = 0; d < 3; ++d)
      sxr[4 * s + d] = U(rng);
    sxr[4 * s + 3] = S(rng);
  }
  BufferedSearch search(0.01);
  search.build(boxes, sxr.data(), 2000);
  EXPECT_EQ(search.candidates(), brute_force_candidates(boxes, sxr.data(), 2000, 0.01));
  EXPECT_GT(search.candidates().size(), 100u);
}

TEST(ContactSearch, RebuildCriterionNeverMissesAContact)
{
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> U(0, 1), step(-0.002, 0.002);
  const int nf = 400, ns = 300;
  std::vector<double> nodes(3 * nf), spheres(4 * ns);
  for (auto& v : nodes)
    v = U(rng);
  for (int s = 0; s < ns; ++s) {
    for (int d = 0; d < 3; ++d)
      spheres[4 * s + d] = U(rng);
    spheres[4 * s + 3] = 0.02;
  }
  auto boxes_of = [&]() {
    std::vector<Aabb> b(nf);
    for (int f = 0; f < nf; ++f)
      for (int d = 0; d < 3; ++d)
        b[f].lo[d] = b[f].hi[d] = nodes[3 * f + d]; // point facets
    return b;
  };
  auto centres = [&]() {
    std::vector<double> c(3 * ns);
    for (int s = 0; s < ns; ++s)
      for (int d = 0; d < 3; ++d)
        c[3 * s + d] = spheres[4 * s + d];
    return c;
  };
  BufferedSearch search(0.01);
  int rebuilds = 0;
  for (int it = 0; it < 200; ++it) {
    auto c = centres();
    if (it == 0 || search.needs_rebuild(nodes.data(), nf, c.data(), ns)) {
      search.build(boxes_of(), spheres.data(), ns);
      search.remember_positions(nodes.data(), nf, c.data(), ns);
      ++rebuilds;
    }
    auto touching = brute_force_candidates(boxes_of(), spheres.data(), ns, 0.0);
    const auto& cand = search.candidates();
    for (const auto& p : touching)
      ASSERT_TRUE(std::binary_search(cand.begin(), cand.end(), p)) << "missed at step " << it;
    for (auto& v : nodes)
      v += step(rng);
    for (int s = 0; s < ns; ++s)
      for (int d = 0; d < 3; ++d)
        spheres[4 * s + d] += step(rng);
  }
  EXPECT_LT(rebuilds, 200);
  EXPECT_GT(rebuilds, 1);
}

namespace
{
// All hits of a sphere against the boundary of a flat 4x4 plate (top face z = 0).
std::vector<FacetHit> hits_on_plate(const Mesh& mesh, const std::vector<Facet>& facets,
                                    const double q[3], double r)
{
  std::vector<FacetHit> hits;
  for (int k = 0; k < static_cast<int>(facets.size()); ++k) {
    const Facet& f = facets[k];
    FacetHit h;
    h.facet = k;
    h.nn = 3;
    for (int j = 0; j < 3; ++j)
      h.nodes[j] = f.n[j];
    h.cp = closest_point_triangle(q, &mesh.X[3 * f.n[0]], &mesh.X[3 * f.n[1]], &mesh.X[3 * f.n[2]]);
    if (h.cp.dist2 < r * r) hits.push_back(h);
  }
  return hits;
}
} // namespace

TEST(ContactResolution, FlatSurfaceGivesExactlyOneContactWhateverTheMesh)
{
  Mesh mesh = make_box_tet_mesh(8, 8, 1, 1.0, 1.0, 0.1, {0, 0, -0.1});
  auto facets = boundary_facets(mesh);
  SurfaceTopology topo;
  topo.build(facets, mesh.num_nodes());
  const double r = 0.3; // much larger than the facets: many are within reach
  for (const auto& q : std::vector<std::array<double, 3>>{
           {0.5, 0.5, 0.29}, {0.5, 0.4375, 0.29}, {0.43, 0.61, 0.29}, {0.51, 0.51, 0.29}}) {
    auto hits = hits_on_plate(mesh, facets, q.data(), r);
    ASSERT_GT(hits.size(), 5u);
    auto kept = resolve_sphere_hits(hits, q.data(), mesh.X.data(), topo);
    int n_contacts = 0;
    for (const auto& h : kept)
      n_contacts += 1;
    EXPECT_EQ(n_contacts, 1) << "at " << q[0] << "," << q[1];
    EXPECT_NEAR(std::sqrt(kept[0].cp.dist2), 0.29, 1e-12);
  }
}

TEST(ContactResolution, ConvexRidgeGivesOneEdgeContact)
{
  // two triangles meeting at the ridge y = 0 (x from 0 to 1), sloping down on both sides
  Mesh mesh;
  mesh.dim = 3;
  mesh.X = {0, 0, 0, 1, 0, 0, 0.5, 1, -0.5, 0.5, -1, -0.5};
  std::vector<Facet> facets(2);
  facets[0].n = {0, 1, 2};
  facets[0].nn = 3;
  facets[1].n = {1, 0, 3};
  facets[1].nn = 3;
  SurfaceTopology topo;
  topo.build(facets, 4);
  const double q[3] = {0.5, 0.0, 0.1};
  std::vector<FacetHit> hits;
  for (int k = 0; k < 2; ++k) {
    FacetHit h;
    h.facet = k;
    h.nn = 3;
    for (int j = 0; j < 3; ++j)
      h.nodes[j] = facets[k].n[j];
    h.cp = closest_point_triangle(q, &mesh.X[3 * h.nodes[0]], &mesh.X[3 * h.nodes[1]],
                                  &mesh.X[3 * h.nodes[2]]);
    hits.push_back(h);
  }
  auto kept = resolve_sphere_hits(hits, q, mesh.X.data(), topo);
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(kept[0].cp.kind, Feature::Edge);
  const double normals[6] = {0, 0, 1, 0, 0.1, 0.995}, overlaps[2] = {1e-3, 2e-3};
  auto clusters = cluster_hits(normals, overlaps, 2);
  ASSERT_EQ(clusters.size(), 1u);
  EXPECT_EQ(clusters[0][0], 1); // deepest first
  const double apart[6] = {0, 0, 1, 1, 0, 0};
  EXPECT_EQ(cluster_hits(apart, overlaps, 2).size(), 2u);
  // Like normals on two fragments (a sphere over the crack between them): two contacts.
  const int same_piece[2] = {4, 4}, two_pieces[2] = {4, 9};
  EXPECT_EQ(cluster_hits(normals, overlaps, 2, same_piece).size(), 1u);
  EXPECT_EQ(cluster_hits(normals, overlaps, 2, two_pieces).size(), 2u);
}

namespace
{

// Flat triangulated square z = 0, n x n cells of size h centred at the origin.
void flat_surface(int n, double h, std::vector<double>& x, std::vector<fracdem::Facet>& facets)
{
  x.clear();
  facets.clear();
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      x.push_back((i - n / 2.0) * h);
      x.push_back((j - n / 2.0) * h);
      x.push_back(0.0);
    }
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      fracdem::Facet a{}, b{};
      a.nn = b.nn = 3;
      a.n[0] = id(i, j), a.n[1] = id(i + 1, j), a.n[2] = id(i + 1, j + 1);
      b.n[0] = id(i, j), b.n[1] = id(i + 1, j + 1), b.n[2] = id(i, j + 1);
      facets.push_back(a);
      facets.push_back(b);
    }
}

} // namespace

TEST(ContactSpread, HertzProfileIsContinuousAndDecays)
{
  EXPECT_DOUBLE_EQ(fracdem::hertz_surface_profile(0.0), 1.0);
  EXPECT_NEAR(fracdem::hertz_surface_profile(1.0), 0.5, 1e-12);
  EXPECT_NEAR(fracdem::hertz_surface_profile(1.0 + 1e-9), 0.5, 1e-6);
  // Far field of a point load: u ~ 2 / (pi s) times the centre value's 1/... -> 2/(3 s) / (pi/2)
  const double s = 50.0;
  EXPECT_NEAR(fracdem::hertz_surface_profile(s) * s, 4.0 / (3.0 * M_PI), 1e-3);
}

TEST(ContactSpread, RecoversIndentationUnderRigidOffsetAndSpreadsAboutTheCentre)
{
  const int n = 80;
  const double h = 0.05e-3, R = 5e-3, delta_p = 2e-6, delta_b = 2e-6, u_rigid = 3e-6;
  std::vector<double> x;
  std::vector<fracdem::Facet> facets;
  flat_surface(n, h, x, facets);
  fracdem::SurfaceTopology topo;
  const int nnodes = static_cast<int>(x.size() / 3);
  topo.build(facets, nnodes);
  const double a = std::sqrt(R * (delta_p + delta_b)); // 0.141 mm = 2.8 h
  // Synthetic Hertz displacement field into the body plus a rigid offset.
  std::vector<double> disp(nnodes), area(nnodes, h * h);
  for (int v = 0; v < nnodes; ++v) {
    const double r = std::hypot(x[3 * v], x[3 * v + 1]);
    disp[v] = u_rigid + delta_b * fracdem::hertz_surface_profile(r / a);
  }
  const double c[3] = {0.3 * h, -0.2 * h, 0.0}, nrm[3] = {0, 0, 1};
  const int centre = (n / 2) * (n + 1) + n / 2;
  fracdem::SurfacePatch patch;
  fracdem::gather_surface_patch(topo, x.data(), &centre, 1, c, nrm, 4 * a, patch);
  EXPECT_GT(patch.nodes.size(), 100u);
  const double u_c = u_rigid + delta_b * fracdem::hertz_surface_profile(std::hypot(c[0], c[1]) / a);
  const double got = fracdem::local_indentation(R, delta_p, u_c, disp, patch);
  EXPECT_NEAR(got, delta_b, 0.05 * delta_b); // ring sampled on a mesh of h = a / 2.8

  std::vector<double> w;
  ASSERT_TRUE(fracdem::hertz_pressure_weights(patch, area, a, w));
  double sum = 0, cx = 0, cy = 0;
  for (size_t k = 0; k < w.size(); ++k) {
    sum += w[k];
    cx += w[k] * x[3 * patch.nodes[k]];
    cy += w[k] * x[3 * patch.nodes[k] + 1];
  }
  EXPECT_NEAR(sum, 1.0, 1e-12);
  EXPECT_NEAR(cx, c[0], 0.25 * h); // the pressure centre follows the contact point
  EXPECT_NEAR(cy, c[1], 0.25 * h);
  // An unresolved contact (disc smaller than the mesh) falls back to the point law.
  EXPECT_FALSE(fracdem::hertz_pressure_weights(patch, area, 0.4 * h, w));
  fracdem::SurfacePatch tiny;
  fracdem::gather_surface_patch(topo, x.data(), &centre, 1, c, nrm, 0.5 * h, tiny);
  EXPECT_DOUBLE_EQ(fracdem::local_indentation(R, delta_p, u_c, disp, tiny), 0.0);
}
