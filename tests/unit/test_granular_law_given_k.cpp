// Unit tests of the contact law with a given stiffness (LAMMPS pair granular hooke|hertz k_n damp)
// against closed forms: elastic force, each damping model's coefficient, the restitution of a
// whole collision, tangential springs and their Coulomb cap.
#include <gtest/gtest.h>

#include <cmath>

#include "contact/granular_law.h"

using namespace fracdem;

namespace
{

constexpr double kR = 0.005, kM = 4e-3; // sphere radius and mass

// A sphere pressed onto the plane z = 0 by delta, moving at v, spinning at w.
ContactInput input(double delta, const double v[3], const double w[3] = nullptr, double dt = 1e-7)
{
  ContactInput in{};
  in.n[2] = 1;
  in.delta = delta;
  in.radius = kR;
  in.mass = kM;
  in.dt = dt;
  for (int d = 0; d < 3; ++d) {
    in.v_rel[d] = v[d];
    in.omega[d] = w ? w[d] : 0.0;
  }
  return in;
}

double normal_force(const ContactMaterial& law, double delta, double vn)
{
  const double v[3] = {0, 0, vn};
  double shear[3] = {0, 0, 0};
  return particle_surface_force(law, input(delta, v), shear).fn;
}

// Rebound over impact speed of a sphere dropped at v0 on the plane, velocity Verlet as LAMMPS's
// fix nve/sphere (half kick, drift, force, half kick), steps of dt.
double restitution(const ContactMaterial& law, double v0, double dt)
{
  double z = 0, v = -v0, f = 0;
  bool touched = false;
  for (int step = 0; step < 10000000; ++step) {
    v += 0.5 * dt * f / kM;
    z += dt * v;
    f = z < 0 ? normal_force(law, -z, v) : 0.0;
    v += 0.5 * dt * f / kM;
    touched |= z < 0;
    if (touched && z >= 0) return v / v0;
  }
  return NAN;
}

} // namespace

TEST(GivenStiffnessLaw, ElasticForceIsTheGivenSpring)
{
  const double kn = 2e5, delta = 1e-5;
  const auto hooke =
      given_stiffness_law(NormalModel::Hooke, kn, 0, DampingModel::Velocity, 0, false, 0, 0, true);
  EXPECT_EQ(normal_force(hooke, delta, 0), kn * delta);
  const auto hertz =
      given_stiffness_law(NormalModel::Hertz, kn, 0, DampingModel::Velocity, 0, false, 0, 0, true);
  EXPECT_NEAR(normal_force(hertz, delta, 0), kn * std::sqrt(kR * delta) * delta,
              1e-14 * kn * std::sqrt(kR * delta) * delta);
  // The moduli-based law is untouched by the given one.
  EXPECT_FALSE(mix_materials(1e7, 0.3, 0, 0, 0.5, 0.3, 1, NormalModel::Hertz, true).given.on);
}

TEST(GivenStiffnessLaw, DampingModelsAreLammpsCoefficients)
{
  const double kn = 2e5, delta = 1e-5, vn = -0.2, a = std::sqrt(kR * delta);
  const double le = std::log(0.5), root = std::sqrt(M_PI * M_PI + le * le);
  struct Case {
    NormalModel m;
    DampingModel d;
    double damp, eta;
  } cases[] = {
      {NormalModel::Hooke, DampingModel::None, 3.0, 0.0},
      {NormalModel::Hooke, DampingModel::Velocity, 3.0, 3.0},
      {NormalModel::Hooke, DampingModel::MassVelocity, 300.0, 300.0 * kM},
      {NormalModel::Hooke, DampingModel::Viscoelastic, 1e5, 1e5 * kM * a},
      {NormalModel::Hooke, DampingModel::CoeffRestitution, 0.5,
       -2 * le / root * std::sqrt(kM * kn)},
      {NormalModel::Hooke, DampingModel::Tsuji, 0.5, tsuji_damping(0.5) * std::sqrt(kM * kn)},
      {NormalModel::Hertz, DampingModel::CoeffRestitution, 0.5,
       -std::sqrt(5.0) * le / root * std::sqrt(kM * kn * a)},
      {NormalModel::Hertz, DampingModel::Viscoelastic, 1e5, 1e5 * kM * a},
  };
  for (const Case& c : cases) {
    const auto law = given_stiffness_law(c.m, kn, c.damp, c.d, 0, false, 0, 0, true);
    const double fe = normal_force(law, delta, 0);
    EXPECT_NEAR(normal_force(law, delta, vn) - fe, -c.eta * vn, 1e-12 * fe)
        << "model " << int(c.m) << " damping " << int(c.d);
  }
  // Marshall's fit at e = 0.5 (LAMMPS 22 Jul 2025's polynomial)
  EXPECT_NEAR(tsuji_damping(0.5), 0.34074062500, 1e-12);
}

TEST(GivenStiffnessLaw, HookeCoeffRestitutionGivesThatRestitution)
{
  const double kn = 2e5, T = M_PI * std::sqrt(kM / kn); // half period of the undamped spring
  for (double e : {0.3, 0.5, 0.9}) {
    const auto law = given_stiffness_law(NormalModel::Hooke, kn, e, DampingModel::CoeffRestitution,
                                         0, false, 0, 0, true);
    EXPECT_NEAR(restitution(law, 0.5, T / 20000), e, 1e-3) << "e = " << e;
  }
  // Hertz with Tsuji's coefficient (sqrt(5) |ln e| / sqrt(ln^2 e + pi^2)): the damping scales
  // with the stiffness, so the restitution is the same at every impact speed, and it is e.
  const double dt = hertz_impact(0.75 * kn, kR, kM, 0.5).duration / 20000;
  for (double e : {0.3, 0.9})
    for (double v0 : {0.05, 0.5}) {
      const auto law = given_stiffness_law(NormalModel::Hertz, kn, e,
                                           DampingModel::CoeffRestitution, 0, false, 0, 0, true);
      EXPECT_NEAR(restitution(law, v0, dt), e, 1e-3) << "Hertz, e = " << e << ", v = " << v0;
    }
}

TEST(GivenStiffnessLaw, HertzElasticImpactMatchesHertzTheory)
{
  // F = k_n sqrt(R) delta^1.5 is Hertz with 4/3 E* = k_n: peak force and energy conservation.
  const double kn = 1e7, v0 = 0.3;
  const auto law =
      given_stiffness_law(NormalModel::Hertz, kn, 0, DampingModel::Velocity, 0, false, 0, 0, true);
  const HertzImpact h = hertz_impact(0.75 * kn, kR, kM, v0);
  const double dt = h.duration / 20000;
  double z = 0, v = -v0, f = 0, peak = 0;
  for (int step = 0; step < 40000 && !(z > 0 && v > 0); ++step) {
    v += 0.5 * dt * f / kM;
    z += dt * v;
    f = z < 0 ? normal_force(law, -z, v) : 0.0;
    v += 0.5 * dt * f / kM;
    peak = std::fmax(peak, f);
  }
  EXPECT_NEAR(peak, h.peak_force, 1e-3 * h.peak_force);
  EXPECT_NEAR(v, v0, 1e-4 * v0);
  EXPECT_NEAR(restitution(law, v0, dt), 1.0, 1e-4);
}

TEST(GivenStiffnessLaw, TangentialSpringsAndCoulombCap)
{
  const double kn = 2e5, kt = 1e5, delta = 1e-5, dt = 1e-7, a = std::sqrt(kR * delta);
  const double v[3] = {0.01, 0, 0};
  for (bool mindlin : {false, true}) {
    const auto law = given_stiffness_law(NormalModel::Hooke, kn, 3.0, DampingModel::Velocity, kt,
                                         mindlin, 0.5, 10.0, true);
    double shear[3] = {0, 0, 0};
    const ContactOutput out = particle_surface_force(law, input(delta, v, nullptr, dt), shear);
    // one step of sticking: spring over v dt, damping x_t eta
    const double k = mindlin ? kt * a : kt;
    EXPECT_NEAR(out.force[0], -k * v[0] * dt - 0.5 * 3.0 * v[0], 1e-12 * 1.5 * v[0]);
    EXPECT_NEAR(out.torque[1], -kR * out.force[0], 1e-15); // LAMMPS wall: lever arm r
  }
  // sliding: capped at mu |F_n|
  const auto law =
      given_stiffness_law(NormalModel::Hooke, kn, 0, DampingModel::None, kt, false, 0, 0.3, true);
  double shear[3] = {0, 0, 0};
  const double fast[3] = {5.0, 0, 0};
  const ContactOutput out = particle_surface_force(law, input(delta, fast, nullptr, 1e-3), shear);
  EXPECT_NEAR(out.force[0], -0.3 * kn * delta, 1e-12 * kn * delta);
  // sliding with damping (LAMMPS's rule): spring + damping capped; the kept spring is the capped
  // force less the damping, -(F_t + eta_t v_t) / k_t
  const auto damped = given_stiffness_law(NormalModel::Hooke, kn, 3.0, DampingModel::Velocity, kt,
                                          false, 0.5, 0.3, true);
  double sh[3] = {0, 0, 0};
  const ContactOutput slip = particle_surface_force(damped, input(delta, fast, nullptr, 1e-3), sh);
  const double fn = kn * delta; // v_n = 0: no normal damping
  EXPECT_NEAR(slip.force[0], -0.3 * fn, 1e-12 * fn);
  EXPECT_NEAR(sh[0], -(-0.3 * fn + 1.5 * fast[0]) / kt, 1e-12 * 7.5 / kt);
  // linear_nohistory, frictionless: no tangential force at all
  const auto none = given_stiffness_law(NormalModel::Hooke, kn, 3.0, DampingModel::Velocity, 0,
                                        false, 0.5, 0.0, false);
  const ContactOutput free = particle_surface_force(none, input(delta, fast), shear);
  EXPECT_EQ(free.force[0], 0.0);
}
