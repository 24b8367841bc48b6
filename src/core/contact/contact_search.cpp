// Uniform-bin broad phase for particle-facet contact with a displacement-triggered rebuild.
#include "contact/contact_search.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fracdem
{

Aabb node_box(const int* nodes, int nn, const double* x)
{
  Aabb b;
  for (int d = 0; d < 3; ++d) {
    b.lo[d] = std::numeric_limits<double>::max();
    b.hi[d] = -std::numeric_limits<double>::max();
  }
  for (int j = 0; j < nn; ++j)
    for (int d = 0; d < 3; ++d) {
      b.lo[d] = std::min(b.lo[d], x[3 * nodes[j] + d]);
      b.hi[d] = std::max(b.hi[d], x[3 * nodes[j] + d]);
    }
  return b;
}

namespace
{
inline bool overlap(const Aabb& f, const double* s, double h_f, double r_s)
{
  for (int d = 0; d < 3; ++d)
    if (f.lo[d] - h_f > s[d] + r_s || f.hi[d] + h_f < s[d] - r_s) return false;
  return true;
}
} // namespace

std::vector<std::pair<int, int>> brute_force_candidates(const std::vector<Aabb>& boxes,
                                                        const double* sxr, int ns, double buffer)
{
  std::vector<std::pair<int, int>> out;
  for (int s = 0; s < ns; ++s)
    for (int f = 0; f < static_cast<int>(boxes.size()); ++f)
      if (overlap(boxes[f], sxr + 4 * s, 0.5 * buffer, sxr[4 * s + 3] + 0.5 * buffer))
        out.emplace_back(s, f);
  return out;
}

void BufferedSearch::build(const std::vector<Aabb>& boxes, const double* sxr, int ns)
{
  candidates_.clear();
  const int nf = static_cast<int>(boxes.size());
  if (ns == 0 || nf == 0) return;
  const double hb = 0.5 * buffer_;
  // Grid over the spheres' inflated extent: facets elsewhere cannot be candidates.
  double lo[3], hi[3], rmax = 0;
  for (int d = 0; d < 3; ++d) {
    lo[d] = 1e300;
    hi[d] = -1e300;
  }
  for (int s = 0; s < ns; ++s) {
    rmax = std::max(rmax, sxr[4 * s + 3]);
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], sxr[4 * s + d]);
      hi[d] = std::max(hi[d], sxr[4 * s + d]);
    }
  }
  const double reach = rmax + buffer_;
  double ext = 0;
  for (const Aabb& b : boxes)
    for (int d = 0; d < 3; ++d)
      ext = std::max(ext, b.hi[d] - b.lo[d]);
  // Cell: at least a sphere's reach; at most the largest facet extent unless that is smaller.
  double cell = std::max(2 * reach, 1e-300);
  double avg = 0;
  for (const Aabb& b : boxes)
    avg += std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]});
  avg /= nf;
  cell = std::max(cell, avg);
  int n[3];
  long long total = 1;
  for (int d = 0; d < 3; ++d) {
    lo[d] -= reach;
    hi[d] += reach;
    n[d] = std::max(1, static_cast<int>(std::ceil((hi[d] - lo[d]) / cell)));
  }
  // Cap the grid size so sparse scenes do not allocate huge empty grids.
  const long long cap = 8LL * (nf + ns) + 64;
  while (static_cast<long long>(n[0]) * n[1] * n[2] > cap) {
    cell *= 1.5;
    for (int d = 0; d < 3; ++d)
      n[d] = std::max(1, static_cast<int>(std::ceil((hi[d] - lo[d]) / cell)));
  }
  total = static_cast<long long>(n[0]) * n[1] * n[2];
  auto cell_range = [&](double a, double b, int d, int& i0, int& i1) {
    i0 = static_cast<int>(std::floor((a - lo[d]) / cell));
    i1 = static_cast<int>(std::floor((b - lo[d]) / cell));
    i0 = std::max(i0, 0);
    i1 = std::min(i1, n[d] - 1);
  };
  // Counting sort of facets into every bin their inflated box touches.
  bin_start_.assign(total + 1, 0);
  std::vector<int>& rng = ranges_; // scratch kept between builds: no allocation per build
  rng.resize(6 * nf);
  for (int f = 0; f < nf; ++f) {
    int* r = &rng[6 * f];
    bool inside = true;
    for (int d = 0; d < 3; ++d) {
      cell_range(boxes[f].lo[d] - hb, boxes[f].hi[d] + hb, d, r[2 * d], r[2 * d + 1]);
      if (r[2 * d] > r[2 * d + 1]) inside = false;
    }
    if (!inside) {
      r[0] = 1;
      r[1] = 0;
      continue;
    }
    for (int k = r[4]; k <= r[5]; ++k)
      for (int j = r[2]; j <= r[3]; ++j)
        for (int i = r[0]; i <= r[1]; ++i)
          ++bin_start_[(static_cast<long long>(k) * n[1] + j) * n[0] + i + 1];
  }
  for (long long b = 0; b < total; ++b)
    bin_start_[b + 1] += bin_start_[b];
  bin_items_.assign(bin_start_[total], 0);
  std::vector<int>& fill = fill_;
  fill.assign(bin_start_.begin(), bin_start_.end() - 1);
  for (int f = 0; f < nf; ++f) {
    const int* r = &rng[6 * f];
    if (r[0] > r[1]) continue;
    for (int k = r[4]; k <= r[5]; ++k)
      for (int j = r[2]; j <= r[3]; ++j)
        for (int i = r[0]; i <= r[1]; ++i)
          bin_items_[fill[(static_cast<long long>(k) * n[1] + j) * n[0] + i]++] = f;
  }
  stamp_.assign(nf, -1);
  std::vector<int>& found = found_;
  for (int s = 0; s < ns; ++s) {
    const double* c = sxr + 4 * s;
    const double rs = c[3] + hb;
    int r[6];
    for (int d = 0; d < 3; ++d)
      cell_range(c[d] - rs, c[d] + rs, d, r[2 * d], r[2 * d + 1]);
    found.clear();
    for (int k = r[4]; k <= r[5]; ++k)
      for (int j = r[2]; j <= r[3]; ++j)
        for (int i = r[0]; i <= r[1]; ++i) {
          const long long b = (static_cast<long long>(k) * n[1] + j) * n[0] + i;
          for (int q = bin_start_[b]; q < bin_start_[b + 1]; ++q) {
            const int f = bin_items_[q];
            if (stamp_[f] == s) continue;
            stamp_[f] = s;
            if (overlap(boxes[f], c, hb, rs)) found.push_back(f);
          }
        }
    std::sort(found.begin(), found.end());
    for (int f : found)
      candidates_.emplace_back(s, f);
  }
}

void BufferedSearch::remember_positions(const double* node_x, int nnodes, const double* sphere_x,
                                        int ns)
{
  node_x0_.assign(node_x, node_x + 3 * nnodes);
  sphere_x0_.assign(sphere_x, sphere_x + 3 * ns);
}

bool BufferedSearch::needs_rebuild(const double* node_x, int nnodes, const double* sphere_x,
                                   int ns) const
{
  if (static_cast<int>(sphere_x0_.size()) != 3 * ns) return true;
  const double dn = node_travel(node_x, nnodes);
  double ds = 0;
  for (int k = 0; k < 3 * ns; ++k)
    ds = std::max(ds, std::fabs(sphere_x[k] - sphere_x0_[k]));
  return dn + ds > buffer_;
}

double BufferedSearch::node_travel(const double* node_x, int nnodes, double* node_shift) const
{
  if (static_cast<int>(node_x0_.size()) != 3 * nnodes)
    return std::numeric_limits<double>::infinity();
  double dn = 0, shift2 = 0;
  for (int v = 0; v < nnodes; ++v) {
    double l2 = 0;
    for (int d = 0; d < 3; ++d) {
      const double u = node_x[3 * v + d] - node_x0_[3 * v + d];
      dn = std::max(dn, std::fabs(u));
      l2 += u * u;
    }
    shift2 = std::max(shift2, l2);
  }
  if (node_shift) *node_shift = std::sqrt(shift2) * (1 + 1e-12);
  return dn;
}

} // namespace fracdem
