// Micro-benchmark of the interaction kernels that make up a particle's work.
#include "balance/cost_calibration.h"

#include <chrono>
#include <cmath>
#include <random>
#include <vector>

#include "contact/geometry.h"
#include "contact/granular_law.h"

namespace fracdem::balance {

InteractionCosts unit_costs() { return InteractionCosts{}; }

namespace {

using Clock = std::chrono::steady_clock;

// Runs `body(k)` for k = 0.. until `budget` seconds passed; returns seconds per call.
// A sink defeats dead-code elimination.
template <typename Body> double time_per_call(Body body, double budget, double& sink)
{
  const auto start = Clock::now();
  long calls = 0;
  double elapsed = 0;
  while (elapsed < budget) {
    for (int k = 0; k < 4096; ++k) sink += body(static_cast<int>(calls + k));
    calls += 4096;
    elapsed = std::chrono::duration<double>(Clock::now() - start).count();
  }
  return elapsed / static_cast<double>(calls);
}

} // namespace

InteractionCosts calibrate_costs(double seconds_budget)
{
  const int n = 1024; // working set that stays in cache, as a neighbour list sweep mostly does
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> xyz(3 * n), rad(n);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) xyz[3 * i + d] = 4.0 * u(rng);
    rad[i] = 0.4 + 0.2 * u(rng);
  }
  const ContactMaterial mat =
      mix_materials(5e6, 0.3, 5e6, 0.3, 0.5, 0.5, 1.0, NormalModel::Hertz, true);
  const double budget = seconds_budget / 5.0;
  double sink = 0;

  const double t_check = time_per_call(
      [&](int k) {
        const int i = k % n, j = (k * 7 + 1) % n;
        const double dx = xyz[3 * i] - xyz[3 * j], dy = xyz[3 * i + 1] - xyz[3 * j + 1],
                     dz = xyz[3 * i + 2] - xyz[3 * j + 2];
        const double rs = rad[i] + rad[j];
        return (dx * dx + dy * dy + dz * dz < rs * rs) ? 1.0 : 0.0;
      },
      budget, sink);

  auto law = [&](int k, double delta) {
    ContactInput in{};
    in.n[0] = 0.6;
    in.n[1] = 0.0;
    in.n[2] = 0.8;
    in.delta = delta;
    in.radius = rad[k % n];
    in.mass = 1.0;
    in.v_rel[0] = 0.1;
    in.v_rel[2] = -0.2;
    in.dt = 1e-5;
    double shear[3] = {1e-4, 0.0, 0.0};
    return particle_surface_force(mat, in, shear).fn;
  };
  const double t_contact = time_per_call(
      [&](int k) { return law(k, 0.01 + 1e-6 * (k & 15)); }, budget, sink);

  const double t_wall = time_per_call(
      [&](int k) {
        const int i = k % n;
        const double gap = xyz[3 * i + 2] - 0.5 - rad[i]; // plane z = 0.5
        return law(k, std::fabs(gap) + 1e-3);
      },
      budget, sink);

  const double a[3] = {0, 0, 0}, b[3] = {4, 0, 0}, c[3] = {0, 4, 0.5};
  const double t_facet_check = time_per_call(
      [&](int k) { return closest_point_triangle(&xyz[3 * (k % n)], a, b, c).dist2; }, budget,
      sink);
  const double t_facet_contact = time_per_call(
      [&](int k) {
        const ClosestPoint cp = closest_point_triangle(&xyz[3 * (k % n)], a, b, c);
        return law(k, 1e-3 + 1e-3 * cp.dist2);
      },
      budget, sink);

  InteractionCosts costs;
  const double base = t_check > 0 ? t_check : 1e-9;
  costs.pair_check = 1.0;
  costs.sphere_contact = t_contact / base;
  costs.wall_contact = t_wall / base;
  costs.facet_check = t_facet_check / base;
  costs.facet_contact = t_facet_contact / base;
  if (sink == 12345.678) costs.pair_check += 0; // keeps `sink` observable
  return costs;
}

} // namespace fracdem::balance
