// Node-to-facet penalty contact between body surfaces (pieces of one body, or two bodies).
#include "contact/surface_contact.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "contact/geometry.h"

namespace fracdem
{

namespace
{
constexpr double kBaryTol = 0.01;

// Length of an edge facet, square root of a triangle facet's area.
double facet_size(const double* x, const Facet& fc)
{
  const double m = facet_measure(x, fc);
  return fc.nn == 3 ? std::sqrt(m) : m;
}
} // namespace

void facet_unit_normal(const double* x, const Facet& fc, double* n)
{
  facet_normal(x, fc.n.data(), 3, n);
  const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int d = 0; d < 3; ++d)
    n[d] = l > 0 ? n[d] / l : 0.0;
}

double facet_reach(const Mesh& mesh, const Facet& fc)
{
  const double s = facet_size(mesh.X.data(), fc);
  // Altitude of the owning element over the facet: 2A/L (tri3), A/L (quad4), 3V/area (tet4).
  const double measure = std::fabs(signed_measure(mesh, fc.elem));
  const ElemType t = mesh.etype[fc.elem];
  const double altitude = t == ElemType::Tet4   ? 3 * measure / (s * s)
                          : t == ElemType::Tri3 ? 2 * measure / s
                                                : measure / s;
  return 0.5 * altitude;
}

// Free nodes: every element around them eroded (erosion_mass keep leaves their mass on them, and
// they fly on as point masses). They have no facet of their own, so they still hit surfaces as
// contacting nodes of the body (issue #10: free nodes can still hit surfaces). Nodes of no
// element at all (none in a mesh as read) are not surface.
std::vector<int> free_nodes(const Mesh& mesh)
{
  const int nn = mesh.num_nodes();
  std::vector<std::uint8_t> in_elem(nn, 0), in_live(nn, 0);
  bool eroded = false;
  for (int e = 0; e < mesh.num_elems(); ++e) {
    eroded = eroded || !mesh.active[e];
    for (int n : mesh.conn[e])
      if (n >= 0) {
        in_elem[n] = 1;
        in_live[n] = in_live[n] || mesh.active[e];
      }
  }
  std::vector<int> out;
  if (!eroded) return out;
  for (int n = 0; n < nn; ++n)
    if (in_elem[n] && !in_live[n]) out.push_back(n);
  return out;
}

void ContactSurface::build(const Mesh& mesh, const std::vector<Facet>& boundary)
{
  std::vector<double> r(boundary.size());
  for (size_t k = 0; k < boundary.size(); ++k)
    r[k] = facet_reach(mesh, boundary[k]);
  build(boundary, r, mesh.X.data(), mesh.num_nodes(), free_nodes(mesh));
}

void ContactSurface::build(const std::vector<Facet>& boundary, const std::vector<double>& reaches,
                           const double* X, int num_nodes, const std::vector<int>& free)
{
  facets = boundary;
  reach = reaches;
  max_reach = 0;
  nodes.clear();
  for (size_t k = 0; k < facets.size(); ++k) {
    const Facet& fc = facets[k];
    for (int j = 0; j < fc.nn; ++j)
      nodes.push_back(fc.n[j]);
    max_reach = std::max(max_reach, reach[k]);
  }
  nodes.insert(nodes.end(), free.begin(), free.end());
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  const int nn = num_nodes;
  incident_offset.assign(nn + 1, 0);
  for (const Facet& fc : facets)
    for (int j = 0; j < fc.nn; ++j)
      ++incident_offset[fc.n[j] + 1];
  for (int i = 0; i < nn; ++i)
    incident_offset[i + 1] += incident_offset[i];
  incident.assign(incident_offset[nn], 0);
  std::vector<int> fill(incident_offset.begin(), incident_offset.end() - 1);
  for (int k = 0; k < static_cast<int>(facets.size()); ++k)
    for (int j = 0; j < facets[k].nn; ++j)
      incident[fill[facets[k].n[j]]++] = k;
  build_sites(X, nn);
  build_edges(X);
}

// Surface nodes grouped by bitwise-equal reference coordinates (copies are exact copies).
void ContactSurface::build_sites(const double* X, int num_nodes)
{
  site.resize(num_nodes);
  for (int i = 0; i < num_nodes; ++i)
    site[i] = i;
  std::vector<int> order = nodes;
  const auto ref = [X](int i) {
    return std::array<double, 3>{X[3 * i], X[3 * i + 1], X[3 * i + 2]};
  };
  std::stable_sort(order.begin(), order.end(), [&](int p, int q) { return ref(p) < ref(q); });
  for (size_t i = 1; i < order.size(); ++i)
    if (ref(order[i]) == ref(order[i - 1])) site[order[i]] = site[order[i - 1]];
}

// Edges shared by exactly two boundary triangles, sorted by their nodes; feature test on the
// reference coordinates (a rigid motion does not change it; rebuilt after every topology change).
void ContactSurface::build_edges(const double* X)
{
  edges.clear();
  max_edge_reach = 0;
  std::vector<std::array<int, 3>> sides; // (lower node, higher node, facet)
  for (int k = 0; k < static_cast<int>(facets.size()); ++k) {
    if (facets[k].nn != 3) return; // 2D: no edge contact
    for (int j = 0; j < 3; ++j) {
      const int p = facets[k].n[j], q = facets[k].n[(j + 1) % 3];
      sides.push_back({std::min(p, q), std::max(p, q), k});
    }
  }
  std::sort(sides.begin(), sides.end());
  const double cos_feature = std::cos(kFeatureAngleDeg * M_PI / 180);
  for (size_t i = 0; i < sides.size();) {
    size_t j = i;
    while (j < sides.size() && sides[j][0] == sides[i][0] && sides[j][1] == sides[i][1])
      ++j;
    if (j - i == 2) {
      SurfaceEdge e{{sides[i][0], sides[i][1]}, {sides[i][2], sides[i + 1][2]}, 0, false};
      e.reach = std::min(reach[e.facet[0]], reach[e.facet[1]]);
      double n0[3], n1[3];
      facet_unit_normal(X, facets[e.facet[0]], n0);
      facet_unit_normal(X, facets[e.facet[1]], n1);
      // Convex: the far vertex of the second facet lies behind the first facet's plane.
      const Facet& f1 = facets[e.facet[1]];
      const int far = f1.n[0] != e.n[0] && f1.n[0] != e.n[1]   ? f1.n[0]
                      : f1.n[1] != e.n[0] && f1.n[1] != e.n[1] ? f1.n[1]
                                                               : f1.n[2];
      double r[3], rr = 0, behind = 0;
      for (int d = 0; d < 3; ++d) {
        r[d] = X[3 * far + d] - X[3 * e.n[0] + d];
        rr += r[d] * r[d];
        behind += r[d] * n0[d];
      }
      const double dot = n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2];
      e.feature = dot < cos_feature && behind < -0.01 * std::sqrt(rr);
      if (e.feature) max_edge_reach = std::max(max_edge_reach, e.reach);
      edges.push_back(e);
    }
    i = j;
  }
}

bool ContactSurface::neighbourhood(int node, int facet) const
{
  const Facet& fc = facets[facet];
  for (int k = incident_offset[node]; k < incident_offset[node + 1]; ++k) {
    const Facet& g = facets[incident[k]];
    for (int i = 0; i < g.nn; ++i)
      for (int j = 0; j < fc.nn; ++j)
        if (g.n[i] == fc.n[j]) return true;
  }
  return false;
}

int ContactSurface::twin_corner(int node, int facet) const
{
  const Facet& fc = facets[facet];
  const int at = site_of(node);
  for (int j = 0; j < fc.nn; ++j)
    if (fc.n[j] != node && site_of(fc.n[j]) == at) return j;
  return -1;
}

bool ContactSurface::vertex_normal(const double* x, int node, double* n) const
{
  n[0] = n[1] = n[2] = 0;
  for (int k = incident_offset[node]; k < incident_offset[node + 1]; ++k) {
    double m[3];
    const Facet& fc = facets[incident[k]];
    facet_normal(x, fc.n.data(), fc.nn, m);
    const double l = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    for (int d = 0; d < 3; ++d)
      n[d] += l > 0 ? m[d] / l : 0.0;
  }
  const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  // Facets around the node that nearly cancel (a sliver fold): no direction to push along.
  const int count = incident_offset[node + 1] - incident_offset[node];
  if (!(l > 0.1 * count)) return false;
  for (int d = 0; d < 3; ++d)
    n[d] /= l;
  return true;
}

/* ---------------------------------------------------------------------- */

// The crack's normal at a split node and its copy, out of the copy's piece: the difference of
// the two vertex normals (faces the twins share, e.g. the body's outer faces at a crack's
// mouth, cancel; the crack's faces add).
bool SurfaceContact::twin_normal(const ContactSurface& s, int node, int copy, const double* x,
                                 double* n) const
{
  double nc[3], nn[3];
  if (!s.vertex_normal(x, copy, nc) || !s.vertex_normal(x, node, nn)) return false;
  for (int d = 0; d < 3; ++d)
    n[d] = nc[d] - nn[d];
  const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(l > 0.1)) return false;
  for (int d = 0; d < 3; ++d)
    n[d] /= l;
  return true;
}

// Outward unit normal of the facet (positions x), the signed distance of q from its plane, and
// the barycentric weights of q's projection.
bool SurfaceContact::touch(const double* q, const Facet& fc, double reach, const double* x,
                           Touch& t, int corner, const double* vn) const
{
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
  if (corner >= 0) {
    // The node's split copy is this corner: the penetration is the twins' closing along the
    // crack's normal vn there (twin_normal), the reaction all on the copy (see the class notes).
    const double* c = &x[3 * fc.n[corner]];
    for (int j = 0; j < 3; ++j)
      t.w[j] = j == corner ? 1.0 : 0.0;
    a = c;
    std::copy(vn, vn + 3, n);
  }
  const double dist = (q[0] - a[0]) * n[0] + (q[1] - a[1]) * n[1] + (q[2] - a[2]) * n[2];
  if (!(dist < 0) || -dist > reach) return false;
  t.depth = -dist;
  std::copy(n, n + 3, t.normal);
  return true;
}

double SurfaceContact::stiffness(const double* q, const Facet& fc, const double* x) const
{
  double t = opt_.thickness;
  if (fc.nn == 3)
    t = facet_size(x, fc);
  else if (opt_.axisymmetric)
    t = 2 * M_PI * std::max(q[0], 0.0);
  return opt_.penalty_scale * opt_.youngs * t;
}

// The penetration the penalty acts on: t.depth less the part of it that the relative approach
// over the step cannot have produced (see the class notes).
double SurfaceContact::effective_depth(int node, const Touch& t, double dt)
{
  if (static_cast<size_t>(node) >= last_eval_.size()) {
    last_eval_.resize(node + 1, -1);
    last_depth_.resize(node + 1, 0.0);
    offset_.resize(node + 1, 0.0);
  }
  const bool continued = last_eval_[node] == eval_ - 1;
  const double before = continued ? last_depth_[node] : 0.0;
  double offset = continued ? offset_[node] : 0.0;
  double approach = 0; // rate of growth of the penetration: -(v_node - v_facet) . n
  for (int d = 0; d < 3; ++d)
    approach -= t.vr[d] * t.normal[d];
  // Twice the approach covers a facet that turns or deforms within the step.
  const double explained = 2 * std::max(approach, 0.0) * dt;
  offset += std::max(t.depth - before - explained, 0.0);
  offset = std::min(offset, t.depth);
  last_eval_[node] = eval_;
  last_depth_[node] = t.depth;
  offset_[node] = offset;
  return t.depth - offset;
}

void SurfaceContact::apply(int node, const Touch& t, const Facet& fc, const ContactBodyState& a,
                           const ContactBodyState& b, double dt) const
{
  const double fn = stiffness(&a.x[3 * node], fc, b.x) * t.depth;
  double force[3];
  for (int d = 0; d < 3; ++d)
    force[d] = fn * t.normal[d];
  if (opt_.friction > 0) {
    const double* vr = t.vr;
    const double vn = vr[0] * t.normal[0] + vr[1] * t.normal[1] + vr[2] * t.normal[2];
    double vt[3];
    for (int d = 0; d < 3; ++d)
      vt[d] = vr[d] - vn * t.normal[d];
    const double speed = std::sqrt(vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]);
    if (speed > 0) {
      const double ft = std::min(opt_.friction * fn, a.m[node] * speed / dt);
      for (int d = 0; d < 3; ++d)
        force[d] -= ft * vt[d] / speed;
    }
  }
  for (int d = 0; d < 3; ++d) {
    if (a.f) a.f[3 * node + d] += force[d];
    if (b.f)
      for (int j = 0; j < fc.nn; ++j)
        b.f[3 * fc.n[j] + d] -= t.w[j] * force[d];
  }
}

void SurfaceContact::rebuild_search(const ContactSurface& facets_of, const double* xb, int ns,
                                    double buffer)
{
  std::vector<Aabb> boxes(facets_of.facets.size());
  for (size_t k = 0; k < boxes.size(); ++k)
    boxes[k] = node_box(facets_of.facets[k].n.data(), facets_of.facets[k].nn, xb);
  sphere_.assign(4 * ns, 0.0);
  for (int s = 0; s < ns; ++s)
    for (int d = 0; d < 3; ++d)
      sphere_[4 * s + d] = sx_[3 * s + d];
  search_ = BufferedSearch(buffer);
  search_.build(boxes, sphere_.data(), ns);
  search_.remember_positions(sxb_.data(), static_cast<int>(sxb_.size() / 3), sx_.data(), ns);
  stale_ = false;
}

int SurfaceContact::evaluate(const ContactSurface& nodes_of, const ContactBodyState& a,
                             const ContactSurface& facets_of, const ContactBodyState& b, bool self,
                             double dt)
{
  if (facets_of.facets.empty() || nodes_of.nodes.empty()) return 0;
  const int ns = static_cast<int>(nodes_of.nodes.size());
  sx_.resize(3 * ns);
  for (int s = 0; s < ns; ++s)
    for (int d = 0; d < 3; ++d)
      sx_[3 * s + d] = a.x[3 * nodes_of.nodes[s] + d];
  const int nb = static_cast<int>(facets_of.nodes.size());
  sxb_.resize(3 * nb);
  for (int s = 0; s < nb; ++s)
    for (int d = 0; d < 3; ++d)
      sxb_[3 * s + d] = b.x[3 * facets_of.nodes[s] + d];
  // The search reach covers the deepest accepted contact; it is rebuilt once nodes and facet
  // nodes together moved by more than that.
  const double buffer = facets_of.max_reach;
  if (stale_ || search_.needs_rebuild(sxb_.data(), nb, sx_.data(), ns))
    rebuild_search(facets_of, b.x, ns, buffer);
  const auto& cand = search_.candidates();
  return static_cast<int>(
      resolve(nodes_of, a, facets_of, b, self, dt, cand.data(), cand.size()).contacts);
}

SurfaceContact::Counts
SurfaceContact::resolve(const ContactSurface& nodes_of, const ContactBodyState& a,
                        const ContactSurface& facets_of, const ContactBodyState& b, bool self,
                        double dt, const std::pair<int, int>* cand, std::size_t ncand,
                        const int* owner, int part, double* tests, double* contacts)
{
  Counts counts;
  size_t c = 0;
  while (c < ncand) {
    const int s = cand[c].first, node = nodes_of.nodes[s];
    // Another part's node, or a free node whose mass left with its elements (erosion_mass
    // remove): nothing to push.
    if ((owner && owner[s] != part) || !(a.m[node] > 0)) {
      while (c < ncand && cand[c].first == s)
        ++c;
      continue;
    }
    Touch best;
    const size_t first = c;
    for (; c < ncand && cand[c].first == s; ++c) {
      const int k = cand[c].second;
      if (self && facets_of.neighbourhood(node, k)) continue;
      // 3D only: in 2D (node to edge) the rule before made no energy (test_fracture_cut's
      // notched tri3 bars: contact work <= 0), and the crack paths it gives are recorded.
      const bool twin = self && facets_of.facets[k].nn == 3;
      const int corner = twin ? facets_of.twin_corner(node, k) : -1;
      double vn[3];
      if (corner >= 0 && !twin_normal(facets_of, node, facets_of.facets[k].n[corner], b.x, vn))
        continue;
      Touch t;
      if (touch(&a.x[3 * node], facets_of.facets[k], facets_of.reach[k], b.x, t, corner, vn) &&
          t.depth > best.depth) {
        best = t;
        best.facet = k;
      }
    }
    counts.tests += static_cast<long>(c - first);
    if (tests) tests[s] += static_cast<double>(c - first);
    if (best.facet >= 0) {
      const Facet& fc = facets_of.facets[best.facet];
      for (int d = 0; d < 3; ++d) {
        best.vr[d] = a.v[3 * node + d];
        for (int j = 0; j < fc.nn; ++j)
          best.vr[d] -= best.w[j] * b.v[3 * fc.n[j] + d];
      }
      best.depth = effective_depth(node, best, dt);
      apply(node, best, fc, a, b, dt);
      ++counts.contacts;
      if (contacts) contacts[s] += 1.0;
    }
  }
  ++eval_;
  return counts;
}

void SurfaceContact::import_state(const std::vector<int>& nodes, const double* in)
{
  // The imported contacts belong to the last evaluation, as export_state read them.
  for (size_t s = 0; s < nodes.size(); ++s) {
    const size_t node = static_cast<size_t>(nodes[s]);
    if (node >= last_eval_.size()) {
      if (!(in[3 * s] > 0.5)) continue;
      last_eval_.resize(node + 1, -1);
      last_depth_.resize(node + 1, 0.0);
      offset_.resize(node + 1, 0.0);
    }
    const bool on = in[3 * s] > 0.5 && eval_ > 0;
    last_eval_[node] = on ? eval_ - 1 : -1;
    last_depth_[node] = on ? in[3 * s + 1] : 0.0;
    offset_[node] = on ? in[3 * s + 2] : 0.0;
  }
}

void SurfaceContact::pack_state(std::vector<double>& out) const
{
  if (eval_ == 0) return;
  for (size_t node = 0; node < last_eval_.size(); ++node)
    if (last_eval_[node] == eval_ - 1) {
      out.push_back(static_cast<double>(node));
      out.push_back(last_depth_[node]);
      out.push_back(offset_[node]);
    }
}

void SurfaceContact::unpack_state(const double* in, size_t n)
{
  if (n % 3 != 0) throw std::runtime_error("surface contact state: corrupt record");
  last_eval_.clear();
  last_depth_.clear();
  offset_.clear();
  // The stored contacts belong to evaluation 0, so evaluation 1 (the next) continues them.
  eval_ = 1;
  for (size_t k = 0; k < n; k += 3) {
    const double x = in[k];
    if (!(x >= 0 && x < 2147483647.0) || x != std::floor(x))
      throw std::runtime_error("surface contact state: corrupt record");
    const size_t node = static_cast<size_t>(x);
    if (node >= last_eval_.size()) {
      last_eval_.resize(node + 1, -1);
      last_depth_.resize(node + 1, 0.0);
      offset_.resize(node + 1, 0.0);
    }
    last_eval_[node] = 0;
    last_depth_[node] = in[k + 1];
    offset_[node] = in[k + 2];
  }
}

} // namespace fracdem
