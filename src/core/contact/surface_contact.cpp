// Node-to-facet penalty contact between the pieces of a body's surface.
#include "contact/surface_contact.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fracdem
{

namespace
{
constexpr double kBaryTol = 0.01;

double facet_size(const double* a, const double* b, const double* c)
{
  const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  if (!c) return std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
  const double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
  return std::sqrt(0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]));
}
} // namespace

void SurfaceContact::rebuild(const Mesh& mesh, const std::vector<Facet>& facets)
{
  mesh_ = &mesh;
  facets_ = facets;
  nodes_.clear();
  double hmax = 0;
  for (const Facet& fc : facets_) {
    for (int j = 0; j < fc.nn; ++j)
      nodes_.push_back(fc.n[j]);
    const double* X = mesh.X.data();
    hmax = std::max(
        hmax, facet_size(&X[3 * fc.n[0]], &X[3 * fc.n[1]], fc.nn == 3 ? &X[3 * fc.n[2]] : nullptr));
  }
  std::sort(nodes_.begin(), nodes_.end());
  nodes_.erase(std::unique(nodes_.begin(), nodes_.end()), nodes_.end());
  const int nn = mesh.num_nodes();
  incident_offset_.assign(nn + 1, 0);
  for (const Facet& fc : facets_)
    for (int j = 0; j < fc.nn; ++j)
      ++incident_offset_[fc.n[j] + 1];
  for (int i = 0; i < nn; ++i)
    incident_offset_[i + 1] += incident_offset_[i];
  incident_.assign(incident_offset_[nn], 0);
  std::vector<int> fill(incident_offset_.begin(), incident_offset_.end() - 1);
  for (int k = 0; k < static_cast<int>(facets_.size()); ++k)
    for (int j = 0; j < facets_[k].nn; ++j)
      incident_[fill[facets_[k].n[j]]++] = k;
  // The search reach covers the deepest accepted contact (half the largest facet).
  buffer_ = facets_.empty() ? 0.0 : 0.5 * hmax;
  search_ = BufferedSearch(buffer_);
  stale_ = true;
}

// Outward unit normal of the facet, the node's signed distance from its plane, and the
// barycentric weights of the node's projection.
bool SurfaceContact::neighbourhood(int node, int facet) const
{
  const Facet& fc = facets_[facet];
  for (int k = incident_offset_[node]; k < incident_offset_[node + 1]; ++k) {
    const Facet& g = facets_[incident_[k]];
    for (int i = 0; i < g.nn; ++i)
      for (int j = 0; j < fc.nn; ++j)
        if (g.n[i] == fc.n[j]) return true;
  }
  return false;
}

bool SurfaceContact::touch(int node, int facet, const double* x, Touch& t) const
{
  const Facet& fc = facets_[facet];
  if (neighbourhood(node, facet)) return false;
  const double* q = &x[3 * node];
  const double* a = &x[3 * fc.n[0]];
  const double* b = &x[3 * fc.n[1]];
  double n[3], size;
  if (fc.nn == 2) {
    const double e[2] = {b[0] - a[0], b[1] - a[1]};
    size = std::sqrt(e[0] * e[0] + e[1] * e[1]);
    if (!(size > 0)) return false;
    n[0] = e[1] / size, n[1] = -e[0] / size, n[2] = 0; // (dy, -dx): out of the owning element
    const double s = ((q[0] - a[0]) * e[0] + (q[1] - a[1]) * e[1]) / (size * size);
    t.w[0] = 1 - s, t.w[1] = s, t.w[2] = 0;
  } else {
    const double* c = &x[3 * fc.n[2]];
    const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                    e1[0] * e2[1] - e1[1] * e2[0]};
    const double area2 = std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
    if (!(area2 > 0)) return false;
    size = std::sqrt(0.5 * area2);
    for (int d = 0; d < 3; ++d)
      n[d] = cr[d] / area2;
    // Barycentric weights of the projection (areas of the sub-triangles along n).
    const double* p[3] = {a, b, c};
    for (int j = 0; j < 3; ++j) {
      const double* u = p[(j + 1) % 3];
      const double* w = p[(j + 2) % 3];
      const double du[3] = {u[0] - q[0], u[1] - q[1], u[2] - q[2]};
      const double dw[3] = {w[0] - q[0], w[1] - q[1], w[2] - q[2]};
      const double sub[3] = {du[1] * dw[2] - du[2] * dw[1], du[2] * dw[0] - du[0] * dw[2],
                             du[0] * dw[1] - du[1] * dw[0]};
      t.w[j] = (sub[0] * n[0] + sub[1] * n[1] + sub[2] * n[2]) / area2;
    }
  }
  for (int j = 0; j < fc.nn; ++j)
    if (t.w[j] < -kBaryTol) return false;
  const double dist = (q[0] - a[0]) * n[0] + (q[1] - a[1]) * n[1] + (q[2] - a[2]) * n[2];
  if (!(dist < 0) || -dist > 0.5 * size) return false;
  t.facet = facet;
  t.depth = -dist;
  std::copy(n, n + 3, t.normal);
  return true;
}

double SurfaceContact::stiffness(int node, int facet, const double* x) const
{
  const Facet& fc = facets_[facet];
  double t = opt_.thickness;
  if (fc.nn == 3)
    t = facet_size(&x[3 * fc.n[0]], &x[3 * fc.n[1]], &x[3 * fc.n[2]]);
  else if (opt_.axisymmetric)
    t = 2 * M_PI * std::max(x[3 * node], 0.0);
  return opt_.penalty_scale * opt_.youngs * t;
}

void SurfaceContact::apply(int node, const Touch& t, const double* x, const double* v,
                           const double* m, double dt, double* f) const
{
  const Facet& fc = facets_[t.facet];
  const double fn = stiffness(node, t.facet, x) * t.depth;
  double force[3];
  for (int d = 0; d < 3; ++d)
    force[d] = fn * t.normal[d];
  if (opt_.friction > 0) {
    double vr[3];
    for (int d = 0; d < 3; ++d) {
      vr[d] = v[3 * node + d];
      for (int j = 0; j < fc.nn; ++j)
        vr[d] -= t.w[j] * v[3 * fc.n[j] + d];
    }
    const double vn = vr[0] * t.normal[0] + vr[1] * t.normal[1] + vr[2] * t.normal[2];
    double vt[3];
    for (int d = 0; d < 3; ++d)
      vt[d] = vr[d] - vn * t.normal[d];
    const double speed = std::sqrt(vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]);
    if (speed > 0) {
      const double ft = std::min(opt_.friction * fn, m[node] * speed / dt);
      for (int d = 0; d < 3; ++d)
        force[d] -= ft * vt[d] / speed;
    }
  }
  for (int d = 0; d < 3; ++d) {
    f[3 * node + d] += force[d];
    for (int j = 0; j < fc.nn; ++j)
      f[3 * fc.n[j] + d] -= t.w[j] * force[d];
  }
}

int SurfaceContact::evaluate(const double* x, const double* v, const double* m, double dt,
                             double* f)
{
  if (facets_.empty()) return 0;
  const int ns = static_cast<int>(nodes_.size());
  sx_.resize(3 * ns);
  for (int s = 0; s < ns; ++s)
    for (int d = 0; d < 3; ++d)
      sx_[3 * s + d] = x[3 * nodes_[s] + d];
  // Facet nodes are boundary nodes too: the relative approach is at most twice their largest
  // motion, which needs_rebuild bounds by counting them as both nodes and spheres.
  if (stale_ || search_.needs_rebuild(sx_.data(), ns, sx_.data(), ns)) {
    std::vector<Aabb> boxes(facets_.size());
    for (size_t k = 0; k < facets_.size(); ++k) {
      for (int d = 0; d < 3; ++d) {
        boxes[k].lo[d] = std::numeric_limits<double>::max();
        boxes[k].hi[d] = -std::numeric_limits<double>::max();
      }
      for (int j = 0; j < facets_[k].nn; ++j)
        for (int d = 0; d < 3; ++d) {
          boxes[k].lo[d] = std::min(boxes[k].lo[d], x[3 * facets_[k].n[j] + d]);
          boxes[k].hi[d] = std::max(boxes[k].hi[d], x[3 * facets_[k].n[j] + d]);
        }
    }
    sphere_.assign(4 * ns, 0.0);
    for (int s = 0; s < ns; ++s)
      for (int d = 0; d < 3; ++d)
        sphere_[4 * s + d] = sx_[3 * s + d];
    search_.build(boxes, sphere_.data(), ns);
    search_.remember_positions(sx_.data(), ns, sx_.data(), ns);
    stale_ = false;
  }
  const auto& cand = search_.candidates();
  int contacts = 0;
  size_t c = 0;
  while (c < cand.size()) {
    const int s = cand[c].first;
    Touch best;
    for (; c < cand.size() && cand[c].first == s; ++c) {
      Touch t;
      if (touch(nodes_[s], cand[c].second, x, t) && t.depth > best.depth) best = t;
    }
    if (best.facet >= 0) {
      apply(nodes_[s], best, x, v, m, dt, f);
      ++contacts;
    }
  }
  return contacts;
}

} // namespace fracdem
