// Buffer-zone candidate search between spheres and facets (paper eqs. 1-2), uniform bins.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace fracdem
{

struct Aabb {
  double lo[3], hi[3];
};

// The bounding box of nodes nodes[0..nn) at positions x (3 per node): a facet's, for the search.
Aabb node_box(const int* nodes, int nn, const double* x);

// Facet boxes are inflated by buffer/2 and spheres by radius + buffer/2, so a pair can only be
// missed once the relative approach exceeds `buffer`. The relative approach per axis is at most
// (largest sphere displacement) + (largest node displacement) since the build, which is what
// needs_rebuild() compares with the buffer: the search is redone only when that bound is used up.
class BufferedSearch
{
public:
  explicit BufferedSearch(double buffer) : buffer_(buffer) {}
  void build(const std::vector<Aabb>& facet_boxes, const double* sphere_xr, int nspheres);
  // (sphere, facet) pairs whose inflated boxes overlap; sorted by sphere, then facet.
  const std::vector<std::pair<int, int>>& candidates() const { return candidates_; }
  // Drops the candidates for which keep(sphere, facet) is false; keep is called once per
  // candidate, in order, and the kept ones keep their order.
  template <class Keep> void prune(Keep keep)
  {
    size_t n = 0;
    for (const auto& c : candidates_)
      if (keep(c.first, c.second)) candidates_[n++] = c;
    candidates_.resize(n);
  }
  void remember_positions(const double* node_x, int nnodes, const double* sphere_x, int nspheres);
  bool needs_rebuild(const double* node_x, int nnodes, const double* sphere_x, int nspheres) const;
  // The nodes' part of needs_rebuild, for callers that track the spheres themselves: their
  // largest displacement along an axis since remember_positions (infinity when the node count
  // changed) and, in node_shift (optional), the largest Euclidean one.
  double node_travel(const double* node_x, int nnodes, double* node_shift = nullptr) const;
  double buffer() const { return buffer_; }

private:
  double buffer_;
  std::vector<std::pair<int, int>> candidates_;
  std::vector<double> node_x0_, sphere_x0_;
  std::vector<int> bin_start_, bin_items_, stamp_, ranges_, fill_, found_;
};

// O(N M) reference used by the tests.
std::vector<std::pair<int, int>> brute_force_candidates(const std::vector<Aabb>& facet_boxes,
                                                        const double* sphere_xr, int nspheres,
                                                        double buffer);

} // namespace fracdem
