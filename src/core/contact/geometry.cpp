// Closest-point queries used by particle-facet contact detection.
#include "contact/geometry.h"

#include <algorithm>
#include <cmath>

namespace fracdem
{

namespace
{
inline double dot(const double* a, const double* b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

ClosestPoint make(const double q[3], const double* a, const double* b, const double* c, double u,
                  double v, double w, Feature kind, int local)
{
  ClosestPoint r;
  r.w[0] = u;
  r.w[1] = v;
  r.w[2] = w;
  for (int d = 0; d < 3; ++d)
    r.p[d] = u * a[d] + v * b[d] + (c ? w * c[d] : 0.0);
  r.kind = kind;
  r.local = local;
  r.dist2 = 0;
  for (int d = 0; d < 3; ++d)
    r.dist2 += (q[d] - r.p[d]) * (q[d] - r.p[d]);
  return r;
}
} // namespace

ClosestPoint closest_point_segment(const double q[3], const double a[3], const double b[3])
{
  double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  double aq[3] = {q[0] - a[0], q[1] - a[1], q[2] - a[2]};
  const double l2 = dot(ab, ab);
  double t = l2 > 0 ? dot(aq, ab) / l2 : 0.0;
  if (t <= 0) return make(q, a, b, nullptr, 1, 0, 0, Feature::Vertex, 0);
  if (t >= 1) return make(q, a, b, nullptr, 0, 1, 0, Feature::Vertex, 1);
  return make(q, a, b, nullptr, 1 - t, t, 0, Feature::Face, -1);
}

ClosestPoint closest_point_triangle(const double q[3], const double a[3], const double b[3],
                                    const double c[3])
{
  double ab[3], ac[3], ap[3];
  for (int d = 0; d < 3; ++d) {
    ab[d] = b[d] - a[d];
    ac[d] = c[d] - a[d];
    ap[d] = q[d] - a[d];
  }
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return make(q, a, b, c, 1, 0, 0, Feature::Vertex, 0);
  double bp[3] = {q[0] - b[0], q[1] - b[1], q[2] - b[2]};
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return make(q, a, b, c, 0, 1, 0, Feature::Vertex, 1);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0 && (d1 - d3) > 0) {
    const double v = d1 / (d1 - d3);
    return make(q, a, b, c, 1 - v, v, 0, Feature::Edge, 0);
  }
  double cp[3] = {q[0] - c[0], q[1] - c[1], q[2] - c[2]};
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return make(q, a, b, c, 0, 0, 1, Feature::Vertex, 2);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0 && (d2 - d6) > 0) {
    const double w = d2 / (d2 - d6);
    return make(q, a, b, c, 1 - w, 0, w, Feature::Edge, 2); // edge 2 = nodes (2, 0)
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0 && ((d4 - d3) + (d5 - d6)) > 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return make(q, a, b, c, 0, 1 - w, w, Feature::Edge, 1);
  }
  const double sum = va + vb + vc;
  if (!(sum > 0)) {
    // Degenerate (zero-area) triangle: closest of its three edges.
    ClosestPoint best;
    best.dist2 = -1;
    const double* P[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      ClosestPoint s = closest_point_segment(q, P[k], P[(k + 1) % 3]);
      if (best.dist2 < 0 || s.dist2 < best.dist2) {
        double w3[3] = {0, 0, 0};
        w3[k] = s.w[0];
        w3[(k + 1) % 3] = s.w[1];
        best = make(q, a, b, c, w3[0], w3[1], w3[2], Feature::Edge, k);
      }
    }
    return best;
  }
  const double v = vb / sum, w = vc / sum;
  return make(q, a, b, c, 1 - v - w, v, w, Feature::Face, -1);
}

// The normal is normalised from the cross product, and off_plane measures how far the vertices
// lie from the resulting plane, so a sliver's inaccurate normal only loosens the bound.
FacetBound facet_bound(const double a[3], const double b[3], const double* c)
{
  const double* P[3] = {a, b, c};
  const int nv = c ? 3 : 2;
  FacetBound f;
  double scale = 0;
  for (int d = 0; d < 3; ++d) {
    double lo = a[d], hi = a[d];
    for (int j = 1; j < nv; ++j) {
      lo = std::min(lo, P[j][d]);
      hi = std::max(hi, P[j][d]);
    }
    f.c[d] = 0.5 * (lo + hi);
    scale = std::max({scale, std::fabs(lo), std::fabs(hi)});
  }
  const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  double nrm[3] = {e1[1], -e1[0], 0.0}; // segment in the z = 0 plane: in-plane normal
  if (c) {
    const double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    nrm[0] = e1[1] * e2[2] - e1[2] * e2[1];
    nrm[1] = e1[2] * e2[0] - e1[0] * e2[2];
    nrm[2] = e1[0] * e2[1] - e1[1] * e2[0];
  }
  const double l = std::sqrt(dot(nrm, nrm));
  for (int d = 0; d < 3; ++d)
    f.n[d] = l > 0 ? nrm[d] / l : 0.0;
  f.radius = f.off_plane = 0;
  for (int j = 0; j < nv; ++j) {
    const double v[3] = {P[j][0] - f.c[0], P[j][1] - f.c[1], P[j][2] - f.c[2]};
    f.radius = std::max(f.radius, std::sqrt(dot(v, v)));
    f.off_plane = std::max(f.off_plane, std::fabs(dot(f.n, v)));
  }
  // Rounding of the coordinates (|x| <= scale) in this bound and in the closest point is a few
  // ulps of scale: 1e-10 relative leaves a margin of about a million.
  f.slack = 1e-10 * (scale + f.radius);
  f.radius *= 1 + 1e-12;
  return f;
}

void facet_normal(const double* x, const int* nodes, int nn, double nrm[3])
{
  const double* a = &x[3 * nodes[0]];
  const double* b = &x[3 * nodes[1]];
  if (nn == 3) {
    const double* c = &x[3 * nodes[2]];
    const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    nrm[0] = e1[1] * e2[2] - e1[2] * e2[1];
    nrm[1] = e1[2] * e2[0] - e1[0] * e2[2];
    nrm[2] = e1[0] * e2[1] - e1[1] * e2[0];
  } else {
    nrm[0] = b[1] - a[1];
    nrm[1] = a[0] - b[0];
    nrm[2] = 0;
  }
}

} // namespace fracdem
