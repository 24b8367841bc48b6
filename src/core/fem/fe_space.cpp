// Linear tet4 / tri3 / quad4 kernels: small-strain and corotational internal forces, stress, masses, dt.
#include "fem/fe_space.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace fracdem {

namespace {

// Block layouts in geo_ (per element):
//   Tet4 : dNdX[4][3], V                                          -> 13 doubles
//   Tri3 : one point  : dNdX[3][2], w, hoop[3], r_ref              -> 11 doubles
//   Quad4: four points: (dNdX[4][2], w, hoop[4], r_ref) x 4        -> 56 doubles
// w is the integration weight (V, A*t, or 2*pi*r*A); hoop[a] = N_a / r_ref at the point
// (zero in plane strain), so that hoop strain = sum_a hoop[a] * u_a,x.
constexpr int kTetBlock = 13;
constexpr int kTriBlock = 11;
constexpr int kQuadPoint = 14;
constexpr int kQuadBlock = 4 * kQuadPoint;
const double kGauss = 1.0 / std::sqrt(3.0);
const double kQuadXi[4][2] = {{-kGauss, -kGauss}, {kGauss, -kGauss}, {kGauss, kGauss}, {-kGauss, kGauss}};

inline double det3(const double m[9])
{
  return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
         m[2] * (m[3] * m[7] - m[4] * m[6]);
}

// Polar decomposition F = R U by Higham's scaled Newton iteration R <- (g R + R^-T / g) / 2.
// Converges quadratically; for the mildly distorted elements of explicit dynamics 3-5 steps.
void polar_rotation(const double F[9], double R[9])
{
  for (int k = 0; k < 9; ++k) R[k] = F[k];
  for (int it = 0; it < 30; ++it) {
    const double d = det3(R);
    double cof[9]; // cofactor matrix = det * R^-T
    cof[0] = R[4] * R[8] - R[5] * R[7];
    cof[1] = R[5] * R[6] - R[3] * R[8];
    cof[2] = R[3] * R[7] - R[4] * R[6];
    cof[3] = R[2] * R[7] - R[1] * R[8];
    cof[4] = R[0] * R[8] - R[2] * R[6];
    cof[5] = R[1] * R[6] - R[0] * R[7];
    cof[6] = R[1] * R[5] - R[2] * R[4];
    cof[7] = R[2] * R[3] - R[0] * R[5];
    cof[8] = R[0] * R[4] - R[1] * R[3];
    const double g = std::cbrt(1.0 / std::fabs(d)); // scaling speeds up far-from-orthogonal F
    double diff = 0;
    for (int k = 0; k < 9; ++k) {
      const double rn = 0.5 * (g * R[k] + cof[k] / (g * d));
      diff = std::max(diff, std::fabs(rn - R[k]));
      R[k] = rn;
    }
    if (diff < 1e-14) break;
  }
}

// Tet4 force from current node coordinates xl (12) and reference Xl (12). Returns energy.
inline double tet_force(const double* g, const double* xl, const double* Xl, bool corot, double lam,
                        double mu, double* fl, double& detF)
{
  const double* dN = g;
  const double V = g[12];
  double F[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0}; // F[i*3+j] = dx_i/dX_j
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 3; ++i) {
      const double xi = xl[3 * a + i];
      F[3 * i + 0] += xi * dN[3 * a + 0];
      F[3 * i + 1] += xi * dN[3 * a + 1];
      F[3 * i + 2] += xi * dN[3 * a + 2];
    }
  detF = det3(F);
  double H[9]; // displacement gradient in the (co-rotated) element frame
  double R[9];
  if (corot) {
    polar_rotation(F, R);
    // H = R^T F - I
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        H[3 * i + j] = R[0 * 3 + i] * F[0 * 3 + j] + R[1 * 3 + i] * F[1 * 3 + j] +
                       R[2 * 3 + i] * F[2 * 3 + j] - (i == j ? 1.0 : 0.0);
  } else {
    for (int k = 0; k < 9; ++k) H[k] = F[k];
    // F - I computed from displacements to avoid cancellation: H = sum (x - X) dN
    for (int k = 0; k < 9; ++k) H[k] = 0;
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) {
        const double ui = xl[3 * a + i] - Xl[3 * a + i];
        H[3 * i + 0] += ui * dN[3 * a + 0];
        H[3 * i + 1] += ui * dN[3 * a + 1];
        H[3 * i + 2] += ui * dN[3 * a + 2];
      }
  }
  const double exx = H[0], eyy = H[4], ezz = H[8];
  const double gxy = H[1] + H[3], gyz = H[5] + H[7], gzx = H[2] + H[6];
  const double tr = exx + eyy + ezz;
  const double sxx = lam * tr + 2 * mu * exx, syy = lam * tr + 2 * mu * eyy,
               szz = lam * tr + 2 * mu * ezz;
  const double sxy = mu * gxy, syz = mu * gyz, szx = mu * gzx;
  double P[9] = {sxx, sxy, szx, sxy, syy, syz, szx, syz, szz};
  if (corot) {
    double RP[9];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        RP[3 * i + j] = R[3 * i + 0] * P[0 + j] + R[3 * i + 1] * P[3 + j] + R[3 * i + 2] * P[6 + j];
    for (int k = 0; k < 9; ++k) P[k] = RP[k];
  }
  for (int a = 0; a < 4; ++a) {
    const double* d = &dN[3 * a];
    fl[3 * a + 0] = -V * (P[0] * d[0] + P[1] * d[1] + P[2] * d[2]);
    fl[3 * a + 1] = -V * (P[3] * d[0] + P[4] * d[1] + P[5] * d[2]);
    fl[3 * a + 2] = -V * (P[6] * d[0] + P[7] * d[1] + P[8] * d[2]);
  }
  return 0.5 * V * (sxx * exx + syy * eyy + szz * ezz + sxy * gxy + syz * gyz + szx * gzx);
}

// One 2D integration point with n nodes (tri3: 3, quad4: 4). Adds into fl (2 per node).
inline double point2d_force(const double* g, int n, const double* xl, const double* Xl, bool corot,
                            double lam, double mu, double* fl, double& detF, double* sig_out)
{
  const double* dN = g;
  const double w = g[2 * n];
  const double* hoop = g + 2 * n + 1;
  double F[4] = {0, 0, 0, 0}, Hu[4] = {0, 0, 0, 0};
  double eth = 0;
  for (int a = 0; a < n; ++a) {
    const double x = xl[2 * a], y = xl[2 * a + 1];
    const double ux = x - Xl[2 * a], uy = y - Xl[2 * a + 1];
    F[0] += x * dN[2 * a];
    F[1] += x * dN[2 * a + 1];
    F[2] += y * dN[2 * a];
    F[3] += y * dN[2 * a + 1];
    Hu[0] += ux * dN[2 * a];
    Hu[1] += ux * dN[2 * a + 1];
    Hu[2] += uy * dN[2 * a];
    Hu[3] += uy * dN[2 * a + 1];
    eth += hoop[a] * ux;
  }
  detF = F[0] * F[3] - F[1] * F[2];
  double c = 1, s = 0;
  double H[4];
  if (corot) {
    const double th = std::atan2(F[2] - F[1], F[0] + F[3]);
    c = std::cos(th);
    s = std::sin(th);
    // H = R^T F - I with R = [[c, -s], [s, c]]
    H[0] = c * F[0] + s * F[2] - 1;
    H[1] = c * F[1] + s * F[3];
    H[2] = -s * F[0] + c * F[2];
    H[3] = -s * F[1] + c * F[3] - 1;
  } else {
    for (int k = 0; k < 4; ++k) H[k] = Hu[k];
  }
  const double exx = H[0], eyy = H[3], gxy = H[1] + H[2];
  const double tr = exx + eyy + eth;
  const double sxx = lam * tr + 2 * mu * exx, syy = lam * tr + 2 * mu * eyy;
  const double sth = lam * tr + 2 * mu * eth, sxy = mu * gxy;
  double P[4] = {sxx, sxy, sxy, syy};
  if (corot) {
    const double p0 = c * P[0] - s * P[2], p1 = c * P[1] - s * P[3];
    const double p2 = s * P[0] + c * P[2], p3 = s * P[1] + c * P[3];
    P[0] = p0;
    P[1] = p1;
    P[2] = p2;
    P[3] = p3;
  }
  for (int a = 0; a < n; ++a) {
    const double dx = dN[2 * a], dy = dN[2 * a + 1];
    fl[2 * a] -= w * (P[0] * dx + P[1] * dy + sth * hoop[a]);
    fl[2 * a + 1] -= w * (P[2] * dx + P[3] * dy);
  }
  if (sig_out) {
    // Cauchy stress ~ rotated small-strain stress (small strains assumed).
    const double rxx = c * c * sxx - 2 * c * s * sxy + s * s * syy;
    const double ryy = s * s * sxx + 2 * c * s * sxy + c * c * syy;
    const double rxy = c * s * (sxx - syy) + (c * c - s * s) * sxy;
    sig_out[0] += rxx;
    sig_out[1] += ryy;
    sig_out[2] += sth;
    sig_out[3] += rxy;
  }
  return 0.5 * w * (sxx * exx + syy * eyy + sth * eth + sxy * gxy);
}

void quad_shape(double xi, double eta, double N[4], double dNdxi[4][2])
{
  const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
  for (int a = 0; a < 4; ++a) {
    N[a] = 0.25 * (1 + sx[a] * xi) * (1 + sy[a] * eta);
    dNdxi[a][0] = 0.25 * sx[a] * (1 + sy[a] * eta);
    dNdxi[a][1] = 0.25 * sy[a] * (1 + sx[a] * xi);
  }
}

std::string elem_msg(int e, const char* what, double value)
{
  std::ostringstream os;
  os << "element " << e << " " << what << " (" << value << ")";
  return os.str();
}

} // namespace

/* ---------------------------------------------------------------------- */

void FeSpace::build(const Mesh& mesh, const Material& mat)
{
  mat_ = mat;
  dim_ = mesh.dim;
  axisym_ = mesh.dim == 2 && mat.plane == PlaneMode::Axisymmetric;
  const int ne = mesh.num_elems();
  offset_.assign(ne + 1, 0);
  for (int e = 0; e < ne; ++e) {
    const ElemType t = mesh.etype[e];
    offset_[e + 1] = offset_[e] + (t == ElemType::Tet4 ? kTetBlock : t == ElemType::Tri3 ? kTriBlock : kQuadBlock);
  }
  geo_.assign(offset_[ne], 0.0);
  measure_.assign(ne, 0.0);
  const double* X = mesh.X.data();
  if (axisym_)
    for (int i = 0; i < mesh.num_nodes(); ++i)
      if (X[3 * i] < 0) {
        std::ostringstream os;
        os << "axisymmetric mesh has node " << i << " at r = x = " << X[3 * i] << " < 0";
        throw FeError(-1, os.str());
      }

  for (int e = 0; e < ne; ++e) {
    const auto& c = mesh.conn[e];
    double* g = &geo_[offset_[e]];
    const ElemType t = mesh.etype[e];
    if (elem_dim(t) != mesh.dim) throw FeError(e, elem_msg(e, "has the wrong dimension for the mesh", elem_dim(t)));
    if (t == ElemType::Tet4) {
      const double* p0 = X + 3 * c[0];
      double J[9]; // columns: edges from node 0
      for (int k = 0; k < 3; ++k) {
        const double* pk = X + 3 * c[k + 1];
        for (int i = 0; i < 3; ++i) J[3 * i + k] = pk[i] - p0[i];
      }
      const double det = det3(J);
      double h = 0;
      for (int k = 0; k < 9; ++k) h = std::max(h, std::fabs(J[k]));
      const double V = det / 6.0;
      if (det <= 0 && std::fabs(det) > 1e-14 * h * h * h)
        throw FeError(e, elem_msg(e, "is inverted: negative volume", V) + "; reorder its nodes");
      if (std::fabs(det) <= 1e-14 * h * h * h) throw FeError(e, elem_msg(e, "is degenerate: volume", V));
      // inverse of J: dN_k/dX for k = 1..3 are rows of J^-1; dN_0 = -sum.
      double inv[9];
      inv[0] = (J[4] * J[8] - J[5] * J[7]) / det;
      inv[1] = (J[2] * J[7] - J[1] * J[8]) / det;
      inv[2] = (J[1] * J[5] - J[2] * J[4]) / det;
      inv[3] = (J[5] * J[6] - J[3] * J[8]) / det;
      inv[4] = (J[0] * J[8] - J[2] * J[6]) / det;
      inv[5] = (J[2] * J[3] - J[0] * J[5]) / det;
      inv[6] = (J[3] * J[7] - J[4] * J[6]) / det;
      inv[7] = (J[1] * J[6] - J[0] * J[7]) / det;
      inv[8] = (J[0] * J[4] - J[1] * J[3]) / det;
      for (int j = 0; j < 3; ++j) {
        g[0 + j] = -(inv[0 + j] + inv[3 + j] + inv[6 + j]);
        for (int k = 0; k < 3; ++k) g[3 * (k + 1) + j] = inv[3 * k + j];
      }
      g[12] = V;
      measure_[e] = V;
    } else if (t == ElemType::Tri3) {
      const double x0 = X[3 * c[0]], y0 = X[3 * c[0] + 1];
      const double x1 = X[3 * c[1]], y1 = X[3 * c[1] + 1];
      const double x2 = X[3 * c[2]], y2 = X[3 * c[2] + 1];
      const double A2 = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
      const double h = std::max({std::fabs(x1 - x0), std::fabs(x2 - x0), std::fabs(y1 - y0), std::fabs(y2 - y0)});
      if (A2 <= 0 && std::fabs(A2) > 1e-14 * h * h)
        throw FeError(e, elem_msg(e, "is inverted: negative area", 0.5 * A2) + "; order nodes counter-clockwise");
      if (std::fabs(A2) <= 1e-14 * h * h) throw FeError(e, elem_msg(e, "is degenerate: area", 0.5 * A2));
      const double A = 0.5 * A2;
      g[0] = (y1 - y2) / A2; g[1] = (x2 - x1) / A2;
      g[2] = (y2 - y0) / A2; g[3] = (x0 - x2) / A2;
      g[4] = (y0 - y1) / A2; g[5] = (x1 - x0) / A2;
      const double r = (x0 + x1 + x2) / 3.0;
      if (axisym_) {
        g[6] = 2 * M_PI * r * A;
        for (int a = 0; a < 3; ++a) g[7 + a] = 1.0 / (3.0 * r);
      } else {
        g[6] = A * mat.thickness;
      }
      g[10] = r;
      measure_[e] = A;
    } else { // Quad4
      double area = 0;
      double h = 0;
      for (int a = 0; a < 4; ++a)
        for (int i = 0; i < 2; ++i) h = std::max(h, std::fabs(X[3 * c[a] + i] - X[3 * c[0] + i]));
      for (int q = 0; q < 4; ++q) {
        double N[4], dNdxi[4][2];
        quad_shape(kQuadXi[q][0], kQuadXi[q][1], N, dNdxi);
        double J[4] = {0, 0, 0, 0}, r = 0;
        for (int a = 0; a < 4; ++a) {
          const double xa = X[3 * c[a]], ya = X[3 * c[a] + 1];
          J[0] += xa * dNdxi[a][0]; J[1] += xa * dNdxi[a][1];
          J[2] += ya * dNdxi[a][0]; J[3] += ya * dNdxi[a][1];
          r += N[a] * xa;
        }
        const double det = J[0] * J[3] - J[1] * J[2];
        if (det <= 1e-14 * h * h)
          throw FeError(e, elem_msg(e, det < 0 ? "is inverted or non-convex: negative Jacobian"
                                               : "is degenerate: Jacobian", det));
        double* gp = g + q * kQuadPoint;
        for (int a = 0; a < 4; ++a) {
          gp[2 * a] = (J[3] * dNdxi[a][0] - J[2] * dNdxi[a][1]) / det;
          gp[2 * a + 1] = (-J[1] * dNdxi[a][0] + J[0] * dNdxi[a][1]) / det;
        }
        if (axisym_) {
          if (r <= 0) throw FeError(e, elem_msg(e, "has an integration point at r <= 0", r));
          gp[8] = 2 * M_PI * r * det;
          for (int a = 0; a < 4; ++a) gp[9 + a] = N[a] / r;
        } else {
          gp[8] = det * mat.thickness;
        }
        gp[13] = r;
        area += det;
      }
      measure_[e] = area;
    }
  }
}

/* ---------------------------------------------------------------------- */

void FeSpace::lumped_masses(const Mesh& mesh, std::vector<double>& m) const
{
  m.assign(mesh.num_nodes(), 0.0);
  const double rho = mat_.rho;
  const double* X = mesh.X.data();
  for (int e = 0; e < mesh.num_elems(); ++e) {
    if (!mesh.active[e]) continue;
    const auto& c = mesh.conn[e];
    const double* g = &geo_[offset_[e]];
    switch (mesh.etype[e]) {
      case ElemType::Tet4:
        for (int a = 0; a < 4; ++a) m[c[a]] += rho * g[12] / 4.0;
        break;
      case ElemType::Tri3:
        if (axisym_) {
          // exact row sums of the r-weighted consistent mass: 2 pi rho A (2 r_a + r_b + r_c) / 12
          const double A = measure_[e];
          const double rs = X[3 * c[0]] + X[3 * c[1]] + X[3 * c[2]];
          for (int a = 0; a < 3; ++a) m[c[a]] += 2 * M_PI * rho * A * (rs + X[3 * c[a]]) / 12.0;
        } else {
          for (int a = 0; a < 3; ++a) m[c[a]] += rho * g[6] / 3.0;
        }
        break;
      case ElemType::Quad4:
        for (int q = 0; q < 4; ++q) {
          double N[4], dNdxi[4][2];
          quad_shape(kQuadXi[q][0], kQuadXi[q][1], N, dNdxi);
          const double w = g[q * kQuadPoint + 8];
          for (int a = 0; a < 4; ++a) m[c[a]] += rho * w * N[a];
        }
        break;
    }
  }
}

/* ---------------------------------------------------------------------- */

double FeSpace::add_internal_forces(const Mesh& mesh, const double* x, int e_begin, int e_end,
                                    double* f, double* elem_energy, int* first_inverted) const
{
  const bool corot = mat_.kinematics == Kinematics::Corotational;
  const double lam = mat_.lambda(), mu = mat_.mu();
  const double* X = mesh.X.data();
  double energy = 0;
  for (int e = e_begin; e < e_end; ++e) {
    if (!mesh.active[e]) {
      if (elem_energy) elem_energy[e] = 0;
      continue;
    }
    const auto& c = mesh.conn[e];
    const double* g = &geo_[offset_[e]];
    double ee = 0, detF = 1;
    bool inverted = false;
    if (mesh.etype[e] == ElemType::Tet4) {
      double xl[12], Xl[12], fl[12];
      for (int a = 0; a < 4; ++a)
        for (int i = 0; i < 3; ++i) {
          xl[3 * a + i] = x[3 * c[a] + i];
          Xl[3 * a + i] = X[3 * c[a] + i];
        }
      ee = tet_force(g, xl, Xl, corot, lam, mu, fl, detF);
      inverted = detF <= 0;
      for (int a = 0; a < 4; ++a) {
        double* fa = f + 3 * c[a];
        fa[0] += fl[3 * a];
        fa[1] += fl[3 * a + 1];
        fa[2] += fl[3 * a + 2];
      }
    } else {
      const int n = mesh.etype[e] == ElemType::Tri3 ? 3 : 4;
      const int npts = n == 3 ? 1 : 4;
      const int stride = n == 3 ? kTriBlock : kQuadPoint;
      double xl[8], Xl[8], fl[8] = {0, 0, 0, 0, 0, 0, 0, 0};
      for (int a = 0; a < n; ++a)
        for (int i = 0; i < 2; ++i) {
          xl[2 * a + i] = x[3 * c[a] + i];
          Xl[2 * a + i] = X[3 * c[a] + i];
        }
      for (int q = 0; q < npts; ++q) {
        ee += point2d_force(g + q * stride, n, xl, Xl, corot, lam, mu, fl, detF, nullptr);
        inverted = inverted || detF <= 0;
      }
      for (int a = 0; a < n; ++a) {
        f[3 * c[a]] += fl[2 * a];
        f[3 * c[a] + 1] += fl[2 * a + 1];
      }
    }
    if (inverted && first_inverted && *first_inverted < 0) *first_inverted = e;
    if (elem_energy) elem_energy[e] = ee;
    energy += ee;
  }
  return energy;
}

/* ---------------------------------------------------------------------- */

void FeSpace::element_stress(const Mesh& mesh, const double* x, int e, double sigma[6]) const
{
  for (int k = 0; k < 6; ++k) sigma[k] = 0;
  const bool corot = mat_.kinematics == Kinematics::Corotational;
  const double lam = mat_.lambda(), mu = mat_.mu();
  const auto& c = mesh.conn[e];
  const double* g = &geo_[offset_[e]];
  const double* X = mesh.X.data();
  if (mesh.etype[e] == ElemType::Tet4) {
    const double* dN = g;
    double F[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0}, H[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          F[3 * i + j] += x[3 * c[a] + i] * dN[3 * a + j];
          H[3 * i + j] += (x[3 * c[a] + i] - X[3 * c[a] + i]) * dN[3 * a + j];
        }
    double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    if (corot) {
      polar_rotation(F, R);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          H[3 * i + j] = R[i] * F[j] + R[3 + i] * F[3 + j] + R[6 + i] * F[6 + j] - (i == j ? 1 : 0);
    }
    const double tr = H[0] + H[4] + H[8];
    double s[9] = {lam * tr + 2 * mu * H[0], mu * (H[1] + H[3]), mu * (H[2] + H[6]),
                   mu * (H[1] + H[3]), lam * tr + 2 * mu * H[4], mu * (H[5] + H[7]),
                   mu * (H[2] + H[6]), mu * (H[5] + H[7]), lam * tr + 2 * mu * H[8]};
    // Cauchy ~ R s R^T (small strains)
    double t[9], r[9];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) t[3 * i + j] = R[3 * i] * s[j] + R[3 * i + 1] * s[3 + j] + R[3 * i + 2] * s[6 + j];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r[3 * i + j] = t[3 * i] * R[3 * j] + t[3 * i + 1] * R[3 * j + 1] + t[3 * i + 2] * R[3 * j + 2];
    sigma[0] = r[0]; sigma[1] = r[4]; sigma[2] = r[8];
    sigma[3] = r[1]; sigma[4] = r[5]; sigma[5] = r[2];
    return;
  }
  const int n = mesh.etype[e] == ElemType::Tri3 ? 3 : 4;
  const int npts = n == 3 ? 1 : 4;
  const int stride = n == 3 ? kTriBlock : kQuadPoint;
  double xl[8], Xl[8], fl[8] = {0, 0, 0, 0, 0, 0, 0, 0}, acc[4] = {0, 0, 0, 0}, detF;
  for (int a = 0; a < n; ++a)
    for (int i = 0; i < 2; ++i) {
      xl[2 * a + i] = x[3 * c[a] + i];
      Xl[2 * a + i] = X[3 * c[a] + i];
    }
  for (int q = 0; q < npts; ++q) point2d_force(g + q * stride, n, xl, Xl, corot, lam, mu, fl, detF, acc);
  sigma[0] = acc[0] / npts;
  sigma[1] = acc[1] / npts;
  sigma[3] = acc[3] / npts;
  // plane strain: sigma_zz = lambda * tr(eps) is what the hoop slot holds with eps_th = 0
  sigma[2] = acc[2] / npts;
}

double FeSpace::von_mises(const double s[6])
{
  const double a = s[0] - s[1], b = s[1] - s[2], c = s[2] - s[0];
  return std::sqrt(0.5 * (a * a + b * b + c * c) + 3 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
}

/* ---------------------------------------------------------------------- */

double FeSpace::stable_time_step(const Mesh& mesh, const double* /*x*/) const
{
  // Element stiffness from unit displacements of the small-strain kernel (exact: it is linear),
  // lumped element masses, Gershgorin: omega^2 <= max_i sum_j |K_ij| / m_i. The element bound
  // holds for the assembled mesh (Rayleigh quotient of sums), and K is rotation invariant, so the
  // reference configuration serves the corotational formulation too.
  const double lam = mat_.lambda(), mu = mat_.mu();
  const double* X = mesh.X.data();
  double w2max = 0;
  for (int e = 0; e < mesh.num_elems(); ++e) {
    if (!mesh.active[e]) continue;
    const auto& c = mesh.conn[e];
    const double* g = &geo_[offset_[e]];
    const ElemType t = mesh.etype[e];
    const int n = nodes_per_elem(t);
    const int nd = t == ElemType::Tet4 ? 3 : 2;
    const int ndof = n * nd;
    double K[144];
    double Xl[12], xl[12], fl[12], detF;
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < nd; ++i) Xl[nd * a + i] = X[3 * c[a] + i];
    for (int j = 0; j < ndof; ++j) {
      for (int k = 0; k < ndof; ++k) xl[k] = Xl[k] + (k == j ? 1.0 : 0.0);
      if (t == ElemType::Tet4) {
        tet_force(g, xl, Xl, false, lam, mu, fl, detF);
      } else {
        for (int k = 0; k < ndof; ++k) fl[k] = 0;
        const int npts = n == 3 ? 1 : 4;
        const int stride = n == 3 ? kTriBlock : kQuadPoint;
        for (int q = 0; q < npts; ++q) point2d_force(g + q * stride, n, xl, Xl, false, lam, mu, fl, detF, nullptr);
      }
      for (int k = 0; k < ndof; ++k) K[k * ndof + j] = -fl[k];
    }
    // element lumped masses
    double me[4] = {0, 0, 0, 0};
    if (t == ElemType::Tet4) {
      for (int a = 0; a < 4; ++a) me[a] = mat_.rho * g[12] / 4.0;
    } else if (t == ElemType::Tri3) {
      if (axisym_) {
        const double rs = X[3 * c[0]] + X[3 * c[1]] + X[3 * c[2]];
        for (int a = 0; a < 3; ++a) me[a] = 2 * M_PI * mat_.rho * measure_[e] * (rs + X[3 * c[a]]) / 12.0;
      } else {
        for (int a = 0; a < 3; ++a) me[a] = mat_.rho * g[6] / 3.0;
      }
    } else {
      for (int q = 0; q < 4; ++q) {
        double N[4], dNdxi[4][2];
        quad_shape(kQuadXi[q][0], kQuadXi[q][1], N, dNdxi);
        for (int a = 0; a < 4; ++a) me[a] += mat_.rho * g[q * kQuadPoint + 8] * N[a];
      }
    }
    for (int k = 0; k < ndof; ++k) {
      double row = 0;
      for (int j = 0; j < ndof; ++j) row += std::fabs(K[k * ndof + j]);
      w2max = std::max(w2max, row / me[k / nd]);
    }
  }
  return w2max > 0 ? 2.0 / std::sqrt(w2max) : 1e300;
}

} // namespace fracdem
