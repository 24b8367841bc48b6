// Unit tests of the core FE body (update, conditions, node split, restart state) and of the
// particle-facet contact pipeline that couples it to particles.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "contact/particle_facet.h"
#include "fem/body.h"
#include "fracture/nodal_fracture.h"
#include "io/mesh_generators.h"
#include "test_support.h"

using namespace fracdem;

namespace
{

using fracdem_test::steel;

// Sum over nodes of mass (d = -1) or of mass * velocity component d.
double total(const Body& b, int d)
{
  double s = 0;
  for (int n = 0; n < b.num_nodes(); ++n)
    s += b.masses()[n] * (d < 0 ? 1.0 : b.velocities()[3 * n + d]);
  return s;
}

// A body with a random velocity field and its internal forces evaluated.
Body shaken_body(ElemType type)
{
  Body b;
  Mesh m = type == ElemType::Tet4 ? make_box_tet_mesh(3, 2, 2, 0.3, 0.2, 0.2)
                                  : make_rect_mesh(4, 3, 0.4, 0.3, {0, 0}, type);
  b.build(std::move(m), steel(), false);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n = 0; n < b.num_nodes(); ++n) {
    const double v[3] = {u(rng), u(rng), type == ElemType::Tet4 ? u(rng) : 0.0};
    b.set_velocity({n}, v);
  }
  b.half_kick_drift(1e-7);
  b.begin_forces();
  const double g[3] = {0, 0, 0};
  int inv = -1;
  b.finish_forces(b.add_internal_forces(&inv), g, 1e-7, true);
  return b;
}

} // namespace

TEST(Body, VelocityVerletStepMatchesHandComputation)
{
  // One free node of known mass under a constant force: v += f dt / (2m), x += v dt.
  Body b;
  b.build(make_rect_mesh(1, 1, 1.0, 1.0, {0, 0}, ElemType::Quad4), steel(), false);
  const double v0[3] = {1.0, -2.0, 0.0};
  b.set_velocity({2}, v0);
  b.begin_forces();
  b.contact_forces()[3 * 2 + 0] = 3.0; // a contact force only (no strain yet)
  const double g[3] = {0, 0, 0};
  int inv = -1;
  b.finish_forces(b.add_internal_forces(&inv), g, 0.1, true);
  const double m = b.masses()[2], dt = 1e-3;
  const double x0 = b.positions()[6];
  b.half_kick_drift(dt);
  const double vh = 1.0 + 0.5 * dt * 3.0 / m;
  EXPECT_DOUBLE_EQ(b.velocities()[6], vh);
  EXPECT_DOUBLE_EQ(b.positions()[6], x0 + dt * vh);
  EXPECT_DOUBLE_EQ(b.velocities()[7], -2.0);
}

TEST(Body, FixedAndPrescribedNodesFollowTheirConditions)
{
  Body b;
  b.build(make_rect_mesh(2, 1, 2.0, 1.0, {0, 0}, ElemType::Tri3), steel(), false);
  const double vp[3] = {0.5, 0, 0}, vi[3] = {9, 9, 0};
  b.set_velocity({0, 1, 2}, vi);
  b.set_fixed({0});
  b.set_prescribed_velocity({1}, vp);
  b.impose_velocity_conditions();
  const double x0 = b.positions()[0], x1 = b.positions()[3];
  for (int s = 0; s < 10; ++s) {
    b.half_kick_drift(1e-6);
    b.begin_forces();
    const double g[3] = {0, -9.81, 0};
    int inv = -1;
    b.finish_forces(b.add_internal_forces(&inv), g, 1e-6, true);
    b.half_kick(1e-6);
  }
  EXPECT_EQ(b.positions()[0], x0);                            // held
  EXPECT_NEAR(b.positions()[3], x1 + 10 * 1e-6 * 0.5, 1e-15); // prescribed
  EXPECT_EQ(b.forces()[0], 0.0);                              // no force on held nodes
  EXPECT_NE(b.velocities()[3 * 2], 9.0);                      // free node moved by forces
}

// A prescribed velocity with a NULL component (mask): the given component moves at its ramped
// velocity, the NULL one is free (kicked by the force; no reaction for the group) or, where
// `fixed` holds it, stays held; a later `velocity` with a component left out keeps it.
TEST(Body, PrescribedVelocityWithAFreeComponent)
{
  Body b;
  b.build(make_rect_mesh(2, 1, 2.0, 1.0, {0, 0}, ElemType::Tri3), steel(), false);
  const double vp[3] = {0.5, 0, 0}, vi[3] = {0, 3, 0}, vx[3] = {2, 0, 0};
  b.set_velocity({0, 1, 2, 3, 4, 5}, vi);
  b.set_velocity({0, 1, 2, 3, 4, 5}, vx, 1); // x only: vy = 3 kept
  EXPECT_EQ(b.velocities()[3 * 5 + 0], 2.0);
  EXPECT_EQ(b.velocities()[3 * 5 + 1], 3.0);
  b.set_fixed({0}, 2, 0);                            // node 0 held in y (group 0)
  b.set_prescribed_velocity({0, 2}, vp, 4e-6, 1, 1); // x prescribed, ramp 4 steps (group 1)
  b.impose_velocity_conditions();
  const double x0[3] = {b.positions()[0], b.positions()[1], b.positions()[6]};
  const double y2 = b.positions()[7];
  const double g[3] = {0, -9.81, 0};
  double rx = 0;
  for (int s = 0; s < 10; ++s) {
    b.advance_time(1e-6); // as the driver does: the step's end time, then the drift
    b.half_kick_drift(1e-6);
    b.begin_forces();
    int inv = -1;
    b.finish_forces(b.add_internal_forces(&inv), g, 1e-6, true);
    b.half_kick(1e-6);
    rx = std::max(rx, std::abs(b.reactions()[3]));
    EXPECT_EQ(b.reactions()[4], 0.0); // group 1 holds no y
  }
  // x: the ramp's mid-step velocities 0.5 (k + 0.5) / 4 for the first 4 steps, then 0.5.
  const double dx = 1e-6 * (0.5 * (0.5 + 1.5 + 2.5 + 3.5) / 4 + 6 * 0.5);
  EXPECT_NEAR(b.positions()[0], x0[0] + dx, 1e-15);
  EXPECT_NEAR(b.positions()[6], x0[2] + dx, 1e-15);
  EXPECT_EQ(b.positions()[1], x0[1]);       // node 0: y held by `fixed`
  EXPECT_NE(b.positions()[7], y2);           // node 2: y free, moved
  EXPECT_NE(b.velocities()[3 * 2 + 1], 0.0); // and kicked by the forces and gravity
  EXPECT_EQ(b.velocities()[3 * 2 + 0], 0.5); // x at its prescribed velocity
  EXPECT_GT(rx, 0.0);                        // the held x component reports its reaction
}

class BodySplit : public ::testing::TestWithParam<ElemType>
{
};

TEST_P(BodySplit, ConservesMassMomentumAndForce)
{
  Body b = shaken_body(GetParam());
  const double m0 = total(b, -1), px = total(b, 0), py = total(b, 1);
  double f0[3] = {0, 0, 0};
  for (int n = 0; n < b.num_nodes(); ++n)
    for (int d = 0; d < 3; ++d)
      f0[d] += b.forces()[3 * n + d];
  // Split an interior node: the elements whose centroid lies at larger x get the copy.
  const Mesh& mesh = b.mesh();
  int node = -1;
  for (int n = 0; n < b.num_nodes() && node < 0; ++n) {
    int count = 0;
    for (int e = 0; e < mesh.num_elems(); ++e)
      for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
        count += mesh.conn[e][a] == n;
    if (count >= (GetParam() == ElemType::Tet4 ? 12 : 4)) node = n;
  }
  ASSERT_GE(node, 0);
  const double normal[3] = {1, 0, 0};
  const SplitPlan plan = b.plan_split(node, normal);
  ASSERT_TRUE(plan.splittable());
  const std::vector<int>& right = plan.side_b;
  ASSERT_FALSE(right.empty());
  const double m_node = b.masses()[node];
  const int copy = b.split_node(plan);
  EXPECT_EQ(copy, b.num_nodes() - 1);
  EXPECT_EQ(b.parents()[copy], node);
  EXPECT_GT(b.masses()[copy], 0.0);
  EXPECT_LT(b.masses()[copy], m_node);
  // Sums unchanged to round-off (relative 1e-14).
  EXPECT_NEAR(total(b, -1), m0, 1e-14 * m0);
  EXPECT_NEAR(total(b, 0), px, 1e-14 * std::fabs(m0));
  EXPECT_NEAR(total(b, 1), py, 1e-14 * std::fabs(m0));
  double f1[3] = {0, 0, 0};
  for (int n = 0; n < b.num_nodes(); ++n)
    for (int d = 0; d < 3; ++d)
      f1[d] += b.forces()[3 * n + d];
  const double fscale = std::fabs(b.forces()[3 * node]) + std::fabs(b.forces()[3 * copy]) + 1;
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(f1[d], f0[d], 1e-12 * fscale);
  // Both halves keep the node's acceleration.
  EXPECT_NEAR(b.forces()[3 * node] / b.masses()[node], b.forces()[3 * copy] / b.masses()[copy],
              1e-12 * std::fabs(b.forces()[3 * copy] / b.masses()[copy]) + 1e-300);
  // The copy's elements use it; none uses both.
  for (int e : right) {
    bool uses_copy = false;
    for (int c : b.mesh().conn[e])
      uses_copy |= c == copy;
    EXPECT_TRUE(uses_copy);
  }
}

INSTANTIATE_TEST_SUITE_P(Elements, BodySplit,
                         ::testing::Values(ElemType::Tri3, ElemType::Quad4, ElemType::Tet4));

TEST(Body, RestartStateRestoresSplitTopologyExactly)
{
  Body a = shaken_body(ElemType::Tri3);
  a.advance_time(0.25);
  const double normal[3] = {1, 0, 0};
  const int copy = a.split_node(a.plan_split(6, normal));
  a.erode({2});
  std::vector<double> buf;
  a.pack_state(buf);
  // A fresh body from the same mesh file, then the record.
  Body b;
  b.build(make_rect_mesh(4, 3, 0.4, 0.3, {0, 0}, ElemType::Tri3), steel(), false);
  b.unpack_state(buf.data());
  ASSERT_EQ(b.num_nodes(), a.num_nodes());
  EXPECT_EQ(b.parents()[copy], 6);
  EXPECT_EQ(b.mesh().conn, a.mesh().conn);
  EXPECT_EQ(b.mesh().active, a.mesh().active);
  EXPECT_EQ(b.mesh().X, a.mesh().X);
  EXPECT_EQ(b.positions(), a.positions());
  EXPECT_EQ(b.velocities(), a.velocities());
  EXPECT_EQ(b.masses(), a.masses());
  EXPECT_EQ(b.time(), a.time());
  // A record for another mesh is refused.
  Body c;
  c.build(make_rect_mesh(2, 2, 0.4, 0.3, {0, 0}, ElemType::Tri3), steel(), false);
  EXPECT_THROW(c.unpack_state(buf.data()), std::runtime_error);
}

TEST(Body, MemoryBytesGrowsLinearlyWithTheElementCount)
{
  // Meshes of 6 n^3 tets: the bytes per element settle to a constant (the body is a few
  // hundred bytes per element, whatever its size), well above the bare connectivity.
  std::vector<double> per_elem;
  for (int n : {4, 8, 16}) {
    Body b;
    b.build(make_box_tet_mesh(n, n, n, 1.0, 1.0, 1.0), steel(), false);
    per_elem.push_back(static_cast<double>(b.memory_bytes()) / b.mesh().num_elems());
  }
  EXPECT_GT(per_elem[2], 16.0 * sizeof(double)); // more than 16 doubles per element
  EXPECT_LT(per_elem[2], 1000.0);                // and a few hundred bytes at most
  EXPECT_NEAR(per_elem[1] / per_elem[2], 1.0, 0.15);
  // A split node adds a row to every nodal array: the count follows.
  Body a = shaken_body(ElemType::Tri3);
  const std::size_t before = a.memory_bytes();
  const double normal[3] = {1, 0, 0};
  a.split_node(a.plan_split(6, normal));
  EXPECT_GT(a.memory_bytes(), before);
}

TEST(BodyMotion, ZeroRotationAxisIsRefusedNotTurnedIntoNaN)
{
  const double zero[3] = {0, 0, 0}, z[3] = {0, 0, 2}, nan[3] = {0, NAN, 1};
  EXPECT_FALSE(valid_axis(zero));
  EXPECT_FALSE(valid_axis(nan));
  EXPECT_TRUE(valid_axis(z));
  Mesh m = make_box_tet_mesh(1, 1, 1, 1.0, 1.0, 1.0);
  MeshTransform rot{MeshTransform::Rotate, {0, 0, 0, 0.5}};
  EXPECT_THROW(apply_transforms(m, {rot}), std::invalid_argument);
  for (double c : m.X)
    EXPECT_TRUE(std::isfinite(c));
  rot.a[2] = 1; // about z: a valid rotation keeps z
  EXPECT_TRUE(apply_transforms(m, {rot}));
}

/* ---------------------------------------------------------------------- */

using fracdem_test::OneParticle;

TEST(ParticleFacet, SphereOnAMeshedPlaneGetsOneHertzContactAndBalancedReactions)
{
  // A sphere resting (no velocity) with overlap delta on the top face of a tet box: whatever
  // facet, edge or vertex lies under it, one contact with Hertz's force 4/3 E* sqrt(R) delta^1.5
  // (granular_law with a rigid surface: E* from the particle alone), and the nodal reactions
  // sum to minus the particle force (momentum balance).
  const Mesh mesh = make_box_tet_mesh(4, 4, 1, 1.0, 1.0, 0.25);
  ParticleFacetContact contact;
  ParticleFacetOptions opt;
  opt.buffer = 0.01;
  contact.configure(opt);
  const double E = 1e7, nu = 0.3;
  contact.set_materials(
      {ContactMaterial{}, mix_materials(E, nu, 0, 0, 0.9, 0.5, 1, NormalModel::Hertz, true)});
  contact.rebuild_surface(mesh);
  const double Estar = E / (1 - nu * nu);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.1, 0.9);
  for (int trial = 0; trial < 40; ++trial) {
    OneParticle p;
    p.radius = 0.05;
    const double delta = 1e-3;
    // Every 4th trial exactly above a mesh vertex / edge, the rest anywhere.
    p.x[0] = trial % 4 ? u(rng) : 0.25 * (1 + trial % 3);
    p.x[1] = trial % 4 ? u(rng) : 0.5;
    p.x[2] = 0.25 + p.radius - delta;
    std::vector<double> fn(3 * mesh.num_nodes(), 0.0);
    ParticleArrays arr = p.arrays();
    contact.invalidate_search();
    const ParticleFacetResult res =
        contact.evaluate(arr, mesh.X.data(), mesh.X.data(),
                         std::vector<double>(3 * mesh.num_nodes(), 0.0).data(), 1e-6, fn.data());
    ASSERT_EQ(res.contacts, 1) << "trial " << trial;
    const double hertz = 4.0 / 3.0 * Estar * std::sqrt(p.radius * delta) * delta;
    EXPECT_NEAR(p.f[2], hertz, 1e-9 * hertz) << "trial " << trial;
    EXPECT_NEAR(p.f[0], 0.0, 1e-9 * hertz);
    double sum[3] = {0, 0, 0};
    for (int n = 0; n < mesh.num_nodes(); ++n)
      for (int d = 0; d < 3; ++d)
        sum[d] += fn[3 * n + d];
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(sum[d], -p.f[d], 1e-12 * hertz);
  }
}

namespace
{

// A quad4 strip 1 x 0.25 whose surface a particle touches (Hertz, tangential history, friction
// 0.5), and a particle pressed 1 mm into its top edge, sliding along it at 0.3 m/s (OneParticle
// points into itself: set in place, not copied).
Mesh strip_mesh()
{
  return make_rect_mesh(8, 2, 1.0, 0.25, {0, 0}, ElemType::Quad4);
}
void configure_strip(const Mesh& mesh, ParticleFacetContact& contact)
{
  ParticleFacetOptions opt;
  opt.buffer = 0.02;
  contact.configure(opt);
  contact.set_materials(
      {ContactMaterial{}, mix_materials(1e7, 0.3, 0, 0, 0.9, 0.5, 1, NormalModel::Hertz, true)});
  contact.rebuild_surface(mesh);
}
void place_sliding(OneParticle& p)
{
  p.radius = 0.05;
  p.x[0] = 0.51;
  p.x[1] = 0.25 + 0.049;
  p.x[2] = 0;
  p.v[0] = 0.3;
}

} // namespace

TEST(ParticleFacet, ChecksEqualCandidatesAndHistoryEndsWithTheContact)
{
  const Mesh mesh = strip_mesh();
  ParticleFacetContact contact;
  configure_strip(mesh, contact);
  OneParticle p;
  place_sliding(p);
  const std::vector<double> zero(3 * mesh.num_nodes(), 0.0);
  std::vector<double> fn(3 * mesh.num_nodes(), 0.0);
  ParticleArrays arr = p.arrays();
  ParticleFacetResult res =
      contact.evaluate(arr, mesh.X.data(), mesh.X.data(), zero.data(), 1e-4, fn.data());
  EXPECT_EQ(res.contacts, 1);
  EXPECT_GT(contact.checks()[0], 0);
  int used = 0;
  for (int k = 0; k < 4; ++k)
    used += p.hist[k * kHistorySlotDoubles] >= 0;
  EXPECT_EQ(used, 1);
  // Lift the particle off: the history record is freed.
  p.x[1] = 0.25 + 0.06;
  res = contact.evaluate(arr, mesh.X.data(), mesh.X.data(), zero.data(), 1e-4, fn.data());
  EXPECT_EQ(res.contacts, 0);
  for (int k = 0; k < 4; ++k)
    EXPECT_LT(p.hist[k * kHistorySlotDoubles], 0);
}

// The host's set-up evaluation (hold_history) reads the tangential springs but does not grow them,
// as the host's granular pairs and walls do in set-up: a sliding contact evaluated, held, then
// evaluated again has the springs of two evaluations, bit for bit (a split run goes on as one).
TEST(ParticleFacet, HeldEvaluationReadsTheTangentialHistoryWithoutGrowingIt)
{
  const Mesh mesh = strip_mesh();
  ParticleFacetContact contact;
  configure_strip(mesh, contact);
  const std::vector<double> zero(3 * mesh.num_nodes(), 0.0);
  auto slide = [&](bool held_between) {
    OneParticle p;
    place_sliding(p); // the spring grows by v dt per counted evaluation
    ParticleArrays arr = p.arrays();
    std::vector<double> fn(3 * mesh.num_nodes(), 0.0);
    contact.invalidate_search();
    contact.evaluate(arr, mesh.X.data(), mesh.X.data(), zero.data(), 1e-4, fn.data());
    if (held_between) {
      const std::vector<double> once = p.hist;
      p.f[0] = 0;
      contact.hold_history(true);
      contact.evaluate(arr, mesh.X.data(), mesh.X.data(), zero.data(), 1e-4, fn.data());
      contact.hold_history(false);
      EXPECT_EQ(p.hist, once);
      EXPECT_LT(p.f[0], 0.0); // the held spring (and the damping) resist the sliding
    }
    contact.evaluate(arr, mesh.X.data(), mesh.X.data(), zero.data(), 1e-4, fn.data());
    return p.hist;
  };
  const std::vector<double> straight = slide(false);
  EXPECT_EQ(slide(true), straight);
  double spring = 0;
  for (int k = 0; k < 4; ++k)
    if (straight[k * kHistorySlotDoubles] >= 0) spring = straight[k * kHistorySlotDoubles + 2];
  EXPECT_NEAR(spring, 2 * 0.3 * 1e-4, 1e-12); // two counted evaluations grew it by v dt each
}

TEST(ParticleFacet, HistorySlotsFindCreateAndReportExhaustion)
{
  std::vector<double> row(2 * kHistorySlotDoubles);
  clear_history_row(row.data(), 2);
  bool full = false;
  double* a = history_slot(row.data(), 2, 0x123456789ull, true, &full);
  double* b = history_slot(row.data(), 2, 42, true, &full);
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  EXPECT_NE(a, b);
  EXPECT_EQ(history_slot(row.data(), 2, 0x123456789ull, false, &full), a);
  EXPECT_FALSE(full);
  EXPECT_EQ(history_slot(row.data(), 2, 7, true, &full), nullptr);
  EXPECT_TRUE(full);
}

TEST(NodalFracture, FragmentMassesSumToTheBodyAndSplitAlongACutColumn)
{
  // A 4 x 2 quad strip cut through every node of the column x = 0.5 (normal x) comes apart in
  // two pieces of equal mass, and the masses add up to the body's (round-off).
  Body b;
  b.build(make_rect_mesh(4, 2, 1.0, 0.5, {0, 0}, ElemType::Quad4), steel(), false);
  const double total = std::accumulate(b.masses().begin(), b.masses().end(), 0.0);
  const double normal[3] = {1, 0, 0};
  for (int j = 0; j <= 2; ++j)
    b.split_node(b.plan_split(2 + 5 * j, normal));
  const std::vector<double> m = fragment_masses(b);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_NEAR(m[0], 0.5 * total, 1e-12 * total);
  EXPECT_NEAR(m[0] + m[1], total, 1e-12 * total);
}

// A row of nx concrete quads (0.01 m each) stretched along x by strain k between x0 and x1 (the
// quads outside move rigidly) in one drift, then back by k - k_back, their forces (and so their
// material state) evaluated; then the bottom middle node split with normal x: the crack runs up
// the middle edge and the top middle node, never split, holds the two halves together alone
// (pinched).
static Body pinched_row(int nx, double k, double k_back, double x0, double x1)
{
  Material m;
  m.E = 3e10;
  m.nu = 0.2;
  m.rho = 2400;
  m.model = MaterialModel::Rankine;
  m.ft = 3e6;
  m.gf = 100;
  Body b;
  b.build(make_rect_mesh(nx, 1, 0.01 * nx, 0.01, {0, 0}, ElemType::Quad4), m, false);
  const double dt = 1e-7, g[3] = {0, 0, 0};
  for (const double strain : {k, k_back - k}) { // to k, then back by k - k_back
    for (int n = 0; n < b.num_nodes(); ++n) {
      const double stretched = std::min(std::max(b.mesh().X[3 * n] - x0, 0.0), x1 - x0);
      const double v[3] = {strain / dt * stretched, 0, 0};
      b.set_velocity({n}, v);
    }
    b.begin_forces(); // no force: the drift is x += dt v exactly
    b.half_kick_drift(dt);
    b.begin_forces();
    int inverted = -1;
    b.finish_forces(b.add_internal_forces(&inverted), g, dt, true);
  }
  const double normal[3] = {1, 0, 0};
  b.split_node(b.plan_split(nx / 2, normal));
  return b;
}

// Two quads side by side (x in [0, 0.02]) stretched uniformly: node 4 is pinched.
static Body pinched_pair(double k, double k_back) { return pinched_row(2, k, k_back, 0, 0.02); }

// A joint has no material area: like a contact it carries compression, and of tension only what
// the material across its opened facets could carry (none once it has failed completely).
TEST(NodalFracture, PinchedNodeHoldsWhileItsSidesPressOrItsMaterialHoldsAndGoesAcrossFailure)
{
  // Squeezed (-3 f_t / E: intact, the quads pressing on each other through the node), the
  // pinched node is kept (one fragment). Stretched below the peak (0.5 f_t / E: intact) or past
  // it (3 f_t / E: both softening), the material across the opened edge could still carry f_t
  // over it: kept too.
  const double eps_t = 3e6 / 3e10;
  double n[3];
  for (const double k : {-3 * eps_t, 0.5 * eps_t, 3 * eps_t}) {
    Body pair = pinched_pair(k, k);
    ASSERT_TRUE(pair.plan_separation(4).splittable());
    EXPECT_LT(pair.element_failure(0, n), 1.0);
    EXPECT_TRUE(insert_cracks(pair, {}, 0.0).empty()) << "strain " << k / eps_t << " f_t / E";
    EXPECT_EQ(fragment_masses(pair).size(), 1u);
  }
  // Four quads whose middle two are stretched until they fail completely (100 f_t / E, past the
  // softening law's end 2 G_f / (f_t h) = 67 f_t / E) while the outer two move rigidly: the
  // node joins two halves of one failed and one intact quad each across failed material, so it
  // is separated (logged with a zero normal) and the row falls in two of equal mass.
  Body row = pinched_row(4, 100 * eps_t, 100 * eps_t, 0.01, 0.03);
  EXPECT_EQ(row.element_failure(1, n), 1.0);
  EXPECT_EQ(row.element_failure(0, n), 0.0);
  const std::vector<SplitEvent> events = insert_cracks(row, {}, 0.0);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].node, 7);
  EXPECT_EQ(events[0].normal[0], 0.0);
  const std::vector<double> m = fragment_masses(row);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_NEAR(m[0], m[1], 1e-12 * m[0]);
}

// The face-connected pieces kept between checks (FacePieces: taken again only when the
// topology changed, and carried over the nodes parted at the end of a check) are those a fresh
// walk finds, after each split of a crack across a quad strip and after the pinched node of a
// failed row is parted (brute-force reference).
static void expect_fresh_pieces(const Body& b, const FacePieces& kept, const char* when)
{
  FacePieces fresh;
  face_pieces(b, fresh);
  EXPECT_EQ(kept.piece, fresh.piece) << when;
  EXPECT_EQ(kept.start, fresh.start) << when;
  EXPECT_EQ(kept.elems, fresh.elems) << when;
  EXPECT_EQ(kept.size, fresh.size) << when;
  EXPECT_EQ(kept.joint_nodes, fresh.joint_nodes) << when;
}

TEST(NodalFracture, FacePiecesKeptBetweenChecksAreAFreshWalks)
{
  Body b;
  b.build(make_rect_mesh(4, 2, 1.0, 0.5, {0, 0}, ElemType::Quad4), steel(), false);
  FacePieces kept;
  insert_cracks(b, {}, 0.0, nullptr, &kept);
  expect_fresh_pieces(b, face_pieces(b, kept), "intact");
  EXPECT_EQ(kept.count(), 1);
  const double normal[3] = {1, 0, 0};
  for (int j = 0; j <= 1; ++j) { // up the column x = 0.5; the top node 12 is pinched, then
    b.split_node(b.plan_split(2 + 5 * j, normal)); // parted (no tension, no strength: steel)
    insert_cracks(b, {}, 0.0, nullptr, &kept);
    expect_fresh_pieces(b, face_pieces(b, kept), "after a split");
  }
  EXPECT_EQ(kept.count(), 2);
  EXPECT_TRUE(kept.joint_nodes.empty());
  EXPECT_EQ(fragment_masses(b).size(), 2u);

  const double eps_t = 3e6 / 3e10;
  Body row = pinched_row(4, 100 * eps_t, 100 * eps_t, 0.01, 0.03);
  FacePieces before;
  EXPECT_TRUE(pieces_touch_at_nodes(row, before)); // the halves at node 7
  FacePieces row_kept;
  ASSERT_EQ(insert_cracks(row, {}, 0.0, nullptr, &row_kept).size(), 1u); // node 7 parted
  expect_fresh_pieces(row, face_pieces(row, row_kept), "after parting");
  EXPECT_TRUE(row_kept.joint_nodes.empty()); // the two halves touch nowhere now
  EXPECT_FALSE(pieces_touch_at_nodes(row, before)); // taken again: a node was parted
}

// A node held in x by one group and in y by another reports each component's reaction to the
// group that holds it (it reported both to the group set last), and a split copy keeps that.
TEST(Body, ReactionOfEachHeldComponentGoesToItsOwnGroup)
{
  Body b;
  b.build(make_rect_mesh(2, 2, 0.2, 0.2, {0, 0}, ElemType::Quad4), steel(), false);
  const Mesh& m = b.mesh();
  b.set_fixed(m.node_sets.at("xmin"), 1, 0); // x held, group 0
  b.set_fixed(m.node_sets.at("ymin"), 2, 1); // y held, group 1; node 0 is in both
  // Stretch the body so that the held nodes carry reactions in both directions.
  const double v[3] = {1.0, 1.0, 0.0};
  for (int n = 0; n < b.num_nodes(); ++n) {
    const double vn[3] = {v[0] * m.X[3 * n], v[1] * m.X[3 * n + 1], 0.0};
    b.set_velocity({n}, vn);
  }
  b.impose_velocity_conditions();
  const double g[3] = {0, 0, 0};
  b.half_kick_drift(1e-5);
  b.begin_forces();
  int inv = -1;
  const std::vector<double> f_before = [&] {
    b.add_internal_forces(&inv);
    return b.forces();
  }();
  b.finish_forces(0.0, g, 1e-5, true);
  // Independent sums: group 0 = minus the x forces on xmin nodes, group 1 = minus the y forces on
  // ymin nodes (all held nodes are at rest: no prescribed motion).
  double want[2] = {0, 0};
  for (int n : m.node_sets.at("xmin"))
    want[0] -= f_before[3 * n];
  for (int n : m.node_sets.at("ymin"))
    want[1] -= f_before[3 * n + 1];
  const std::vector<double>& r = b.reactions();
  ASSERT_GE(r.size(), 6u);
  EXPECT_GT(std::abs(want[0]), 0.0);
  EXPECT_GT(std::abs(want[1]), 0.0);
  EXPECT_NEAR(r[0], want[0], 1e-9 * std::abs(want[0])); // group 0, x
  EXPECT_EQ(r[1], 0.0);                                 // group 0 holds no y
  EXPECT_EQ(r[3], 0.0);                                 // group 1 holds no x
  EXPECT_NEAR(r[4], want[1], 1e-9 * std::abs(want[1])); // group 1, y
}
