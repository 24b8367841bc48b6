// Unit tests of the particle-facet contact pipeline: periodic images, deep dimples, time
// resolution of fast contacts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "contact/granular_law.h"
#include "contact/particle_facet.h"
#include "io/mesh_generators.h"
#include "test_support.h"

using namespace fracdem;
using fracdem_test::OneParticle;

namespace
{

ParticleFacetContact make_contact(const Mesh& mesh, double E = 1e7)
{
  ParticleFacetContact contact;
  ParticleFacetOptions opt;
  opt.buffer = 0.01;
  contact.configure(opt);
  contact.set_materials(
      {ContactMaterial{}, mix_materials(E, 0.3, 0, 0, 0.9, 0.5, 1, NormalModel::Hertz, true)});
  contact.rebuild_surface(mesh);
  return contact;
}

ParticleFacetResult evaluate(ParticleFacetContact& contact, const Mesh& mesh,
                             const std::vector<double>& x, OneParticle& p, double dt = 1e-6)
{
  std::vector<double> fn(3 * mesh.num_nodes(), 0.0), v(3 * mesh.num_nodes(), 0.0);
  ParticleArrays arr = p.arrays();
  return contact.evaluate(arr, mesh.X.data(), x.data(), v.data(), dt, fn.data());
}

} // namespace

TEST(ParticleFacet, PeriodicImageTouchesTheBodyAsTheTranslatedParticleDoes)
{
  // A sphere one period (3 m in x, 2 m in y) away from the top face of a tet box: with those
  // periods its image touches the face with the force of the sphere placed over the face; without
  // them nothing touches.
  const Mesh mesh = make_box_tet_mesh(4, 4, 1, 1.0, 1.0, 0.25);
  const double period[3] = {3.0, 2.0, 0.0};
  OneParticle direct;
  direct.radius = 0.05;
  direct.x[0] = 0.37;
  direct.x[1] = 0.61;
  direct.x[2] = 0.25 + 0.05 - 1e-3;
  auto c1 = make_contact(mesh);
  ASSERT_EQ(evaluate(c1, mesh, mesh.X, direct).contacts, 1);
  for (int sx : {-1, 1})
    for (int sy : {-1, 0, 1}) {
      // (OneParticle points into itself: fresh ones, never copies)
      const double at[3] = {direct.x[0] + sx * period[0], direct.x[1] + sy * period[1],
                            direct.x[2]};
      OneParticle far;
      far.radius = direct.radius;
      std::copy(at, at + 3, far.x);
      auto c2 = make_contact(mesh);
      EXPECT_EQ(evaluate(c2, mesh, mesh.X, far).contacts, 0) << "not periodic: no contact";
      OneParticle image;
      image.radius = direct.radius;
      std::copy(at, at + 3, image.x);
      ParticleArrays arr = image.arrays();
      for (int d = 0; d < 3; ++d)
        arr.period[d] = period[d];
      std::vector<double> fn(3 * mesh.num_nodes(), 0.0), v(3 * mesh.num_nodes(), 0.0);
      auto c3 = make_contact(mesh);
      ASSERT_EQ(c3.evaluate(arr, mesh.X.data(), mesh.X.data(), v.data(), 1e-6, fn.data()).contacts,
                1);
      for (int d = 0; d < 3; ++d)
        EXPECT_NEAR(image.f[d], direct.f[d], 1e-9 * std::fabs(direct.f[2])) << sx << " " << sy;
    }
}

TEST(ParticleFacet, ASphereDeepInItsDimpleIsOneContact)
{
  // The top-face node under the sphere sinks by 0.2 (facets around it tilt by ~39 degrees, their
  // current normals differ by up to ~78): still one surface region, so one contact (grouping by
  // the current normals gave two and doubled the force).
  const Mesh mesh = make_box_tet_mesh(4, 4, 1, 1.0, 1.0, 0.25);
  std::vector<double> x = mesh.X;
  int centre = -1;
  for (int n = 0; n < mesh.num_nodes(); ++n)
    if (std::fabs(x[3 * n] - 0.5) < 1e-12 && std::fabs(x[3 * n + 1] - 0.5) < 1e-12 &&
        std::fabs(x[3 * n + 2] - 0.25) < 1e-12)
      centre = n;
  ASSERT_GE(centre, 0);
  x[3 * centre + 2] -= 0.2;
  OneParticle p;
  p.radius = 0.3;
  p.x[0] = 0.5;
  p.x[1] = 0.5;
  p.x[2] = 0.05 + 0.3 - 0.02;
  auto contact = make_contact(mesh);
  EXPECT_EQ(evaluate(contact, mesh, x, p).contacts, 1);
}

TEST(ParticleFacet, AFastApproachIsFlaggedWithTheTimeStepThatResolvesIt)
{
  // A sphere approaching at v: the step resolves the contact when v dt <= 0.3 delta_max(v).
  const Mesh mesh = make_box_tet_mesh(4, 4, 1, 1.0, 1.0, 0.25);
  const double E = 1e7, nu = 0.3, v = 5.0;
  OneParticle p;
  p.radius = 0.05;
  p.mass = 2500 * 4.0 / 3.0 * M_PI * std::pow(p.radius, 3);
  p.x[0] = 0.37;
  p.x[1] = 0.61;
  p.x[2] = 0.25 + 0.05 - 1e-4;
  p.v[2] = -v;
  const double dmax = hertz_impact(E / (1 - nu * nu), p.radius, p.mass, v).max_overlap;
  const double dt_ok = kMaxApproachPerStep * dmax / v;
  auto c1 = make_contact(mesh, E);
  const ParticleFacetResult fine = evaluate(c1, mesh, mesh.X, p, 0.9 * dt_ok);
  EXPECT_EQ(fine.unresolved_speed, 0.0);
  auto c2 = make_contact(mesh, E);
  const ParticleFacetResult coarse = evaluate(c2, mesh, mesh.X, p, 1.1 * dt_ok);
  EXPECT_NEAR(coarse.unresolved_speed, v, 1e-12 * v);
  EXPECT_NEAR(coarse.resolving_dt, dt_ok, 1e-9 * dt_ok);
}

TEST(ParticleFacet, ContactDampsTheReducedMassOfParticleAndSurfacePoint)
{
  // A sphere approaching a node of the top face: the dashpot force (force at speed v minus force
  // at rest) goes with sqrt(m_eff). A rigid surface (no masses) or infinitely heavy nodes: the
  // particle's mass; nodes as heavy as the particle: m_eff = m / 2.
  const Mesh mesh = make_box_tet_mesh(4, 4, 1, 1.0, 1.0, 0.25);
  auto dashpot = [&](const double* node_mass) {
    double f[2];
    for (int moving = 0; moving < 2; ++moving) {
      auto contact = make_contact(mesh);
      contact.set_node_masses(node_mass);
      OneParticle p;
      p.radius = 0.05;
      p.mass = 0.7;
      p.x[0] = 0.5;
      p.x[1] = 0.5;
      p.x[2] = 0.25 + 0.05 - 1e-3;
      p.v[2] = moving ? -1.0 : 0.0;
      evaluate(contact, mesh, mesh.X, p);
      f[moving] = p.f[2];
    }
    return f[1] - f[0];
  };
  const double rigid = dashpot(nullptr);
  ASSERT_GT(rigid, 0.0);
  const std::vector<double> heavy(mesh.num_nodes(), 1e15), equal(mesh.num_nodes(), 0.7);
  EXPECT_NEAR(dashpot(heavy.data()), rigid, 1e-6 * rigid);
  EXPECT_NEAR(dashpot(equal.data()), rigid * std::sqrt(0.5), 1e-9 * rigid);
}
