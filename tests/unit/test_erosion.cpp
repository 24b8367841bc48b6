// Unit tests of element erosion (criteria, selection, mass / momentum / energy accounts, free
// nodes, restart) and of the axis shield of axisymmetric bodies.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "fem/body.h"
#include "fem/erosion.h"
#include "io/mesh_generators.h"
#include "materials/material_table.h"

using namespace fracdem;

namespace
{

Material material(const std::vector<std::string>& words)
{
  Material m;
  m.E = 2e11;
  m.nu = 0.3;
  m.rho = 7800;
  if (!words.empty()) EXPECT_EQ(parse_material_arguments(words, m), "");
  return m;
}

const std::vector<std::string> kJ2 = {"j2", "yield", "5e8", "hardening", "2e9"};
const std::vector<std::string> kRankine = {"rankine", "strength", "3e6", "fracture_energy", "100"};

double centroid_x(const Body& b, int e)
{
  double c = 0;
  for (int a = 0; a < 4; ++a)
    c += 0.25 * b.mesh().X[3 * b.mesh().conn[e][a]];
  return c;
}

void evaluate_forces(Body& b, double dt)
{
  b.begin_forces();
  int inverted = -1;
  const double g[3] = {0, 0, 0};
  b.finish_forces(b.add_internal_forces(&inverted), g, dt, true);
}

// A 4 x 1 x 1-cell bar (x in [0, 0.04]) whose half x > 0.02 is stretched (k > 0) or compressed
// (k < 0) along x by strain k in one drift; the half x < 0.02 is not strained.
Body kinked_bar(const Material& m, double k)
{
  Body b;
  b.build(make_box_tet_mesh(4, 1, 1, 0.04, 0.01, 0.01), m, false);
  const double dt = 1e-7;
  for (int n = 0; n < b.num_nodes(); ++n) {
    const double v[3] = {k / dt * std::max(0.0, b.mesh().X[3 * n] - 0.02), 0, 0};
    b.set_velocity({n}, v);
  }
  b.half_kick_drift(dt); // no force yet: x += dt v
  evaluate_forces(b, dt);
  return b;
}

// The elements of the strained half: those whose centroid lies beyond x = 0.02.
std::vector<int> strained_half(const Body& b)
{
  std::vector<int> out;
  for (int e = 0; e < b.mesh().num_elems(); ++e)
    if (centroid_x(b, e) > 0.02) out.push_back(e);
  return out;
}

// A tet block with random velocities and its forces evaluated.
Body shaken_block()
{
  Body b;
  b.build(make_box_tet_mesh(3, 2, 2, 0.03, 0.02, 0.02), material({}), false);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n = 0; n < b.num_nodes(); ++n) {
    const double v[3] = {u(rng), u(rng), u(rng)};
    b.set_velocity({n}, v);
  }
  b.half_kick_drift(1e-6);
  evaluate_forces(b, 1e-6);
  return b;
}

double total_mass(const Body& b)
{
  double m = 0;
  for (double mi : b.masses())
    m += mi;
  return m;
}

double momentum(const Body& b, int d)
{
  return b.momentum(d);
}

} // namespace

TEST(Erosion, SetupRefusesCriteriaThatCannotApply)
{
  ErosionCriteria c;
  c.plastic_strain = 0.3;
  EXPECT_EQ(erosion_setup_error(c, material(kJ2), false), "");
  EXPECT_NE(erosion_setup_error(c, material({}), false).find("plastic_strain"), std::string::npos);
  EXPECT_NE(erosion_setup_error(c, material(kJ2), true).find("rigid"), std::string::npos);
  c.plastic_strain = -0.1;
  EXPECT_NE(erosion_setup_error(c, material(kJ2), false).find("erosion"), std::string::npos);
  ErosionCriteria d;
  d.damage = 1.0;
  EXPECT_EQ(erosion_setup_error(d, material(kRankine), false), "");
  EXPECT_NE(erosion_setup_error(d, material(kJ2), false).find("erosion damage"), std::string::npos);
  d.damage = 1.5;
  EXPECT_NE(erosion_setup_error(d, material(kRankine), false).find("(0, 1]"), std::string::npos);
  ErosionCriteria t;
  t.min_dt = 1e-8;
  EXPECT_EQ(erosion_setup_error(t, material({}), false), "");
  EXPECT_NE(erosion_setup_error(ErosionCriteria(), material({}), false), "");
}

TEST(Erosion, PlasticStrainSelectsTheYieldedHalf)
{
  const Body b = kinked_bar(material(kJ2), 0.05);
  const std::vector<int> half = strained_half(b);
  ASSERT_FALSE(half.empty());
  EXPECT_GT(element_plastic_strain(b, half[0]), 0.01);
  EXPECT_EQ(element_plastic_strain(b, 0), 0.0);
  ErosionCriteria c;
  c.plastic_strain = 0.01;
  std::vector<int> elems;
  std::vector<ErosionCause> causes;
  select_eroding(b, c, elems, causes);
  EXPECT_EQ(elems, half);
  for (ErosionCause why : causes)
    EXPECT_EQ(why, ErosionCause::PlasticStrain);
  c.plastic_strain = 10.0; // beyond any element
  select_eroding(b, c, elems, causes);
  EXPECT_TRUE(elems.empty());
}

TEST(Erosion, DamageSelectsTheCrackedHalf)
{
  Material m = material(kRankine);
  m.E = 3e10;
  m.rho = 2400;
  m.nu = 0.2;
  const Body b = kinked_bar(m, 0.05);
  ErosionCriteria c;
  c.damage = 1.0;
  std::vector<int> elems;
  std::vector<ErosionCause> causes;
  select_eroding(b, c, elems, causes);
  EXPECT_EQ(elems, strained_half(b));
  for (ErosionCause why : causes)
    EXPECT_EQ(why, ErosionCause::Damage);
}

TEST(Erosion, MinDtSelectsTheSqueezedHalfAndTheStepAfterwardsIsAboveIt)
{
  const Body b = kinked_bar(material({}), -0.9); // squeezed to a tenth
  double dt_intact = 1e300;
  for (int e = 0; e < b.mesh().num_elems(); ++e)
    if (centroid_x(b, e) < 0.02) dt_intact = std::min(dt_intact, b.element_time_step(e));
  ErosionCriteria c;
  c.min_dt = 0.95 * dt_intact;
  std::vector<int> elems;
  std::vector<ErosionCause> causes;
  select_eroding(b, c, elems, causes);
  EXPECT_EQ(elems, strained_half(b));
  for (int e : elems)
    EXPECT_LT(b.element_time_step(e), c.min_dt);
  EXPECT_LT(b.stable_time_step(), c.min_dt);
  EXPECT_DOUBLE_EQ(stable_time_step_after_erosion(b, c), dt_intact);
  Body eroded = b;
  eroded.erode(elems);
  EXPECT_DOUBLE_EQ(eroded.stable_time_step(), dt_intact);
}

// erosion_mass keep: mass and momentum stay with the nodes; the elements' strain energy moves
// from the strain energy to the erosion account.
TEST(Erosion, KeepConservesMassAndMomentumAndAccountsTheStrainEnergy)
{
  Body b = shaken_block();
  std::vector<double> energies;
  b.element_energies(energies);
  const std::vector<int> gone = {0, 5, 17, 30};
  const double m0 = total_mass(b), se0 = b.strain_energy(), ke0 = b.kinetic_energy();
  const double p0[3] = {momentum(b, 0), momentum(b, 1), momentum(b, 2)};
  double held = 0;
  for (int e : gone)
    held += energies[e];
  ASSERT_GT(held, 0);
  const double out = b.erode(gone);
  EXPECT_EQ(total_mass(b), m0);
  for (int d = 0; d < 3; ++d)
    EXPECT_EQ(momentum(b, d), p0[d]);
  EXPECT_EQ(b.kinetic_energy(), ke0);
  EXPECT_EQ(b.eroded().elements, 4);
  EXPECT_EQ(b.eroded().mass, 0.0);
  EXPECT_NEAR(out, held, 1e-12 * held);
  EXPECT_NEAR(b.eroded().energy, held, 1e-12 * held);
  EXPECT_NEAR(b.strain_energy(), se0 - held, 1e-12 * se0);
  evaluate_forces(b, 1e-6); // the next evaluation counts the active elements only: same total
  EXPECT_NEAR(b.strain_energy() + b.eroded().energy, se0, 1e-12 * se0);
}

// erosion_mass remove: the total mass drops by exactly the elements' lumped masses; the momentum
// and kinetic energy of that mass are carried into the account.
TEST(Erosion, RemoveTakesExactlyTheElementMassWithItsMomentum)
{
  Body b = shaken_block();
  const std::vector<int> gone = {3, 4, 20};
  double element_mass = 0;
  for (int e : gone) {
    double me[4];
    b.space().element_nodal_masses(b.mesh(), e, me);
    element_mass += me[0] + me[1] + me[2] + me[3];
  }
  std::vector<double> energies;
  b.element_energies(energies);
  const double strain = energies[3] + energies[4] + energies[20];
  const double m0 = total_mass(b), ke0 = b.kinetic_energy();
  const double p0[3] = {momentum(b, 0), momentum(b, 1), momentum(b, 2)};
  b.erode(gone, true);
  EXPECT_NEAR(m0 - total_mass(b), element_mass, 1e-12 * m0);
  EXPECT_NEAR(b.eroded().mass, element_mass, 1e-12 * m0);
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(momentum(b, d) + b.eroded().momentum[d], p0[d], 1e-12 * m0);
  EXPECT_NEAR(b.kinetic_energy() + (b.eroded().energy - strain), ke0, 1e-12 * ke0);
}

// A node left with neither element nor mass stops cleanly (no 1/0, no NaN) and the rest goes on.
TEST(Erosion, RemoveStopsBareNodesAndTheBodyGoesOn)
{
  Body b = shaken_block();
  const int node = 0; // a corner: all its elements go
  const std::vector<int> star(b.stars().begin(node), b.stars().end(node));
  const double m0 = total_mass(b);
  b.erode(star, true);
  EXPECT_EQ(b.masses()[node], 0.0);
  EXPECT_EQ(b.velocities()[0], 0.0);
  EXPECT_NEAR(total_mass(b) + b.eroded().mass, m0, 1e-12 * m0);
  const double x0[3] = {b.positions()[0], b.positions()[1], b.positions()[2]};
  for (int s = 0; s < 20; ++s) {
    b.half_kick_drift(1e-7);
    evaluate_forces(b, 1e-7);
    b.half_kick(1e-7);
  }
  for (int d = 0; d < 3; ++d)
    EXPECT_EQ(b.positions()[d], x0[d]);
  for (double x : b.positions())
    EXPECT_TRUE(std::isfinite(x));
  EXPECT_TRUE(std::isfinite(b.kinetic_energy() + b.strain_energy()));
}

// erosion_mass keep: a node left without elements goes on as a free point mass (ballistic
// under gravity, no NaN).
TEST(Erosion, KeptNodesWithoutElementsFlyAsPointMasses)
{
  Body b = shaken_block();
  std::vector<int> all(b.mesh().num_elems());
  for (int e = 0; e < b.mesh().num_elems(); ++e)
    all[e] = e;
  b.erode(all);
  const double g[3] = {0, 0, -9.81}, dt = 1e-4;
  b.begin_forces(); // as fix fem/body does after an erosion: no element force is left
  int none = -1;
  b.finish_forces(b.add_internal_forces(&none), g, dt, true);
  const std::vector<double> x0 = b.positions(), v0 = b.velocities();
  const int steps = 10;
  for (int s = 0; s < steps; ++s) {
    b.half_kick_drift(dt);
    b.begin_forces();
    int inv = -1;
    b.finish_forces(b.add_internal_forces(&inv), g, dt, true);
    b.half_kick(dt);
  }
  const double t = steps * dt;
  for (int n = 0; n < b.num_nodes(); ++n) {
    EXPECT_NEAR(b.velocities()[3 * n + 2], v0[3 * n + 2] - 9.81 * t, 1e-12);
    EXPECT_NEAR(b.positions()[3 * n], x0[3 * n] + v0[3 * n] * t, 1e-12);
  }
  EXPECT_EQ(b.strain_energy(), 0.0);
}

TEST(Erosion, RestartKeepsTheAccounts)
{
  Body b = shaken_block();
  b.erode({2, 9}, true);
  std::vector<double> buf;
  b.pack_state(buf);
  EXPECT_EQ(buf[0], 4.0);
  Body c;
  c.build(make_box_tet_mesh(3, 2, 2, 0.03, 0.02, 0.02), material({}), false);
  c.unpack_state(buf.data());
  EXPECT_EQ(c.eroded().elements, 2);
  EXPECT_EQ(c.eroded().mass, b.eroded().mass);
  EXPECT_EQ(c.eroded().energy, b.eroded().energy);
  for (int d = 0; d < 3; ++d)
    EXPECT_EQ(c.eroded().momentum[d], b.eroded().momentum[d]);
  EXPECT_EQ(c.masses(), b.masses());
  EXPECT_EQ(c.mesh().num_active_elems(), b.mesh().num_active_elems());
  // A body that never eroded keeps writing the old record.
  Body d = shaken_block();
  d.pack_state(buf);
  EXPECT_EQ(buf[0], 2.0);
}

// Axisymmetric disc (r in [0, 0.01]) thrown at the axis: no node ever reaches r < 0; the shield
// takes the radial kinetic energy of the nodes it stops, and kinetic + strain - shield work stays
// the initial kinetic energy.
TEST(AxisShield, NothingCrossesTheAxisAndTheBalanceCloses)
{
  Material m;
  m.E = 1e7;
  m.nu = 0.3;
  m.rho = 1000;
  m.plane = PlaneMode::Axisymmetric;
  Body b;
  b.build(make_rect_mesh(6, 6, 0.01, 0.01, {0, 0}, ElemType::Tri3), m, false);
  for (int n = 0; n < b.num_nodes(); ++n) {
    const double v[3] = {-10.0, 0, 0};
    b.set_velocity({n}, v);
  }
  const double dt = 0.2 * b.stable_time_step();
  evaluate_forces(b, dt);
  const double e0 = b.kinetic_energy();
  double worst = 0, min_r = 1;
  for (int s = 0; s < 2000; ++s) {
    b.advance_time(dt);
    b.half_kick_drift(dt);
    evaluate_forces(b, dt);
    b.half_kick(dt);
    for (int n = 0; n < b.num_nodes(); ++n)
      min_r = std::min(min_r, b.positions()[3 * n]);
    const double balance = b.kinetic_energy() + b.strain_energy() - b.shield_work() - e0;
    worst = std::max(worst, std::fabs(balance) / e0);
  }
  EXPECT_GE(min_r, 0.0);
  EXPECT_GT(b.shield_hits(), 0);
  EXPECT_LT(b.shield_work(), 0.0);
  EXPECT_LT(worst, 0.02) << "shield work " << b.shield_work() << " of " << e0;
  std::vector<double> buf;
  b.pack_state(buf);
  Body c;
  c.build(make_rect_mesh(6, 6, 0.01, 0.01, {0, 0}, ElemType::Tri3), m, false);
  c.unpack_state(buf.data());
  EXPECT_EQ(c.shield_work(), b.shield_work());
  EXPECT_EQ(c.shield_hits(), b.shield_hits());
}
