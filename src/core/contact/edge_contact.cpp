// Edge-to-edge penalty contact between 3D surfaces: closest points, penalty, friction, spread.
#include "contact/edge_contact.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace fracdem
{

namespace
{
inline double dot3(const double* a, const double* b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

inline void cross3(const double* a, const double* b, double* c)
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

// Outward normal of an edge (not normalised: only its direction is used).
void edge_normal(const ContactSurface& s, const SurfaceEdge& e, const double* x, double* n)
{
  double n0[3], n1[3];
  facet_unit_normal(x, s.facets[e.facet[0]], n0);
  facet_unit_normal(x, s.facets[e.facet[1]], n1);
  for (int d = 0; d < 3; ++d)
    n[d] = n0[d] + n1[d];
}

// Largest per-axis displacement of the surface's nodes since x0 (infinity: no x0 of this size).
double travel(const std::vector<int>& nodes, const double* x, const std::vector<double>& x0)
{
  if (x0.size() != 3 * nodes.size()) return std::numeric_limits<double>::infinity();
  double m = 0;
  for (size_t i = 0; i < nodes.size(); ++i)
    for (int d = 0; d < 3; ++d)
      m = std::max(m, std::fabs(x[3 * nodes[i] + d] - x0[3 * i + d]));
  return m;
}

void remember(const std::vector<int>& nodes, const double* x, std::vector<double>& x0)
{
  x0.resize(3 * nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i)
    for (int d = 0; d < 3; ++d)
      x0[3 * i + d] = x[3 * nodes[i] + d];
}

// The feature edges among `edges` (all of s's when null), and their nodes, ascending.
void feature_edges(const ContactSurface& s, const std::vector<int>* edges, std::vector<int>& feat,
                   std::vector<int>* nodes)
{
  feat.clear();
  const int n = edges ? static_cast<int>(edges->size()) : static_cast<int>(s.edges.size());
  for (int i = 0; i < n; ++i) {
    const int k = edges ? (*edges)[i] : i;
    if (s.edges[k].feature) feat.push_back(k);
  }
  if (!nodes) return;
  nodes->clear();
  for (int k : feat)
    nodes->insert(nodes->end(), s.edges[k].n, s.edges[k].n + 2);
  std::sort(nodes->begin(), nodes->end());
  nodes->erase(std::unique(nodes->begin(), nodes->end()), nodes->end());
}

// Whether node p's site (p, or its split parent or copies) is a corner of edge e's facets.
bool on_facets(const ContactSurface& s, const SurfaceEdge& e, int p)
{
  const int site = s.site_of(p);
  for (int k : e.facet)
    for (int j = 0; j < 3; ++j)
      if (s.site_of(s.facets[k].n[j]) == site) return true;
  return false;
}
} // namespace

bool edges_adjacent(const ContactSurface& s, int e, int f)
{
  const SurfaceEdge& E = s.edges[e];
  const SurfaceEdge& F = s.edges[f];
  return on_facets(s, F, E.n[0]) || on_facets(s, F, E.n[1]) || on_facets(s, E, F.n[0]) ||
         on_facets(s, E, F.n[1]);
}

bool edge_touch(const ContactSurface& a, int ea, const double* xa, const ContactSurface& b, int eb,
                const double* xb, EdgeTouch& t)
{
  const SurfaceEdge& E = a.edges[ea];
  const SurfaceEdge& F = b.edges[eb];
  const double* a0 = &xa[3 * E.n[0]];
  const double* a1 = &xa[3 * E.n[1]];
  const double* b0 = &xb[3 * F.n[0]];
  const double* b1 = &xb[3 * F.n[1]];
  double d1[3], d2[3], r[3];
  for (int d = 0; d < 3; ++d) {
    d1[d] = a1[d] - a0[d];
    d2[d] = b1[d] - b0[d];
    r[d] = a0[d] - b0[d];
  }
  // Closest points of the two lines (the 2 x 2 normal equations).
  const double aa = dot3(d1, d1), ab = dot3(d1, d2), bb = dot3(d2, d2);
  const double ar = dot3(d1, r), br = dot3(d2, r);
  const double den = aa * bb - ab * ab; // |d1 x d2|^2
  const double ps = EdgeContact::kParallelSin;
  if (!(den > ps * ps * aa * bb)) return false;
  const double s = (ab * br - bb * ar) / den;
  const double u = (aa * br - ab * ar) / den;
  if (!(s > 0 && s < 1 && u > 0 && u < 1)) return false;
  double n[3], nb[3], na[3];
  cross3(d1, d2, n);
  const double len = std::sqrt(dot3(n, n));
  for (int d = 0; d < 3; ++d)
    n[d] /= len;
  edge_normal(b, F, xb, nb);
  if (dot3(n, nb) < 0)
    for (int d = 0; d < 3; ++d)
      n[d] = -n[d];
  edge_normal(a, E, xa, na);
  if (!(dot3(n, na) < 0)) return false; // A's outside does not face B
  double gap = 0;
  for (int d = 0; d < 3; ++d) {
    t.pa[d] = a0[d] + s * d1[d];
    t.pb[d] = b0[d] + u * d2[d];
    gap += (t.pb[d] - t.pa[d]) * n[d];
  }
  if (!(gap > 0) || gap > std::min(E.reach, F.reach)) return false;
  t.ea = ea;
  t.eb = eb;
  t.s = s;
  t.t = u;
  t.depth = gap;
  std::copy(n, n + 3, t.normal);
  return true;
}

/* ---------------------------------------------------------------------- */

// A pair at distance <= reach_ now was, at the build, at most reach_ + (the two sides' travel)
// apart per axis; the search inflates both sides by reach_, so it finds every such pair until
// the travel exceeds reach_.
bool EdgeContact::needs_rebuild(const ContactSurface& a, const double* xa, const ContactSurface& b,
                                const double* xb) const
{
  if (restricted_) return travel(watch_a_, xa, xa0_) + travel(watch_b_, xb, xb0_) > reach_;
  return travel(a.nodes, xa, xa0_) + travel(b.nodes, xb, xb0_) > reach_;
}

void EdgeContact::restrict_search(std::vector<int> edges_a, std::vector<int> edges_b)
{
  restricted_ = true;
  only_a_ = std::move(edges_a);
  only_b_ = std::move(edges_b);
  stale_ = true;
}

void EdgeContact::rebuild_search(const ContactSurface& a, const double* xa, const ContactSurface& b,
                                 const double* xb)
{
  feature_edges(a, restricted_ ? &only_a_ : nullptr, feat_a_, restricted_ ? &watch_a_ : nullptr);
  feature_edges(b, restricted_ ? &only_b_ : nullptr, feat_b_, restricted_ ? &watch_b_ : nullptr);
  reach_ = std::min(a.max_edge_reach, b.max_edge_reach);
  // A's edges as spheres around their midpoints (they cover the segment), B's as boxes.
  std::vector<double> spheres(4 * feat_a_.size());
  for (size_t i = 0; i < feat_a_.size(); ++i) {
    const SurfaceEdge& e = a.edges[feat_a_[i]];
    double l2 = 0;
    for (int d = 0; d < 3; ++d) {
      const double p = xa[3 * e.n[0] + d], q = xa[3 * e.n[1] + d];
      spheres[4 * i + d] = 0.5 * (p + q);
      l2 += (q - p) * (q - p);
    }
    spheres[4 * i + 3] = 0.5 * std::sqrt(l2) * (1 + 1e-12);
  }
  std::vector<Aabb> boxes(feat_b_.size());
  for (size_t i = 0; i < feat_b_.size(); ++i) {
    const SurfaceEdge& e = b.edges[feat_b_[i]];
    for (int d = 0; d < 3; ++d) {
      boxes[i].lo[d] = std::min(xb[3 * e.n[0] + d], xb[3 * e.n[1] + d]);
      boxes[i].hi[d] = std::max(xb[3 * e.n[0] + d], xb[3 * e.n[1] + d]);
    }
  }
  search_ = BufferedSearch(2 * reach_);
  search_.build(boxes, spheres.data(), static_cast<int>(feat_a_.size()));
  remember(restricted_ ? watch_a_ : a.nodes, xa, xa0_);
  remember(restricted_ ? watch_b_ : b.nodes, xb, xb0_);
  stale_ = false;
}

std::vector<std::pair<int, int>> EdgeContact::candidates() const
{
  std::vector<std::pair<int, int>> out;
  for (const auto& c : search_.candidates())
    out.emplace_back(feat_a_[c.first], feat_b_[c.second]);
  return out;
}

// SurfaceContact::effective_depth's rule for an edge pair: the penetration less the part the
// relative approach of the step cannot have produced.
double EdgeContact::effective_depth(const std::array<int, 4>& key, const EdgeTouch& t, double dt)
{
  const Record probe{key, 0, 0};
  const auto it = std::lower_bound(last_.begin(), last_.end(), probe);
  const bool continued = it != last_.end() && it->key == key;
  const double before = continued ? it->depth : 0.0;
  double offset = continued ? it->offset : 0.0;
  const double approach = -dot3(t.vr, t.normal);
  const double explained = 2 * std::max(approach, 0.0) * dt;
  offset += std::max(t.depth - before - explained, 0.0);
  offset = std::min(offset, t.depth);
  next_.push_back({key, t.depth, offset});
  return t.depth - offset;
}

// The four nodal forces of one contact force `force` acting at pA on A and opposite at pB on B:
// by the segment parameters, then the couple of the two points' offset cancelled (class notes).
void EdgeContact::spread(const EdgeTouch& t, const double* const* x, const double* force,
                         double (&f)[4][3])
{
  const double w[4] = {1 - t.s, t.s, -(1 - t.t), -t.t};
  double moment[3] = {0, 0, 0}; // about pB
  for (int k = 0; k < 4; ++k) {
    double rel[3], m[3];
    for (int d = 0; d < 3; ++d) {
      f[k][d] = w[k] * force[d];
      rel[d] = x[k][d] - t.pb[d];
    }
    cross3(rel, f[k], m);
    for (int d = 0; d < 3; ++d)
      moment[d] += m[d];
  }
  double d1[3], d2[3], ua[3], ub[3];
  for (int d = 0; d < 3; ++d) {
    d1[d] = x[1][d] - x[0][d];
    d2[d] = x[3][d] - x[2][d];
  }
  cross3(t.normal, d1, ua);
  cross3(t.normal, d2, ub);
  // alpha ua + beta ub = -moment (least squares: the moment's part along n is round-off).
  const double g11 = dot3(ua, ua), g12 = dot3(ua, ub), g22 = dot3(ub, ub);
  const double r1 = -dot3(moment, ua), r2 = -dot3(moment, ub);
  const double det = g11 * g22 - g12 * g12;
  if (!(det > 0)) return;
  const double alpha = (r1 * g22 - r2 * g12) / det, beta = (g11 * r2 - g12 * r1) / det;
  // +c n at an edge's first node and -c n at its second add the moment c n x (x1 - x0).
  for (int d = 0; d < 3; ++d) {
    f[0][d] += alpha * t.normal[d];
    f[1][d] -= alpha * t.normal[d];
    f[2][d] += beta * t.normal[d];
    f[3][d] -= beta * t.normal[d];
  }
}

void EdgeContact::apply(const EdgeTouch& t, const ContactSurface& a, const ContactBodyState& sa,
                        const ContactSurface& b, const ContactBodyState& sb, double dt) const
{
  const SurfaceEdge& E = a.edges[t.ea];
  const SurfaceEdge& F = b.edges[t.eb];
  const int node[4] = {E.n[0], E.n[1], F.n[0], F.n[1]};
  const double size = 0.5 * (std::sqrt(facet_measure(sb.x, b.facets[F.facet[0]])) +
                             std::sqrt(facet_measure(sb.x, b.facets[F.facet[1]])));
  const double fn = opt_.penalty_scale * opt_.youngs * size * t.depth;
  double force[3];
  for (int d = 0; d < 3; ++d)
    force[d] = fn * t.normal[d];
  const double vn = dot3(t.vr, t.normal);
  double vt[3];
  for (int d = 0; d < 3; ++d)
    vt[d] = t.vr[d] - vn * t.normal[d];
  const double speed = std::sqrt(dot3(vt, vt));
  if (opt_.friction > 0 && speed > 0) {
    // Inverse effective mass of pA against pB under the spread by (1 - s, s), (1 - t, t).
    const double w[4] = {1 - t.s, t.s, 1 - t.t, t.t};
    double winv = 0;
    for (int k = 0; k < 4; ++k) {
      const double m = (k < 2 ? sa.m : sb.m)[node[k]];
      if (m > 0) winv += w[k] * w[k] / m;
    }
    double ft = opt_.friction * fn;
    if (winv > 0) ft = std::min(ft, speed / (winv * dt));
    for (int d = 0; d < 3; ++d)
      force[d] -= ft * vt[d] / speed;
  }
  const double* x[4] = {&sa.x[3 * node[0]], &sa.x[3 * node[1]], &sb.x[3 * node[2]],
                        &sb.x[3 * node[3]]};
  double f[4][3];
  spread(t, x, force, f);
  for (int k = 0; k < 4; ++k) {
    double* out = k < 2 ? sa.f : sb.f;
    if (out)
      for (int d = 0; d < 3; ++d)
        out[3 * node[k] + d] += f[k][d];
  }
}

int EdgeContact::evaluate(const ContactSurface& a, const ContactBodyState& sa,
                          const ContactSurface& b, const ContactBodyState& sb, bool self, double dt,
                          const std::function<bool(int, int)>& keep)
{
  touches_.clear();
  next_.clear();
  if (!(a.max_edge_reach > 0 && b.max_edge_reach > 0)) { // no feature edges on a side
    last_.clear();
    return 0;
  }
  if (stale_ || needs_rebuild(a, sa.x, b, sb.x)) {
    rebuild_search(a, sa.x, b, sb.x);
    // Self contact: each unordered pair once, the edges around a corner never.
    if (self)
      search_.prune([&](int i, int j) {
        return feat_a_[i] < feat_b_[j] && !edges_adjacent(a, feat_a_[i], feat_b_[j]);
      });
  }
  for (const auto& c : search_.candidates()) {
    if (keep && !keep(feat_a_[c.first], feat_b_[c.second])) continue;
    EdgeTouch t;
    if (!edge_touch(a, feat_a_[c.first], sa.x, b, feat_b_[c.second], sb.x, t)) continue;
    const SurfaceEdge& E = a.edges[t.ea];
    const SurfaceEdge& F = b.edges[t.eb];
    for (int d = 0; d < 3; ++d)
      t.vr[d] = (1 - t.s) * sa.v[3 * E.n[0] + d] + t.s * sa.v[3 * E.n[1] + d] -
                (1 - t.t) * sb.v[3 * F.n[0] + d] - t.t * sb.v[3 * F.n[1] + d];
    t.depth = effective_depth({E.n[0], E.n[1], F.n[0], F.n[1]}, t, dt);
    apply(t, a, sa, b, sb, dt);
    touches_.push_back(t);
  }
  std::sort(next_.begin(), next_.end());
  last_.swap(next_);
  return static_cast<int>(touches_.size());
}

void EdgeContact::pack_state(std::vector<double>& out) const
{
  for (const Record& r : last_) {
    for (int k = 0; k < 4; ++k)
      out.push_back(static_cast<double>(r.key[k]));
    out.push_back(r.depth);
    out.push_back(r.offset);
  }
}

void EdgeContact::unpack_state(const double* in, size_t n)
{
  if (n % 6 != 0) throw std::runtime_error("edge contact state: corrupt record");
  last_.clear();
  for (size_t k = 0; k < n; k += 6) {
    Record r;
    for (int j = 0; j < 4; ++j) {
      const double x = in[k + j];
      if (!(x >= 0 && x < 2147483647.0) || x != std::floor(x))
        throw std::runtime_error("edge contact state: corrupt record");
      r.key[j] = static_cast<int>(x);
    }
    r.depth = in[k + 4];
    r.offset = in[k + 5];
    last_.push_back(r);
  }
  std::sort(last_.begin(), last_.end());
}

} // namespace fracdem
