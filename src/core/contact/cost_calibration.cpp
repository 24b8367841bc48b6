// Micro-benchmark of the interaction kernels that make up a particle's work.
#include "contact/cost_calibration.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <vector>

#include "contact/geometry.h"
#include "contact/granular_law.h"
#include "contact/liquid_bridge.h"

namespace fracdem
{

namespace
{

using Clock = std::chrono::steady_clock;

// Synthetic particles with a neighbour list shaped like a host list (indirect loads, ~8
// neighbours each), so that a pair check costs what it costs inside a pair style.
// The per-particle term amortises a reneighbouring (binning, a 5 x 5 x 5 stencil of bins half a
// cutoff wide, as LIGGGHTS bins) over this many steps, about the interval of the settling bed.
constexpr int kStepsPerReneighbour = 40;
constexpr int kBins = 16; // bins per dimension of the synthetic binning (a power of two)

struct Scene {
  int n = 4096, per = 8;
  std::vector<double> x, v, r;
  std::vector<double> m, f, w, t; // mass, force, angular velocity, torque
  std::vector<int> binhead = std::vector<int>(kBins * kBins * kBins, 0);
  std::vector<int> nbr;
  double shear[3] = {1e-4, 0, 0};
};

Scene make_scene()
{
  Scene s;
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  s.x.resize(3 * s.n);
  s.v.resize(3 * s.n);
  s.r.resize(s.n);
  for (int i = 0; i < s.n; ++i) {
    for (int d = 0; d < 3; ++d)
      s.x[3 * i + d] = 16.0 * u(rng), s.v[3 * i + d] = u(rng) - 0.5;
    s.r[i] = 0.5;
  }
  s.m.assign(s.n, 1.0);
  s.f.assign(3 * s.n, 0.0);
  s.w.assign(3 * s.n, 0.0);
  s.t.assign(3 * s.n, 1e-3);
  s.nbr.resize(static_cast<size_t>(s.n) * s.per);
  for (auto& j : s.nbr)
    j = static_cast<int>(rng() % s.n);
  return s;
}

// Out of line, as a pair style's contact branch is: the compiler cannot fold it into the sweep.
__attribute__((noinline)) double contact_law(const ContactMaterial& mat, const double* xi,
                                             const double* xj, double radsum, double* shear)
{
  ContactInput in{};
  double d[3], r2 = 0;
  for (int k = 0; k < 3; ++k)
    d[k] = xi[k] - xj[k], r2 += d[k] * d[k];
  const double dist = std::sqrt(r2) + 1e-12;
  for (int k = 0; k < 3; ++k)
    in.n[k] = d[k] / dist;
  in.delta = std::fabs(radsum - dist) * 1e-3 + 1e-6;
  in.radius = 0.5;
  in.mass = 1.0;
  in.v_rel[0] = 0.1;
  in.v_rel[2] = -0.2;
  in.dt = 1e-5;
  return particle_surface_force(mat, in, shear).fn;
}

// Seconds per item of `sweep(items)`, repeated for `budget` seconds.
// The fastest of the sweeps that fit in the budget: a sweep that the OS interrupted (another
// process, a timer) would otherwise inflate the mean, and the costs are differences of means.
template <typename Sweep> double seconds_per_item(Sweep sweep, long items, double budget)
{
  const auto start = Clock::now();
  double elapsed = 0, fastest = HUGE_VAL;
  while (elapsed < budget || fastest == HUGE_VAL) {
    const auto t0 = Clock::now();
    sweep();
    const auto t1 = Clock::now();
    fastest = std::min(fastest, std::chrono::duration<double>(t1 - t0).count());
    elapsed = std::chrono::duration<double>(t1 - start).count();
  }
  return fastest / static_cast<double>(items);
}

// The scene, the contact law's material, the time of each measurement and a sink the compiler
// cannot see through (so that no sweep is optimised away).
struct Bench {
  Scene s = make_scene();
  ContactMaterial mat = mix_materials(5e6, 0.3, 5e6, 0.3, 0.5, 0.5, 1.0, NormalModel::Hertz, true);
  double budget;
  volatile double sink = 0;
};

// Seconds per neighbour pair of a sweep whose pairs touch below radsum: with a threshold no pair
// reaches (not 0, which the compiler proves unreachable and deletes the loop) a pair check, with
// one every pair reaches a check and the law.
double pair_seconds(Bench& b, double radsum)
{
  Scene& s = b.s;
  const long pairs = static_cast<long>(s.n) * s.per;
  const auto sweep = [&] {
    double acc = 0;
    for (int i = 0; i < s.n; ++i) {
      const double* xi = &s.x[3 * i];
      for (int k = 0; k < s.per; ++k) {
        const int j = s.nbr[static_cast<size_t>(i) * s.per + k];
        const double* xj = &s.x[3 * j];
        const double dx = xi[0] - xj[0], dy = xi[1] - xj[1], dz = xi[2] - xj[2];
        if (dx * dx + dy * dy + dz * dz < radsum * radsum)
          acc += contact_law(b.mat, xi, xj, radsum, s.shear);
      }
    }
    b.sink = b.sink + acc;
  };
  return seconds_per_item(sweep, pairs, b.budget);
}

// Seconds per neighbour pair of the pair check plus a water bridge's capillary and viscous force
// (its gap, Derjaguin radius and rate), every pair bridged.
double bridge_seconds(Bench& b)
{
  Scene& s = b.s;
  const BridgeLaw law = prepare_bridge(LiquidBridge{0.072, 0.35, 1e-3, 1e-3});
  const long pairs = static_cast<long>(s.n) * s.per;
  const auto sweep = [&] {
    double acc = 0;
    for (int i = 0; i < s.n; ++i) {
      const double* xi = &s.x[3 * i];
      for (int k = 0; k < s.per; ++k) {
        const int j = s.nbr[static_cast<size_t>(i) * s.per + k];
        const double* xj = &s.x[3 * j];
        const double d[3] = {xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]};
        const double r = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) + 1e-12;
        const double* vi = &s.v[3 * i];
        const double* vj = &s.v[3 * j];
        const double rate =
            ((vi[0] - vj[0]) * d[0] + (vi[1] - vj[1]) * d[1] + (vi[2] - vj[2]) * d[2]) / r;
        const double rs = derjaguin_radius(s.r[i], s.r[j]);
        const double gap = 1e-3 * r; // below the rupture distance for every pair of the scene
        acc += capillary_force(law, rs, gap) + viscous_force(law, rs, gap + 1e-6, rate);
      }
    }
    b.sink = b.sink + acc;
  };
  return seconds_per_item(sweep, pairs, b.budget);
}

// Binning and stencil walk of one reneighbouring, spread over kStepsPerReneighbour steps.
void amortised_binning(Scene& s)
{
  for (int i = 0; i < s.n; i += kStepsPerReneighbour) {
    int cell[3];
    for (int d = 0; d < 3; ++d)
      cell[d] = static_cast<int>(s.x[3 * i + d] * 0.25) & (kBins - 1);
    int found = 0;
    for (int dz = -2; dz <= 2; ++dz)
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const int b = (((cell[2] + dz) & (kBins - 1)) * kBins + ((cell[1] + dy) & (kBins - 1))) *
                            kBins +
                        ((cell[0] + dx) & (kBins - 1));
          found += s.binhead[b];
        }
    s.binhead[(cell[2] * kBins + cell[1]) * kBins + cell[0]] = found & 1;
  }
}

// Per particle and step, whatever its neighbours: what a step does for a free-flying sphere
// (nve/sphere's two half steps of velocity, position and angular velocity, the force and torque
// clearing, gravity's force) plus the particle's share of a reneighbouring, amortised: its
// binning and the walk over its stencil bins (the distance checks against the particles there
// are the pair checks; the walk over bins is paid also where they are empty).
double free_particle_seconds(Bench& b)
{
  Scene& s = b.s;
  const auto sweep = [&] {
    const double dtf = 0.5e-5, dtv = 1e-5, g = -9.81;
    for (int i = 0; i < s.n; ++i) {
      const double inv_m = 1.0 / s.m[i], inv_i = 2.5 * inv_m / (s.r[i] * s.r[i]);
      for (int d = 0; d < 3; ++d) {
        s.v[3 * i + d] += dtf * s.f[3 * i + d] * inv_m;
        s.x[3 * i + d] += dtv * s.v[3 * i + d];
        s.w[3 * i + d] += dtf * s.t[3 * i + d] * inv_i;
        s.f[3 * i + d] = 0.0, s.t[3 * i + d] = 0.0;
      }
      s.f[3 * i + 2] += s.m[i] * g;
      for (int d = 0; d < 3; ++d) {
        s.v[3 * i + d] += dtf * s.f[3 * i + d] * inv_m;
        s.w[3 * i + d] += dtf * s.t[3 * i + d] * inv_i;
      }
    }
    amortised_binning(s);
    b.sink = b.sink + s.x[7] + s.w[5];
  };
  return seconds_per_item(sweep, s.n, b.budget);
}

// Seconds per particle of a primitive wall (plane z = plane): the gap test for all, and the law
// for those below the plane.
double wall_seconds(Bench& b, double plane)
{
  Scene& s = b.s;
  const auto sweep = [&] {
    double acc = 0;
    for (int i = 0; i < s.n; ++i) {
      const double* xi = &s.x[3 * i];
      const double gap = xi[2] - plane - s.r[i];
      if (gap < 0) {
        const double xw[3] = {xi[0], xi[1], plane};
        acc += contact_law(b.mat, xi, xw, s.r[i], s.shear);
      }
    }
    b.sink = b.sink + acc;
  };
  return seconds_per_item(sweep, s.n, b.budget);
}

// Seconds per particle of a facet: the closest point on a triangle, and (with_law) the law.
double facet_seconds(Bench& b, bool with_law)
{
  Scene& s = b.s;
  const double a[3] = {0, 0, 0}, c1[3] = {16, 0, 0}, c2[3] = {0, 16, 0.5};
  const auto sweep = [&] {
    double acc = 0;
    for (int i = 0; i < s.n; ++i) {
      const ClosestPoint cp = closest_point_triangle(&s.x[3 * i], a, c1, c2);
      acc += with_law ? contact_law(b.mat, &s.x[3 * i], cp.p, 0.5, s.shear) : cp.dist2;
    }
    b.sink = b.sink + acc;
  };
  return seconds_per_item(sweep, s.n, b.budget);
}

} // namespace

balance::InteractionCosts calibrate_costs(double seconds_budget)
{
  Bench b;
  b.budget = seconds_budget / 8.0;
  const double t_check = pair_seconds(b, 1e-9);
  const double t_contact_all = pair_seconds(b, 1e9);
  const double t_particle = free_particle_seconds(b);
  const double t_wall_check = wall_seconds(b, -1e9); // no particle below
  const double t_wall_all = wall_seconds(b, 1e9);
  const double t_facet_check = facet_seconds(b, false);
  const double t_facet_all = facet_seconds(b, true);
  const double t_bridge_all = bridge_seconds(b);

  balance::InteractionCosts costs;
  const double base = t_check > 1e-12 ? t_check : 1e-12;
  auto rel = [&](double t) { return std::max(t / base, 0.05); };
  costs.pair_check = 1.0;
  costs.sphere_contact = rel(t_contact_all - t_check);
  costs.particle = rel(t_particle);
  costs.wall_check = rel(t_wall_check);
  costs.wall_contact = rel(t_wall_all - t_wall_check);
  costs.facet_check = rel(t_facet_check);
  costs.facet_contact = rel(t_facet_all - t_facet_check);
  costs.bridge = rel(t_bridge_all - t_check);
  return costs;
}

} // namespace fracdem
