// Closest points on triangles and segments with the feature (face/edge/vertex) they lie on.
#pragma once

#include <cmath>
#include <cstdint>

namespace fracdem
{

enum class Feature : std::uint8_t { Face, Edge, Vertex };

struct ClosestPoint {
  double p[3];  // closest point
  double w[3];  // barycentric weights of p on the facet nodes (2 used for segments)
  Feature kind; // where p lies
  int local;    // edge k = nodes (k, k+1 mod 3), or vertex index; -1 for Face
  double dist2; // squared distance from the query point
};

// Ericson's Voronoi-region method (Real-Time Collision Detection, 5.1.5); degenerate
// triangles fall through to their closest edge.
ClosestPoint closest_point_triangle(const double q[3], const double a[3], const double b[3],
                                    const double c[3]);
// Interior points report Face (the segment is a 2D body's boundary facet); ends report Vertex 0/1.
ClosestPoint closest_point_segment(const double q[3], const double a[3], const double b[3]);

// Normal of facet `nodes` (nn = 3: triangle, right-hand rule; nn = 2: in-plane edge normal) at
// node positions x, not normalised (its length is twice the area or the edge length).
void facet_normal(const double* x, const int* nodes, int nn, double nrm[3]);

// A facet's plane and bounding ball, for culling spheres that cannot reach it before the closest
// point is computed. Every point p of the facet has |n.(p - c)| <= off_plane and |p - c| <= radius
// (off_plane covers the plane's rounding on slivers); slack covers the rounding of the bound.
struct FacetBound {
  double c[3];      // centre of the vertices' bounding box
  double n[3];      // unit normal (a segment: its in-plane normal; degenerate: zero)
  double radius;    // largest vertex distance from c
  double off_plane; // largest vertex distance from the plane
  double slack;     // rounding allowance of facet_distance_bound, absolute
};
FacetBound facet_bound(const double a[3], const double b[3], const double* c_or_null);

// A lower bound on the distance from q to every point of the facet, rounding included (so the
// exact closest point is never nearer): from |q - p|^2 = (normal part)^2 + (in-plane part)^2,
// dist^2 >= (|n.(q-c)| - off_plane)_+^2 + (|in-plane part of q-c| - radius)_+^2.
inline double facet_distance_bound(const FacetBound& f, const double q[3])
{
  const double dq[3] = {q[0] - f.c[0], q[1] - f.c[1], q[2] - f.c[2]};
  const double h = f.n[0] * dq[0] + f.n[1] * dq[1] + f.n[2] * dq[2];
  const double across = std::fmax((h < 0 ? -h : h) - f.off_plane, 0.0);
  const double w[3] = {dq[0] - h * f.n[0], dq[1] - h * f.n[1], dq[2] - h * f.n[2]};
  const double t2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
  const double along = t2 > f.radius * f.radius ? std::sqrt(t2) - f.radius : 0.0;
  return std::sqrt(across * across + along * along) - f.slack;
}

} // namespace fracdem
