// Hertz contact on a resolved deformable surface: local indentation and pressure spreading.
#pragma once

#include <vector>

#include "contact/contact_resolution.h"

namespace fracdem
{

// Surface displacement of an elastic half-space under Hertz pressure, relative to its value at
// the centre, at radial distance s = r / a: 1 - s^2/2 inside the contact (s <= 1), and
// ((2 - s^2) asin(1/s) + sqrt(s^2 - 1)) / pi outside.
double hertz_surface_profile(double s);

// Surface nodes near a contact point: breadth-first over the surface's node adjacency from
// `seeds`, keeping nodes whose distance from c in the plane normal to n is <= rmax.
struct SurfacePatch {
  std::vector<int> nodes;
  std::vector<double> radius; // in-plane distance from c
  // Scratch kept between calls: per node, the epoch of the last search that visited it.
  std::vector<unsigned> visited;
  unsigned epoch = 0;
};
void gather_surface_patch(const SurfaceTopology& topo, const double* x, const int* seeds,
                          int nseeds, const double c[3], const double n[3], double rmax,
                          SurfacePatch& patch);

// A sphere of radius R pressed into a resolved elastic surface. The body's compliance is the
// finite-element body's own, so the contact law carries the sphere's; but the contact radius
// a = sqrt(R (delta_p + delta_b)) grows with the body's local indentation delta_b, which a point
// law misses. delta_b is the surface displacement into the body at the contact point u_c, less
// the displacement of the surrounding ring scaled by Hertz's half-space profile (which removes
// rigid motion and global deflection): u_ring = u_rigid + delta_b * profile(s).
//   u_c: displacement into the body at the contact point; disp: per-node displacement into the
//   body (indexed by node id); patch: nodes around the contact.
// Returns delta_b >= 0, or 0 where no surface node lies in the ring [1.5 a, 3.5 a] (the mesh does
// not resolve the contact: the point law applies). Iterates a <-> delta_b a few times.
double local_indentation(double R, double delta_p, double u_c, const std::vector<double>& disp,
                         const SurfacePatch& patch);

// Nodal weights of a Hertz pressure p ~ sqrt(1 - r^2/a^2) over the contact disc, each node's
// share times its surface area (node_area, by node id); weights sum to one. Returns false (and
// no weights) where fewer than `min_nodes` nodes lie inside the disc.
bool hertz_pressure_weights(const SurfacePatch& patch, const std::vector<double>& node_area,
                            double a, std::vector<double>& weights, int min_nodes = 4);

} // namespace fracdem
