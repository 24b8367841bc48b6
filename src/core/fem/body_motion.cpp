// Rigid placement transforms and prescribed rigid-body motion.
#include "fem/body_motion.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fracdem
{

void rotate_about_axis(const double axis_in[3], double angle, const double p[3], double out[3])
{
  double n = std::sqrt(axis_in[0] * axis_in[0] + axis_in[1] * axis_in[1] + axis_in[2] * axis_in[2]);
  double k[3] = {axis_in[0] / n, axis_in[1] / n, axis_in[2] / n};
  double c = std::cos(angle), s = std::sin(angle);
  double kdotp = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
  double kxp[3] = {k[1] * p[2] - k[2] * p[1], k[2] * p[0] - k[0] * p[2], k[0] * p[1] - k[1] * p[0]};
  for (int d = 0; d < 3; ++d)
    out[d] = p[d] * c + kxp[d] * s + k[d] * kdotp * (1 - c);
}

bool valid_axis(const double axis[3])
{
  const double n2 = axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2];
  return std::isfinite(n2) && n2 > 0;
}

bool apply_transforms(Mesh& mesh, const std::vector<MeshTransform>& transforms)
{
  const int nn = mesh.num_nodes();
  for (const MeshTransform& t : transforms) {
    if (t.kind == MeshTransform::Rotate && !valid_axis(t.a))
      throw std::invalid_argument("rotate: the axis has zero length (or is not finite)");
    for (int i = 0; i < nn; ++i) {
      double* p = &mesh.X[3 * i];
      if (t.kind == MeshTransform::Scale) {
        for (int d = 0; d < 3; ++d)
          p[d] *= t.a[0];
      } else if (t.kind == MeshTransform::Move) {
        for (int d = 0; d < 3; ++d)
          p[d] += t.a[d];
      } else {
        double q[3];
        rotate_about_axis(t.a, t.a[3], p, q);
        for (int d = 0; d < 3; ++d)
          p[d] = q[d];
      }
    }
  }
  if (mesh.dim == 2)
    for (int i = 0; i < nn; ++i)
      if (std::fabs(mesh.X[3 * i + 2]) > 0) return false;
  return true;
}

void RigidMotion::evaluate(double t, const double* X, int nn, double* x, double* v) const
{
  if (kind == None) {
    std::copy(X, X + 3 * nn, x);
    std::fill(v, v + 3 * nn, 0.0);
  } else if (kind == Linear) {
    for (int n = 0; n < nn; ++n)
      for (int d = 0; d < 3; ++d) {
        x[3 * n + d] = X[3 * n + d] + velocity[d] * t;
        v[3 * n + d] = velocity[d];
      }
  } else {
    const double w = 2 * M_PI / period;
    const double* k = axis;
    for (int n = 0; n < nn; ++n) {
      double p[3], q[3];
      for (int d = 0; d < 3; ++d)
        p[d] = X[3 * n + d] - origin[d];
      rotate_about_axis(k, w * t, p, q);
      for (int d = 0; d < 3; ++d)
        x[3 * n + d] = origin[d] + q[d];
      v[3 * n + 0] = w * (k[1] * q[2] - k[2] * q[1]);
      v[3 * n + 1] = w * (k[2] * q[0] - k[0] * q[2]);
      v[3 * n + 2] = w * (k[0] * q[1] - k[1] * q[0]);
    }
  }
}

} // namespace fracdem
