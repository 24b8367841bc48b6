// Local indentation and Hertz pressure spreading for particle contacts on deformable surfaces.
#include "contact/contact_spread.h"

#include <algorithm>
#include <cmath>

namespace fracdem
{

double hertz_surface_profile(double s)
{
  s = std::fabs(s);
  if (s <= 1.0) return 1.0 - 0.5 * s * s;
  return ((2.0 - s * s) * std::asin(1.0 / s) + std::sqrt(s * s - 1.0)) / M_PI;
}

void gather_surface_patch(const SurfaceTopology& topo, const double* x, const int* seeds,
                          int nseeds, const double c[3], const double n[3], double rmax,
                          SurfacePatch& patch)
{
  patch.nodes.clear();
  patch.radius.clear();
  auto in_plane = [&](int v) {
    double d[3], dn = 0;
    for (int k = 0; k < 3; ++k)
      d[k] = x[3 * v + k] - c[k], dn += d[k] * n[k];
    double r2 = 0;
    for (int k = 0; k < 3; ++k)
      r2 += (d[k] - dn * n[k]) * (d[k] - dn * n[k]);
    return std::sqrt(r2);
  };
  std::vector<int> frontier(seeds, seeds + nseeds), next;
  std::vector<int>& seen = patch.nodes; // visited and kept
  // Visited marks by epoch: no clearing per call, constant time per node on fine meshes.
  if (++patch.epoch == 0) {
    std::fill(patch.visited.begin(), patch.visited.end(), 0u);
    patch.epoch = 1;
  }
  auto visit = [&](int v) {
    if (v >= static_cast<int>(patch.visited.size()))
      patch.visited.resize(std::max<size_t>(v + 1, topo.node_neighbors.size()), 0u);
    if (patch.visited[v] == patch.epoch) return false;
    patch.visited[v] = patch.epoch;
    return true;
  };
  for (int v : frontier)
    visit(v);
  while (!frontier.empty()) {
    next.clear();
    for (int v : frontier) {
      const double r = in_plane(v);
      if (r > rmax) continue; // beyond the patch: do not expand from here
      seen.push_back(v);
      patch.radius.push_back(r);
      if (v < static_cast<int>(topo.node_neighbors.size()))
        for (int w : topo.node_neighbors[v])
          if (visit(w)) next.push_back(w);
    }
    frontier.swap(next);
  }
}

double local_indentation(double R, double delta_p, double u_c, const std::vector<double>& disp,
                         const SurfacePatch& patch)
{
  // Ring nodes weigh in smoothly (sin^2 window over [1.5 a, 3.5 a], zero at both ends): a node
  // crossing the ring's edge as the contact grows must not make the estimate, and so the force,
  // jump — that would ring the light surface nodes.
  constexpr double kLo = 1.5, kHi = 3.5;
  double delta_b = 0;
  for (int it = 0; it < 4; ++it) {
    const double a = std::sqrt(R * (delta_p + delta_b));
    double sum_w = 0, sum_u = 0, sum_f = 0;
    for (size_t k = 0; k < patch.nodes.size(); ++k) {
      const double s = patch.radius[k] / a;
      if (s <= kLo || s >= kHi) continue;
      const double w = std::pow(std::sin(M_PI * (s - kLo) / (kHi - kLo)), 2);
      sum_w += w;
      sum_u += w * disp[patch.nodes[k]];
      sum_f += w * hertz_surface_profile(s);
    }
    if (sum_w <= 0) return 0.0;
    const double u_ring = sum_u / sum_w, f_ring = sum_f / sum_w;
    const double next = std::max(0.0, (u_c - u_ring) / (1.0 - f_ring));
    if (std::fabs(next - delta_b) <= 1e-6 * (delta_p + next)) return next;
    delta_b = next;
  }
  return delta_b;
}

bool hertz_pressure_weights(const SurfacePatch& patch, const std::vector<double>& node_area,
                            double a, std::vector<double>& weights, int min_nodes)
{
  weights.assign(patch.nodes.size(), 0.0);
  double sum = 0;
  int inside = 0;
  for (size_t k = 0; k < patch.nodes.size(); ++k) {
    const double s = patch.radius[k] / a;
    if (s >= 1.0) continue;
    weights[k] = node_area[patch.nodes[k]] * std::sqrt(1.0 - s * s);
    sum += weights[k];
    ++inside;
  }
  if (inside < min_nodes || sum <= 0) {
    weights.clear();
    return false;
  }
  for (double& w : weights)
    w /= sum;
  return true;
}

} // namespace fracdem
