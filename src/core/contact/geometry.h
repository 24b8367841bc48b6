// Closest points on triangles and segments with the feature (face/edge/vertex) they lie on.
#pragma once

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

} // namespace fracdem
