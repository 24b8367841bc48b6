// Rigid placement of a mesh (scale, move, rotate) and the prescribed motion of a rigid body.
#pragma once

#include <vector>

#include "fem/mesh.h"

namespace fracdem
{

// Rodrigues' rotation of p by `angle` (radians) about the axis direction `axis` (any length > 0).
void rotate_about_axis(const double axis[3], double angle, const double p[3], double out[3]);
// True when `axis` defines a direction: finite components, non-zero length. A zero axis would
// turn every rotated coordinate into NaN (0 / 0 in the normalisation).
bool valid_axis(const double axis[3]);

// One placement step applied to the reference coordinates when a body is created.
struct MeshTransform {
  enum Kind { Scale, Move, Rotate } kind;
  double a[4]; // Scale: factor; Move: dx dy dz; Rotate: axis ax ay az, angle (radians)
};
// Applies the transforms in order to mesh.X. Returns false when a 2D mesh leaves the z = 0 plane.
// Throws std::invalid_argument for a Rotate whose axis is not valid_axis().
bool apply_transforms(Mesh& mesh, const std::vector<MeshTransform>& transforms);

// Prescribed motion of a rigid body: at rest, constant velocity, or steady rotation about an axis.
struct RigidMotion {
  enum Kind { None, Linear, Rotate } kind = None;
  double velocity[3] = {0, 0, 0};
  double origin[3] = {0, 0, 0}, axis[3] = {0, 0, 1}; // axis of unit length
  double period = 0;
  // Positions x and velocities v (3 per node) at time t of nodes whose reference positions are X.
  void evaluate(double t, const double* X, int nnodes, double* x, double* v) const;
};

} // namespace fracdem
