// Unit tests of the artificial bulk viscosity: the pressure and time-step formulas, the element
// forces (work, momentum, objectivity, damage) and the body's viscous-work account and restart.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "fem/body.h"
#include "fem/fe_space.h"
#include "io/mesh_generators.h"
#include "materials/bulk_viscosity.h"
#include "materials/rankine.h"

using namespace fracdem;

namespace
{

BulkViscosity defaults()
{
  BulkViscosity bv;
  bv.on = true;
  return bv;
}

Material steel(MaterialModel model = MaterialModel::Elastic)
{
  Material m;
  m.E = 2e11;
  m.nu = 0.3;
  m.rho = 7800;
  m.model = model;
  m.ft = 3e6;
  m.gf = 100;
  return m;
}

// Velocities v = A x (3 per node) for a 3x3 velocity gradient A.
std::vector<double> linear_field(const Mesh& m, const double A[9])
{
  std::vector<double> v(3 * m.num_nodes());
  for (int n = 0; n < m.num_nodes(); ++n)
    for (int i = 0; i < 3; ++i)
      v[3 * n + i] =
          A[3 * i] * m.X[3 * n] + A[3 * i + 1] * m.X[3 * n + 1] + A[3 * i + 2] * m.X[3 * n + 2];
  return v;
}

struct ViscousResult {
  std::vector<double> f, scale, rate;
  double power = 0; // sum_a f_a . v_a
  double force[3] = {0, 0, 0};
};

ViscousResult viscous(const FeSpace& fs, const Mesh& m, const std::vector<double>& v,
                      const double* state = nullptr)
{
  ViscousResult r;
  r.f.assign(3 * m.num_nodes(), 0.0);
  r.scale.assign(m.num_elems(), 0.0);
  r.rate.assign(m.num_elems(), 0.0);
  fs.add_viscous_forces(m, m.X.data(), v.data(), 0, m.num_elems(), defaults(), state, r.f.data(),
                        r.scale.data(), r.rate.data());
  for (int n = 0; n < m.num_nodes(); ++n)
    for (int i = 0; i < 3; ++i) {
      r.power += r.f[3 * n + i] * v[3 * n + i];
      r.force[i] += r.f[3 * n + i];
    }
  return r;
}

} // namespace

TEST(BulkViscosity, PressureFollowsTheLinearPlusQuadraticFormulaInCompression)
{
  const BulkViscosity bv = defaults();
  const double rho = 7800, c = 5900, l = 2e-3;
  for (double D : {-1.0, -1e3, -1e5, -3e6}) {
    const double expected = rho * l * (0.06 * c * -D + 1.2 * 1.2 * l * D * D);
    EXPECT_NEAR(bulk_viscosity_pressure(bv, rho, c, l, D), expected, 1e-14 * expected) << D;
  }
  BulkViscosity only_linear = bv;
  only_linear.q2 = 0;
  EXPECT_DOUBLE_EQ(bulk_viscosity_pressure(only_linear, rho, c, l, -10.0), rho * l * 0.06 * c * 10);
}

TEST(BulkViscosity, ZeroInExpansionAndDissipativeInCompression)
{
  const BulkViscosity bv = defaults();
  EXPECT_EQ(bulk_viscosity_pressure(bv, 7800, 5900, 1e-3, 0.0), 0.0);
  EXPECT_EQ(bulk_viscosity_pressure(bv, 7800, 5900, 1e-3, 1e4), 0.0);
  EXPECT_EQ(bulk_viscosity_pressure(bv, 7800, 5900, 1e-3, std::nan("")), 0.0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1e6, 1e6);
  for (int k = 0; k < 1000; ++k) {
    const double D = u(rng);
    const double q = bulk_viscosity_pressure(bv, 7800, 5900, 1e-3, D);
    EXPECT_GE(q, 0.0);
    EXPECT_GE(-q * D, 0.0); // dissipated power per unit volume
  }
}

TEST(BulkViscosity, TimeStepFactorAndDampingRatioFollowTheFormulas)
{
  const BulkViscosity bv = defaults();
  for (double xi : {0.0, 0.06, 0.5, 1.0, 10.0})
    EXPECT_NEAR(damped_time_step_factor(xi), std::sqrt(1 + xi * xi) - xi, 1e-13) << xi;
  EXPECT_DOUBLE_EQ(damped_time_step_factor(0.0), 1.0);
  // Heavily damped: 1 / (2 xi) without the cancellation of the naive difference.
  EXPECT_NEAR(damped_time_step_factor(1e4), 0.5e-4 * (1 - 0.25e-8), 1e-18);
  const double c = 5000, l = 1e-3;
  EXPECT_DOUBLE_EQ(bulk_viscosity_damping_ratio(bv, c, l, 1e5), 0.06); // expansion: linear only
  EXPECT_DOUBLE_EQ(bulk_viscosity_damping_ratio(bv, c, l, -1e5), 0.06 + 1.44 * l / c * 1e5);
  // LS-DYNA's form dt = l / (Q + sqrt(Q^2 + c^2)), Q = xi c, is the same step.
  const double xi = bulk_viscosity_damping_ratio(bv, c, l, -2e5), Q = xi * c;
  EXPECT_NEAR(l / c * damped_time_step_factor(xi), l / (Q + std::sqrt(Q * Q + c * c)), 1e-20);

  // The element step: the undamped bound times the factor of its damping ratio.
  const Mesh m = make_box_tet_mesh(2, 2, 2, 0.02, 0.02, 0.02);
  FeSpace fs;
  fs.build(m, steel());
  const double cd = steel().dilatational_wave_speed();
  for (int e : {0, 5, 17}) {
    const double dt0 = fs.element_time_step(m, m.X.data(), e);
    for (double D : {0.0, 1e4, -1e4, -1e6}) {
      const double xi_e = bulk_viscosity_damping_ratio(bv, cd, cd * dt0, D);
      EXPECT_NEAR(fs.element_time_step(m, m.X.data(), e, bv, D),
                  dt0 * (std::sqrt(1 + xi_e * xi_e) - xi_e), 1e-12 * dt0);
    }
  }
  const double dt_off = fs.stable_time_step(m, m.X.data());
  EXPECT_NEAR(fs.stable_time_step(m, m.X.data(), &bv), dt_off * damped_time_step_factor(0.06),
              1e-12 * dt_off);
  BulkViscosity off;
  EXPECT_EQ(fs.stable_time_step(m, m.X.data(), &off), dt_off);
}

TEST(BulkViscosity, CoefficientsAreChecked)
{
  BulkViscosity bv = defaults();
  EXPECT_STREQ(bulk_viscosity_check(bv), "");
  bv.q1 = -0.1;
  EXPECT_NE(std::string(bulk_viscosity_check(bv)).find("Q1"), std::string::npos);
  bv.q1 = 0.06;
  bv.q2 = -1;
  EXPECT_NE(std::string(bulk_viscosity_check(bv)).find("Q2"), std::string::npos);
  bv.q2 = std::nan("");
  EXPECT_NE(std::string(bulk_viscosity_check(bv)).find("Q2"), std::string::npos);
}

// Uniform compression v = -k x: every element has D = -3k (-2k in plane strain) and q of the
// formula; the forces sum to zero and do the work q W D. Expansion and rigid rotation: nothing.
TEST(BulkViscosity, ElementForcesDoTheViscousWorkAndConserveMomentum)
{
  for (ElemType t : {ElemType::Tet4, ElemType::Tri3, ElemType::Quad4}) {
    const Mesh m = t == ElemType::Tet4 ? make_box_tet_mesh(2, 2, 2, 0.02, 0.02, 0.02)
                                       : make_rect_mesh(3, 2, 0.03, 0.02, {0, 0}, t);
    FeSpace fs;
    fs.build(m, steel());
    const double k = 1e3, dim = t == ElemType::Tet4 ? 3 : 2;
    const double A[9] = {-k, 0, 0, 0, -k, 0, 0, 0, t == ElemType::Tet4 ? -k : 0};
    const ViscousResult r = viscous(fs, m, linear_field(m, A));
    double work = 0;
    for (int e = 0; e < m.num_elems(); ++e) {
      EXPECT_NEAR(r.rate[e], -dim * k, 1e-9 * k);
      const double c = steel().dilatational_wave_speed();
      const double q = bulk_viscosity_pressure(
          defaults(), 7800, c, fs.characteristic_length(m, m.X.data(), e), r.rate[e]);
      EXPECT_NEAR(r.scale[e], q * fs.reference_measure(e), 1e-9 * r.scale[e]);
      work += r.scale[e] * r.rate[e];
    }
    EXPECT_LT(r.power, 0);
    EXPECT_NEAR(r.power, work, 1e-9 * std::fabs(work));
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(r.force[i], 0.0, 1e-9 * std::fabs(work) / k);

    const double expand[9] = {k, 0, 0, 0, k, 0, 0, 0, 0};
    const ViscousResult e = viscous(fs, m, linear_field(m, expand));
    for (double fi : e.f)
      EXPECT_EQ(fi, 0.0);
    const double spin[9] = {0, -k, 0, k, 0, 0, 0, 0, 0};
    const ViscousResult s = viscous(fs, m, linear_field(m, spin));
    for (int el = 0; el < m.num_elems(); ++el)
      EXPECT_NEAR(s.rate[el], 0.0, 1e-9 * k);
  }
}

// A damaged element (Rankine damage d) carries (1 - d) of the viscous pressure.
TEST(BulkViscosity, DamageScalesThePressureDown)
{
  const Mesh m = make_box_tet_mesh(1, 1, 1, 0.02, 0.02, 0.02);
  FeSpace fs;
  fs.build(m, steel(MaterialModel::Rankine));
  std::vector<double> state(fs.state_size(), 0.0);
  const double A[9] = {-1e3, 0, 0, 0, 0, 0, 0, 0, 0};
  const std::vector<double> v = linear_field(m, A);
  const ViscousResult intact = viscous(fs, m, v, state.data());
  state[fs.state_offset(2) + 2] = 0.75; // damage slot of element 2's point
  const ViscousResult damaged = viscous(fs, m, v, state.data());
  for (int e = 0; e < m.num_elems(); ++e)
    EXPECT_NEAR(damaged.scale[e], intact.scale[e] * (e == 2 ? 0.25 : 1.0), 1e-12 * intact.scale[e]);
}

// A block squeezed by its initial velocities: the viscous work grows, the step's energy balance
// kinetic + strain + viscous work holds, and the accounts survive a restart record.
TEST(BulkViscosity, BodyAccountsTheViscousWorkAndRestartsIt)
{
  Body b;
  b.build(make_box_tet_mesh(3, 3, 3, 0.03, 0.03, 0.03), steel(), false);
  b.set_bulk_viscosity(defaults());
  for (int n = 0; n < b.num_nodes(); ++n) {
    const double* X = &b.mesh().X[3 * n];
    const double v[3] = {-20 * (X[0] - 0.015) / 0.015, -20 * (X[1] - 0.015) / 0.015, 0.0};
    b.set_velocity({n}, v);
  }
  const double g[3] = {0, 0, 0}, dt = 2e-8;
  auto forces = [&](bool count) {
    b.begin_forces();
    int inv = -1;
    b.finish_forces(b.add_internal_forces(&inv), g, dt, count);
  };
  forces(false);
  const double e0 = b.kinetic_energy() + b.strain_energy();
  for (int step = 0; step < 200; ++step) {
    b.advance_time(dt);
    b.half_kick_drift(dt);
    forces(true);
    b.half_kick(dt);
  }
  const double wv = b.viscous_work();
  EXPECT_GT(wv, 0.02 * e0);                                                // 5.5 %
  EXPECT_NEAR(b.kinetic_energy() + b.strain_energy() + wv, e0, 1e-4 * e0); // 1.9e-5
  EXPECT_LT(b.stable_time_step(), b.space().stable_time_step(b.mesh(), b.positions().data()));

  std::vector<double> buf;
  b.pack_state(buf);
  EXPECT_EQ(buf[0], 3.0);
  Body c;
  c.build(make_box_tet_mesh(3, 3, 3, 0.03, 0.03, 0.03), steel(), false);
  c.set_bulk_viscosity(defaults());
  c.unpack_state(buf.data());
  EXPECT_EQ(c.viscous_work(), wv);
  EXPECT_EQ(c.element_viscous_work(), b.element_viscous_work());
  Body off;
  off.build(make_box_tet_mesh(3, 3, 3, 0.03, 0.03, 0.03), steel(), false);
  EXPECT_THROW(off.unpack_state(buf.data()), std::runtime_error);
  off.pack_state(buf);
  EXPECT_EQ(buf[0], 2.0); // bodies without viscosity keep writing the version-2 record
}

// A continued run (second 'run', read_restart) starts with the host's set-up evaluation at the
// full-step velocities; the viscous force of the step is that of its mid-step velocities. The
// set-up evaluation repeats it (Body::replay_viscous_forces_once), from the body itself and from
// its restart record, so the continued run's first step is the uninterrupted one's.
TEST(BulkViscosity, SetUpOfAContinuedRunRepeatsTheLastViscousForces)
{
  auto make = [] {
    Body b;
    b.build(make_box_tet_mesh(3, 3, 3, 0.03, 0.03, 0.03), steel(), false);
    b.set_bulk_viscosity(defaults());
    return b;
  };
  Body b = make();
  for (int n = 0; n < b.num_nodes(); ++n) {
    const double* X = &b.mesh().X[3 * n];
    const double v[3] = {-20 * (X[0] - 0.015) / 0.015, -20 * (X[1] - 0.015) / 0.015, 0.0};
    b.set_velocity({n}, v);
  }
  const double g[3] = {0, 0, 0}, dt = 2e-8;
  auto forces = [&](Body& body, bool count, bool setup) {
    body.begin_forces();
    if (setup) body.replay_viscous_forces_once();
    int inv = -1;
    body.finish_forces(body.add_internal_forces(&inv), g, dt, count);
    return std::vector<double>(body.forces_data(), body.forces_data() + 3 * body.num_nodes());
  };
  forces(b, false, true); // a fresh body's set-up takes its velocities (nothing to repeat)
  std::vector<double> last;
  for (int step = 0; step < 50; ++step) {
    b.advance_time(dt);
    b.half_kick_drift(dt);
    last = forces(b, true, false);
    b.half_kick(dt);
  }
  std::vector<double> buf;
  b.pack_state(buf);
  Body restored = make();
  restored.unpack_state(buf.data());
  double scale = 0, worst_same = 0, worst_restored = 0, worst_plain = 0;
  for (double f : last)
    scale = std::max(scale, std::abs(f));
  const std::vector<double> same = forces(b, false, true);
  const std::vector<double> again = forces(restored, false, true);
  Body plain = make(); // the set-up without the repeat: full-step velocities
  plain.unpack_state(buf.data());
  const std::vector<double> full = forces(plain, false, false);
  for (size_t k = 0; k < last.size(); ++k) {
    worst_same = std::max(worst_same, std::abs(same[k] - last[k]));
    worst_restored = std::max(worst_restored, std::abs(again[k] - last[k]));
    worst_plain = std::max(worst_plain, std::abs(full[k] - last[k]));
  }
  EXPECT_LT(worst_same, 1e-13 * scale);
  EXPECT_LT(worst_restored, 1e-13 * scale);
  EXPECT_GT(worst_plain, 1e-6 * scale); // what the set-up did before: the full-step velocities
}
