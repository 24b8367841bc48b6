// Feature-based (Voronoi region) de-duplication of sphere-facet contacts.
#include "contact/contact_resolution.h"

#include <algorithm>
#include <cmath>

namespace fracdem
{

namespace
{
inline std::uint64_t edge_key(int a, int b)
{
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

void feature_nodes(const FacetHit& h, int out[3], int* m)
{
  if (h.cp.kind == Feature::Face) {
    *m = h.nn;
    for (int k = 0; k < h.nn; ++k)
      out[k] = h.nodes[k];
  } else if (h.cp.kind == Feature::Edge) {
    *m = 2;
    out[0] = h.nodes[h.cp.local];
    out[1] = h.nodes[(h.cp.local + 1) % h.nn];
  } else {
    *m = 1;
    out[0] = h.nodes[h.cp.local];
  }
  std::sort(out, out + *m);
}

bool subset(const int* a, int m, const int* b, int n)
{
  for (int i = 0; i < m; ++i)
    if (std::find(b, b + n, a[i]) == b + n) return false;
  return true;
}

// Tolerance relative to |q - p|: features exactly on a region boundary stay valid (the face hit
// next to them is then either absent or the same contact, removed as covered).
constexpr double kTol = 1e-10;

bool edge_region(const FacetHit& h, const double q[3], const double* x, const SurfaceTopology& t)
{
  const int a = h.nodes[h.cp.local], b = h.nodes[(h.cp.local + 1) % h.nn];
  auto it = t.edge_apex.find(edge_key(a, b));
  if (it == t.edge_apex.end()) return true;
  const double* pa = x + 3 * a;
  const double* pb = x + 3 * b;
  double e[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
  const double ee = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
  double d[3] = {q[0] - h.cp.p[0], q[1] - h.cp.p[1], q[2] - h.cp.p[2]};
  const double dl = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (int w : it->second) {
    const double* pw = x + 3 * w;
    // in-plane direction from the apex across the edge, perpendicular to the edge
    double s[3] = {pa[0] - pw[0], pa[1] - pw[1], pa[2] - pw[2]};
    const double se = (s[0] * e[0] + s[1] * e[1] + s[2] * e[2]) / ee;
    for (int k = 0; k < 3; ++k)
      s[k] -= se * e[k];
    const double sl = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    if (sl == 0) continue;
    if ((d[0] * s[0] + d[1] * s[1] + d[2] * s[2]) / sl < -kTol * dl) return false;
  }
  return true;
}

bool vertex_region(int v, const double q[3], const double* x, const SurfaceTopology& t)
{
  const double* pv = x + 3 * v;
  double d[3] = {q[0] - pv[0], q[1] - pv[1], q[2] - pv[2]};
  const double dl = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (int w : t.node_neighbors[v]) {
    const double* pw = x + 3 * w;
    double s[3] = {pw[0] - pv[0], pw[1] - pv[1], pw[2] - pv[2]};
    const double sl = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    if ((d[0] * s[0] + d[1] * s[1] + d[2] * s[2]) > kTol * dl * sl) return false;
  }
  return true;
}
} // namespace

void SurfaceTopology::build(const std::vector<Facet>& facets, int nnodes)
{
  node_neighbors.assign(nnodes, {});
  edge_apex.clear();
  for (const Facet& f : facets) {
    for (int k = 0; k < f.nn; ++k) {
      const int a = f.n[k], b = f.n[(k + 1) % f.nn];
      if (f.nn == 2 && k == 1) break; // a segment has one edge
      node_neighbors[a].push_back(b);
      node_neighbors[b].push_back(a);
      if (f.nn == 3) edge_apex[edge_key(a, b)].push_back(f.n[(k + 2) % 3]);
    }
  }
  for (auto& nb : node_neighbors) {
    std::sort(nb.begin(), nb.end());
    nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
  }
}

std::uint64_t feature_key(const FacetHit& h)
{
  int nodes[3], m;
  feature_nodes(h, nodes, &m);
  // 21 bits per node id (2M nodes); unused slots all ones, so the kind is part of the key.
  std::uint64_t key = 0;
  for (int i = 0; i < 3; ++i) {
    const std::uint64_t v = i < m ? static_cast<std::uint64_t>(nodes[i]) & 0x1FFFFF : 0x1FFFFF;
    key = (key << 21) | v;
  }
  return key;
}

std::vector<FacetHit> resolve_sphere_hits(std::vector<FacetHit> hits, const double q[3],
                                          const double* x, const SurfaceTopology& topo)
{
  std::stable_sort(hits.begin(), hits.end(),
                   [](const FacetHit& a, const FacetHit& b) { return a.facet < b.facet; });
  std::vector<FacetHit> kept;
  for (Feature kind : {Feature::Face, Feature::Edge, Feature::Vertex}) {
    for (const FacetHit& h : hits) {
      if (h.cp.kind != kind) continue;
      if (kind == Feature::Edge && !edge_region(h, q, x, topo)) continue;
      if (kind == Feature::Vertex && !vertex_region(h.nodes[h.cp.local], q, x, topo)) continue;
      int nodes[3], m;
      feature_nodes(h, nodes, &m);
      bool covered = false;
      if (kind != Feature::Face)
        for (const FacetHit& k : kept) {
          int kn[3], km;
          feature_nodes(k, kn, &km);
          if (subset(nodes, m, kn, km)) {
            covered = true;
            break;
          }
        }
      if (!covered) kept.push_back(h);
    }
  }
  return kept;
}

} // namespace fracdem

namespace fracdem
{

std::vector<std::vector<int>> cluster_hits(const double* nrm, const double* ov, int n,
                                           const int* pieces, double cmax)
{
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i)
    order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return ov[a] > ov[b]; });
  std::vector<std::vector<int>> clusters;
  for (int i : order) {
    bool placed = false;
    for (auto& c : clusters) {
      if (pieces && pieces[c[0]] != pieces[i]) continue;
      const double* l = nrm + 3 * c[0];
      const double* m = nrm + 3 * i;
      if (l[0] * m[0] + l[1] * m[1] + l[2] * m[2] >= cmax) {
        c.push_back(i);
        placed = true;
        break;
      }
    }
    if (!placed) clusters.push_back({i});
  }
  return clusters;
}

} // namespace fracdem
