// Linear tet4 / tri3 / quad4 kernels: small-strain, corotational and (plastic laws) logarithmic-
// strain corotational internal forces, stress, masses, dt.
#include "fem/fe_space.h"

#include "materials/material_table.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <type_traits>
#include <vector>

namespace fracdem
{

namespace
{

// Per-element blocks in geo_ (flat, contiguous, indexed by offset_[e]):
//   Tet4 : dNdX[4][3], V                                          -> 13 doubles
//   Tri3 : one point  : dNdX[3][2], w, hoop[3], r                  -> 11 doubles
//   Quad4: four points: (dNdX[4][2], w, hoop[4], r) x 4            -> 56 doubles
// w is the integration weight (V, A*t, or 2*pi*r*A: full ring); hoop[a] = N_a / r at the point
// (zero in plane strain), so the hoop strain is sum_a hoop[a] * u_a,x.
constexpr int kTetBlock = 13;
constexpr int kTriBlock = 11;
constexpr int kQuadPoint = 14;
constexpr int kQuadBlock = 4 * kQuadPoint;
constexpr double kPi = 3.14159265358979323846;
const double kGauss = 0.57735026918962576451; // 1/sqrt(3)
const double kQuadXi[4][2] = {
    {-kGauss, -kGauss}, {kGauss, -kGauss}, {kGauss, kGauss}, {-kGauss, kGauss}};

int block_size(ElemType t)
{
  return t == ElemType::Tet4 ? kTetBlock : t == ElemType::Tri3 ? kTriBlock : kQuadBlock;
}

inline double det3(const double m[9])
{
  return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
         m[2] * (m[3] * m[7] - m[4] * m[6]);
}

// Rotation of the polar decomposition F = R U (det F > 0) by Higham's Newton iteration
// R <- (g R + R^-T / g) / 2. Quadratic convergence; the determinant scaling g (a cbrt) only pays
// off far from orthogonality, so it is skipped for the mildly strained elements of explicit runs.
// Stops once a correction is < 1e-8: the next error is then ~1e-16 (quadratic convergence).
inline void polar_rotation(const double F[9], double R[9])
{
  for (int k = 0; k < 9; ++k)
    R[k] = F[k];
  for (int it = 0; it < 40; ++it) {
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
    const double d = R[0] * cof[0] + R[1] * cof[1] + R[2] * cof[2];
    const double g = std::fabs(d - 1.0) > 0.25 ? std::cbrt(1.0 / d) : 1.0;
    const double a = 0.5 * g, b = 0.5 / (g * d);
    double diff = 0;
    for (int k = 0; k < 9; ++k) {
      const double rn = a * R[k] + b * cof[k];
      diff = std::max(diff, std::fabs(rn - R[k]));
      R[k] = rn;
    }
    if (diff < 1e-8) break;
  }
}

// Logarithmic strain of the corotated stretch U (plastic laws under `model corotational`, see
// quad_kernel_log). A stretch is floored at kMinStretch so that an element that has just inverted
// (flagged, then eroded or the run stops) still yields finite numbers.
constexpr double kMinStretch = 1e-8;

// (ln a - ln b) / (a - b) for a, b > 0 (1 / a at a = b): the factor that maps a stress T
// conjugate to ln U onto S = dW/dU in U's principal frame, S'_ij = T'_ij dlog(l_i, l_j). Written
// 2 atanh(x) / (x (a + b)), x = (a - b) / (a + b), so that it stays exact as a -> b.
inline double log_divided_difference(double a, double b)
{
  const double x = (a - b) / (a + b), x2 = x * x;
  const double r = x2 < 1e-6 ? 1 + x2 * (1.0 / 3.0 + x2 / 5.0) : std::atanh(x) / x;
  return 2 * r / (a + b);
}

// Off-diagonal factor of the first Piola stress in U's principal frame: with W(ln U) and F = R U,
// dW = S : (R^T dF) - S : (Omega U), S = dW/dU (S'_ij = T'_ij dlog(l_i, l_j)), Omega = R^T dR.
// skew(R^T dF) = (Omega U + U Omega) / 2 gives Omega'_ij = 2 skew(R^T dF)'_ij / (l_i + l_j), so
// the rotation's term (zero for T coaxial with U) adds to the first and P = dW/dF = R Q M' Q^T,
// M'_ij = S'_ij 2 l_i / (l_i + l_j): f = -dE/dx exactly at a frozen history.
inline double stretch_stress_factor(double li, double lj)
{
  return log_divided_difference(li, lj) * 2 * li / (li + lj);
}

// In-plane corotated stretch U = R^T F (R: rotation2d's c, s), symmetric, in its principal frame:
// stretches l1, l2 and the first principal direction (pc, ps).
struct Stretch2 {
  double l1, l2, pc, ps;
  Stretch2(const double F[4], double c, double s)
  {
    const double a = c * F[0] + s * F[2], d = -s * F[1] + c * F[3];
    const double b = 0.5 * ((c * F[1] + s * F[3]) + (-s * F[0] + c * F[2]));
    const double m = 0.5 * (a + d), r = std::hypot(0.5 * (a - d), b);
    const double ph = 0.5 * std::atan2(2 * b, a - d);
    l1 = std::max(m + r, kMinStretch);
    l2 = std::max(m - r, kMinStretch);
    pc = std::cos(ph);
    ps = std::sin(ph);
  }
  // ln U: xx, yy, xy (tensor shear).
  void log(double L[3]) const
  {
    const double g1 = std::log(l1), g2 = std::log(l2);
    L[0] = pc * pc * g1 + ps * ps * g2;
    L[1] = ps * ps * g1 + pc * pc * g2;
    L[2] = pc * ps * (g1 - g2);
  }
  // The in-plane T (conjugate to ln U; xx, yy, xy) -> M (xx, xy, yx, yy) with P = R M = dW/dF:
  // in U's principal frame M'_ii = T'_ii / l_i, M'_ij = T'_ij dlog(l_i, l_j) 2 l_i / (l_i + l_j)
  // (see stretch_stress_factor).
  void force_stress(double xx, double yy, double xy, double M[4]) const
  {
    const double c = pc, s = ps;
    const double t11 = c * c * xx + 2 * c * s * xy + s * s * yy;
    const double t22 = s * s * xx - 2 * c * s * xy + c * c * yy;
    const double t12 = c * s * (yy - xx) + (c * c - s * s) * xy;
    const double a = t11 / l1, e = t22 / l2;
    const double b = t12 * stretch_stress_factor(l1, l2), d = t12 * stretch_stress_factor(l2, l1);
    M[0] = c * c * a - c * s * (b + d) + s * s * e;
    M[1] = c * s * (a - e) + c * c * b - s * s * d;
    M[2] = c * s * (a - e) + c * c * d - s * s * b;
    M[3] = s * s * a + c * s * (b + d) + c * c * e;
  }
};

// C = op(A) op(B) for 3x3 row-major matrices, op = transpose where asked.
inline void mul3(const double* A, bool ta, const double* B, bool tb, double* C)
{
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double v = 0;
      for (int k = 0; k < 3; ++k)
        v += (ta ? A[3 * k + i] : A[3 * i + k]) * (tb ? B[3 * j + k] : B[3 * k + j]);
      C[3 * i + j] = v;
    }
}

// A = Q diag(l) Q^T for a symmetric 3x3 A (row-major; Q's columns are the eigenvectors) by
// cyclic Jacobi rotations: robust for (nearly) repeated stretches, where the eigenvectors are
// ill-defined but Q diag(f(l)) Q^T is still accurate; converges quadratically.
inline void sym_eigen3(const double A[9], double l[3], double Q[9])
{
  double a[9];
  for (int k = 0; k < 9; ++k) {
    a[k] = A[k];
    Q[k] = k % 4 == 0 ? 1.0 : 0.0;
  }
  const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = a[1] * a[1] + a[2] * a[2] + a[5] * a[5];
    if (!(off > 1e-32 * (a[0] * a[0] + a[4] * a[4] + a[8] * a[8]))) break;
    for (const auto& pq : pairs) {
      const int p = pq[0], q = pq[1];
      const double apq = a[3 * p + q];
      if (apq == 0) continue;
      const double th = (a[3 * q + q] - a[3 * p + p]) / (2 * apq);
      const double t = std::fabs(th) > 1e150
                           ? 0.5 / th
                           : std::copysign(1.0, th) / (std::fabs(th) + std::sqrt(th * th + 1));
      const double c = 1 / std::sqrt(t * t + 1), s = t * c;
      for (int k = 0; k < 3; ++k) { // columns p, q of a and Q
        const double akp = a[3 * k + p], akq = a[3 * k + q];
        a[3 * k + p] = c * akp - s * akq;
        a[3 * k + q] = s * akp + c * akq;
        const double qkp = Q[3 * k + p], qkq = Q[3 * k + q];
        Q[3 * k + p] = c * qkp - s * qkq;
        Q[3 * k + q] = s * qkp + c * qkq;
      }
      for (int k = 0; k < 3; ++k) { // rows p, q of a
        const double apk = a[3 * p + k], aqk = a[3 * q + k];
        a[3 * p + k] = c * apk - s * aqk;
        a[3 * q + k] = s * apk + c * aqk;
      }
    }
  }
  for (int i = 0; i < 3; ++i)
    l[i] = a[4 * i];
}

// Constitutive laws seen by the element kernels: strain in, stress (and updated state) out, per
// integration point. eps: Voigt (xx, yy, zz, xy, yz, zx), engineering shear; zz is the hoop
// strain in axisymmetric runs. trace: the element's dilatation at the point (B-bar: the element
// mean). Returns sigma : eps (twice the energy density). bind() selects element e's data.
struct ElasticLaw {
  double lam, mu;
  bool plane_stress; // sigma_zz = 0 (lam is then the plane-stress reduced constant)
  int damaged = 0;   // never: elasticity does not fail
  void bind(int, const std::array<int, 4>&) {}
  double operator()(const double e[6], double trace, int, double s[6]) const
  {
    const double ltr = lam * trace;
    s[0] = ltr + 2 * mu * e[0];
    s[1] = ltr + 2 * mu * e[1];
    s[2] = plane_stress ? 0.0 : ltr + 2 * mu * e[2];
    s[3] = mu * e[3];
    s[4] = mu * e[4];
    s[5] = mu * e[5];
    return s[0] * e[0] + s[1] * e[1] + s[2] * e[2] + s[3] * e[3] + s[4] * e[4] + s[5] * e[5];
  }
};

// Rankine rotating crack with crack-band softening (materials/rankine.h); state: one block of
// kRankineStateSize doubles per integration point, element blocks at state_offset[e].
struct RankineLaw {
  RankineParams params;
  StressMode mode;
  const double* X;
  const int* state_offset;
  double* state;
  double elem_X[12];
  int nnodes = 0;
  double* elem_state = nullptr;
  int elem = -1;
  std::vector<int>* damaged_elems = nullptr; // elements with a damaged point, if wanted
  std::vector<int>* failed_elems = nullptr;  // elements with a point that carries no tension
  const std::uint8_t* may_soften = nullptr;  // softening mask (crack tracking), null: all may
  std::vector<int>* overstressed = nullptr;  // held elements whose stress reached ft
  bool held = false;                         // the bound element may not soften
  void bind(int e, const std::array<int, 4>& c)
  {
    elem = e;
    held = may_soften && !may_soften[e];
    nnodes = c[3] >= 0 ? 4 : 3;
    for (int a = 0; a < nnodes; ++a)
      for (int i = 0; i < 3; ++i)
        elem_X[3 * a + i] = X[3 * c[a] + i];
    elem_state = state + state_offset[e];
  }
  int damaged = 0; // points with damage > 0 seen (fracture checks skip an intact body)
  double operator()(const double e[6], double, int q, double s[6])
  {
    double* st = elem_state + q * kRankineStateSize;
    if (held && rankine_damage(st) == 0) {
      bool over = false;
      const double w2 = 2.0 * rankine_held_stress(params, mode, e, st, s, &over);
      if (over && overstressed && (overstressed->empty() || overstressed->back() != elem))
        overstressed->push_back(elem);
      return w2;
    }
    const double w2 = 2.0 * rankine_stress(params, mode, e, elem_X, nnodes, st, s);
    if (rankine_damage(st) > 0) {
      ++damaged;
      if (damaged_elems && (damaged_elems->empty() || damaged_elems->back() != elem))
        damaged_elems->push_back(elem);
      if (failed_elems && (failed_elems->empty() || failed_elems->back() != elem) &&
          rankine_cracked(params, st))
        failed_elems->push_back(elem);
    }
    return w2;
  }
};

// J2 plasticity with a flow-stress family and an EOS (materials/plasticity.h); state: one block of
// kPlasticStateSize doubles per integration point. dt: time since the previous force evaluation
// (the strain rate of rate-dependent flow stresses; <= 0 reuses the stored rate).
struct PlasticLaw {
  J2Params params;
  StressMode mode;
  double dt;
  const int* state_offset;
  double* state;
  double* elem_state = nullptr;
  int damaged = 0; // plasticity does not fail (erosion by plastic strain is the body's business)
  void bind(int e, const std::array<int, 4>&) { elem_state = state + state_offset[e]; }
  double operator()(const double e[6], double, int q, double s[6])
  {
    return 2.0 * plastic_stress(params, mode, e, dt, elem_state + q * kPlasticStateSize, s);
  }
};

// Tet4, one point. u: nodal displacements (12). Adds -grad E into fl (12, overwritten).
// sig (optional): Cauchy stress, Voigt 6. Returns the strain energy.
template <bool Corot, class Law>
inline double tet_kernel(const double* g, const double* u, Law& law, double* fl, double& detF,
                         double* sig)
{
  const double* dN = g;
  const double V = g[12];
  double H[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0}; // H[i*3+j] = du_i/dX_j, from displacements (accuracy)
  for (int a = 0; a < 4; ++a) {
    const double d0 = dN[3 * a], d1 = dN[3 * a + 1], d2 = dN[3 * a + 2];
    for (int i = 0; i < 3; ++i) {
      const double ui = u[3 * a + i];
      H[3 * i + 0] += ui * d0;
      H[3 * i + 1] += ui * d1;
      H[3 * i + 2] += ui * d2;
    }
  }
  double F[9] = {H[0] + 1, H[1], H[2], H[3], H[4] + 1, H[5], H[6], H[7], H[8] + 1};
  detF = det3(F);
  double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  if (Corot) {
    // An inverted element has no proper polar rotation: keep R = I (it is flagged anyway).
    if (detF > 0) polar_rotation(F, R);
    // H = R^T F - I: displacement gradient in the co-rotated frame
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        H[3 * i + j] =
            R[i] * F[j] + R[3 + i] * F[3 + j] + R[6 + i] * F[6 + j] - (i == j ? 1.0 : 0.0);
  }
  const double exx = H[0], eyy = H[4], ezz = H[8];
  const double gxy = H[1] + H[3], gyz = H[5] + H[7], gzx = H[2] + H[6];
  const double eps[6] = {exx, eyy, ezz, gxy, gyz, gzx};
  double st[6];
  const double w2 = law(eps, exx + eyy + ezz, 0, st);
  const double sxx = st[0], syy = st[1], szz = st[2], sxy = st[3], syz = st[4], szx = st[5];
  double P[9] = {sxx, sxy, szx, sxy, syy, syz, szx, syz, szz};
  if (Corot) { // first Piola stress P = R sigma
    double RP[9];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        RP[3 * i + j] = R[3 * i + 0] * P[0 + j] + R[3 * i + 1] * P[3 + j] + R[3 * i + 2] * P[6 + j];
    if (sig) { // Cauchy ~ R sigma R^T (small strains)
      double c[9];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          c[3 * i + j] =
              RP[3 * i] * R[3 * j] + RP[3 * i + 1] * R[3 * j + 1] + RP[3 * i + 2] * R[3 * j + 2];
      sig[0] = c[0];
      sig[1] = c[4];
      sig[2] = c[8];
      sig[3] = c[1];
      sig[4] = c[5];
      sig[5] = c[2];
    }
    for (int k = 0; k < 9; ++k)
      P[k] = RP[k];
  } else if (sig) {
    sig[0] = sxx;
    sig[1] = syy;
    sig[2] = szz;
    sig[3] = sxy;
    sig[4] = syz;
    sig[5] = szx;
  }
  for (int a = 0; a < 4; ++a) {
    const double d0 = V * dN[3 * a], d1 = V * dN[3 * a + 1], d2 = V * dN[3 * a + 2];
    fl[3 * a + 0] = -(P[0] * d0 + P[1] * d1 + P[2] * d2);
    fl[3 * a + 1] = -(P[3] * d0 + P[4] * d1 + P[5] * d2);
    fl[3 * a + 2] = -(P[6] * d0 + P[7] * d1 + P[8] * d2);
  }
  return 0.5 * V * w2;
}

// In-plane polar rotation (closed form): R = [[c,-s],[s,c]] makes R^T F symmetric.
inline void rotation2d(const double F[4], double& c, double& s)
{
  const double a = F[0] + F[3], b = F[2] - F[1];
  const double n = std::sqrt(a * a + b * b);
  if (n > 0) {
    c = a / n;
    s = b / n;
  } else {
    c = 1;
    s = 0;
  }
}

// Tri3, one point. u: nodal displacements (2 per node). fl (6) overwritten. sig (optional):
// xx, yy, zz|hoop, xy. Returns the strain energy.
template <bool Corot, class Law>
inline double tri_kernel(const double* g, const double* u, Law& law, double* fl, double& detF,
                         double* sig)
{
  const double* dN = g;
  const double w = g[6];
  const double* hoop = g + 7;
  double H[4] = {0, 0, 0, 0}, eth = 0;
  for (int a = 0; a < 3; ++a) {
    const double ux = u[2 * a], uy = u[2 * a + 1], dx = dN[2 * a], dy = dN[2 * a + 1];
    H[0] += ux * dx;
    H[1] += ux * dy;
    H[2] += uy * dx;
    H[3] += uy * dy;
    eth += hoop[a] * ux;
  }
  const double F[4] = {H[0] + 1, H[1], H[2], H[3] + 1};
  detF = F[0] * F[3] - F[1] * F[2];
  double c = 1, s = 0;
  if (Corot) {
    rotation2d(F, c, s);
    H[0] = c * F[0] + s * F[2] - 1;
    H[1] = c * F[1] + s * F[3];
    H[2] = -s * F[0] + c * F[2];
    H[3] = -s * F[1] + c * F[3] - 1;
  }
  const double exx = H[0], eyy = H[3], gxy = H[1] + H[2];
  const double eps[6] = {exx, eyy, eth, gxy, 0, 0};
  double st[6];
  const double w2 = law(eps, exx + eyy + eth, 0, st);
  const double sxx = st[0], syy = st[1], sth = st[2], sxy = st[3];
  double P0 = sxx, P1 = sxy, P2 = sxy, P3 = syy;
  if (Corot) {
    P0 = c * sxx - s * sxy;
    P1 = c * sxy - s * syy;
    P2 = s * sxx + c * sxy;
    P3 = s * sxy + c * syy;
  }
  for (int a = 0; a < 3; ++a) {
    const double dx = w * dN[2 * a], dy = w * dN[2 * a + 1];
    fl[2 * a] = -(P0 * dx + P1 * dy + sth * w * hoop[a]);
    fl[2 * a + 1] = -(P2 * dx + P3 * dy);
  }
  if (sig) {
    sig[0] = c * c * sxx - 2 * c * s * sxy + s * s * syy;
    sig[1] = s * s * sxx + 2 * c * s * sxy + c * c * syy;
    sig[2] = sth;
    sig[3] = c * s * (sxx - syy) + (c * c - s * s) * sxy;
  }
  return 0.5 * w * w2;
}

// Quad4, 2x2 Gauss with B-bar: the dilatation theta_q at each point (in-plane trace + hoop strain)
// is replaced by its weighted element mean theta_bar, eps_bar = eps_q + (theta_bar - theta_q)/3 I
// (the out-of-plane / hoop component included), which removes volumetric locking near nu = 1/2
// and keeps the element energy-consistent: E = sum_q w_q eps_bar:C:eps_bar / 2 and
// f_a = -sum_q w_q [R sigma grad N_a + sigma_zz hoop_a e_x + p_q (bbar_a - b_a(q))],
// with b_a(q) = d theta_q / d x_a = R_q grad N_a + hoop_a e_x and p_q = tr(sigma_q) / 3.
// u: displacements (2 per node); fl (8) overwritten; sig (optional) gets the point average.
// Without B-bar (plane stress, where nothing locks) each point keeps its own dilatation.
template <bool Corot, class Law>
inline double quad_kernel(const double* g, const double* u, Law& law, bool bbar_on, double* fl,
                          double& detmin, double* sig)
{
  double H[4][4], eth[4], th[4], cq[4], sq[4];
  double W = 0, thbar = 0;
  detmin = 1e300;
  for (int q = 0; q < 4; ++q) {
    const double* gq = g + q * kQuadPoint;
    const double* dN = gq;
    const double* hoop = gq + 9;
    double h[4] = {0, 0, 0, 0}, et = 0;
    for (int a = 0; a < 4; ++a) {
      const double ux = u[2 * a], uy = u[2 * a + 1], dx = dN[2 * a], dy = dN[2 * a + 1];
      h[0] += ux * dx;
      h[1] += ux * dy;
      h[2] += uy * dx;
      h[3] += uy * dy;
      et += hoop[a] * ux;
    }
    const double F[4] = {h[0] + 1, h[1], h[2], h[3] + 1};
    detmin = std::min(detmin, F[0] * F[3] - F[1] * F[2]);
    double c = 1, s = 0;
    if (Corot) {
      rotation2d(F, c, s);
      h[0] = c * F[0] + s * F[2] - 1;
      h[1] = c * F[1] + s * F[3];
      h[2] = -s * F[0] + c * F[2];
      h[3] = -s * F[1] + c * F[3] - 1;
    }
    for (int k = 0; k < 4; ++k)
      H[q][k] = h[k];
    eth[q] = et;
    cq[q] = c;
    sq[q] = s;
    th[q] = h[0] + h[3] + et;
    W += gq[8];
    thbar += gq[8] * th[q];
  }
  thbar /= W;
  for (int k = 0; k < 8; ++k)
    fl[k] = 0;
  double bbar[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  double psum = 0, energy = 0;
  if (sig) sig[0] = sig[1] = sig[2] = sig[3] = 0;
  for (int q = 0; q < 4; ++q) {
    const double* gq = g + q * kQuadPoint;
    const double* dN = gq;
    const double w = gq[8];
    const double* hoop = gq + 9;
    const double c = cq[q], s = sq[q];
    const double d = bbar_on ? (thbar - th[q]) / 3.0 : 0.0;
    const double exx = H[q][0] + d, eyy = H[q][3] + d, ezz = eth[q] + d, gxy = H[q][1] + H[q][2];
    const double eps[6] = {exx, eyy, ezz, gxy, 0, 0};
    double st[6];
    const double w2 = law(eps, bbar_on ? thbar : th[q], q, st);
    const double sxx = st[0], syy = st[1], szz = st[2], sxy = st[3];
    const double p = bbar_on ? (sxx + syy + szz) / 3.0 : 0.0;
    double P0 = sxx, P1 = sxy, P2 = sxy, P3 = syy;
    if (Corot) {
      P0 = c * sxx - s * sxy;
      P1 = c * sxy - s * syy;
      P2 = s * sxx + c * sxy;
      P3 = s * sxy + c * syy;
    }
    for (int a = 0; a < 4; ++a) {
      const double dx = dN[2 * a], dy = dN[2 * a + 1];
      const double bx = c * dx - s * dy + hoop[a], by = s * dx + c * dy;
      fl[2 * a] -= w * (P0 * dx + P1 * dy + szz * hoop[a] - p * bx);
      fl[2 * a + 1] -= w * (P2 * dx + P3 * dy - p * by);
      bbar[2 * a] += w * bx;
      bbar[2 * a + 1] += w * by;
    }
    psum += w * p;
    energy += 0.5 * w * w2;
    if (sig) {
      sig[0] += 0.25 * (c * c * sxx - 2 * c * s * sxy + s * s * syy);
      sig[1] += 0.25 * (s * s * sxx + 2 * c * s * sxy + c * c * syy);
      sig[2] += 0.25 * szz;
      sig[3] += 0.25 * (c * s * (sxx - syy) + (c * c - s * s) * sxy);
    }
  }
  const double pw = psum / W;
  for (int k = 0; k < 8; ++k)
    fl[k] -= pw * bbar[k];
  return energy;
}

// Logarithmic-strain corotational kernels (plastic laws, `model corotational`). The law gets
// ln U of the corotated stretch U = R^T F (in 2D with the hoop stretch l_t = 1 + u_r / r, ln l_t)
// and returns the stress T conjugate to it per unit reference volume: the rotated Kirchhoff
// stress, Cauchy = R T R^T / J. The forces are f = -dE/dx with P = dW/dF formed in U's
// principal frame (Stretch2 / sym_eigen3, stretch_stress_factor), the rotation's variation
// included, so they are exact for any stress (not only one coaxial with U) at a frozen history.
// Isochoric plastic flow in ln U keeps the volume at any strain, which U - I does not.

// R T R^T / J into sig (xx, yy, zz|hoop, xy); t: the law's Voigt stress (tensor shear).
inline void add_cauchy_2d(double c, double s, const double t[6], double scale, double* sig)
{
  sig[0] += scale * (c * c * t[0] - 2 * c * s * t[3] + s * s * t[1]);
  sig[1] += scale * (s * s * t[0] + 2 * c * s * t[3] + c * c * t[1]);
  sig[2] += scale * t[2];
  sig[3] += scale * (c * s * (t[0] - t[1]) + (c * c - s * s) * t[3]);
}

// Tet4, one point (see tet_kernel). detF: det F.
template <class Law>
inline double tet_kernel_log(const double* g, const double* u, Law& law, double* fl, double& detF,
                             double* sig)
{
  const double* dN = g;
  const double V = g[12];
  double F[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        F[3 * i + j] += u[3 * a + i] * dN[3 * a + j];
  detF = det3(F);
  double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, U[9], Q[9], l[3], gl[3];
  if (detF > 0) polar_rotation(F, R);
  mul3(R, true, F, false, U);
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      U[3 * i + j] = U[3 * j + i] = 0.5 * (U[3 * i + j] + U[3 * j + i]);
  sym_eigen3(U, l, Q);
  for (int i = 0; i < 3; ++i) {
    l[i] = std::max(l[i], kMinStretch);
    gl[i] = std::log(l[i]);
  }
  double L[9]; // ln U = Q diag(gl) Q^T
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      L[3 * i + j] = Q[3 * i] * gl[0] * Q[3 * j] + Q[3 * i + 1] * gl[1] * Q[3 * j + 1] +
                     Q[3 * i + 2] * gl[2] * Q[3 * j + 2];
  const double eps[6] = {L[0], L[4], L[8], 2 * L[1], 2 * L[5], 2 * L[2]};
  double t[6];
  const double w2 = law(eps, gl[0] + gl[1] + gl[2], 0, t);
  const double T[9] = {t[0], t[3], t[5], t[3], t[1], t[4], t[5], t[4], t[2]};
  double A[9], B[9], P[9];
  mul3(T, false, Q, false, A);
  mul3(Q, true, A, false, B); // T' = Q^T T Q, then M' (stretch_stress_factor), P = R Q M' Q^T
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      B[3 * i + j] *= i == j ? 1.0 / l[i] : stretch_stress_factor(l[i], l[j]);
  mul3(B, false, Q, true, A);
  mul3(Q, false, A, false, B);
  mul3(R, false, B, false, P);
  if (sig) {
    mul3(T, false, R, true, A);
    mul3(R, false, A, false, B);
    const double inv = 1.0 / std::max(detF, 1e-300);
    const double c[6] = {B[0], B[4], B[8], B[1], B[5], B[2]};
    for (int k = 0; k < 6; ++k)
      sig[k] = inv * c[k];
  }
  for (int a = 0; a < 4; ++a) {
    const double d0 = V * dN[3 * a], d1 = V * dN[3 * a + 1], d2 = V * dN[3 * a + 2];
    for (int i = 0; i < 3; ++i)
      fl[3 * a + i] = -(P[3 * i] * d0 + P[3 * i + 1] * d1 + P[3 * i + 2] * d2);
  }
  return 0.5 * V * w2;
}

// In-plane deformation gradient and hoop stretch of a 2D point (dN, hoop of its block).
inline void point_gradient(const double* dN, const double* hoop, const double* u, int nn,
                           double F[4], double& lt)
{
  F[0] = F[3] = 1;
  F[1] = F[2] = 0;
  lt = 1;
  for (int a = 0; a < nn; ++a) {
    const double ux = u[2 * a], uy = u[2 * a + 1], dx = dN[2 * a], dy = dN[2 * a + 1];
    F[0] += ux * dx;
    F[1] += ux * dy;
    F[2] += uy * dx;
    F[3] += uy * dy;
    lt += hoop[a] * ux;
  }
}

// Tri3, one point (see tri_kernel). detJ: det F times the hoop stretch (the volume ratio).
template <class Law>
inline double tri_kernel_log(const double* g, const double* u, Law& law, double* fl, double& detJ,
                             double* sig)
{
  const double* dN = g;
  const double w = g[6];
  const double* hoop = g + 7;
  double F[4], lt, c, s, L[3];
  point_gradient(dN, hoop, u, 3, F, lt);
  detJ = (F[0] * F[3] - F[1] * F[2]) * lt;
  rotation2d(F, c, s);
  const Stretch2 U(F, c, s);
  U.log(L);
  lt = std::max(lt, kMinStretch);
  const double gt = std::log(lt);
  const double eps[6] = {L[0], L[1], gt, 2 * L[2], 0, 0};
  double t[6];
  const double w2 = law(eps, L[0] + L[1] + gt, 0, t);
  double M[4];
  U.force_stress(t[0], t[1], t[3], M);
  const double sth = t[2] / lt;
  const double P0 = c * M[0] - s * M[2], P1 = c * M[1] - s * M[3];
  const double P2 = s * M[0] + c * M[2], P3 = s * M[1] + c * M[3];
  for (int a = 0; a < 3; ++a) {
    const double dx = w * dN[2 * a], dy = w * dN[2 * a + 1];
    fl[2 * a] = -(P0 * dx + P1 * dy + sth * w * hoop[a]);
    fl[2 * a + 1] = -(P2 * dx + P3 * dy);
  }
  if (sig) {
    sig[0] = sig[1] = sig[2] = sig[3] = 0;
    add_cauchy_2d(c, s, t, 1.0 / std::max(detJ, 1e-300), sig);
  }
  return 0.5 * w * w2;
}

// Quad4, 2x2 Gauss (see quad_kernel), with the volumetric part taken from the element's volume
// ratio J_bar = sum_q w_q J_q / W (an F-bar for the dilatation: theta_bar = ln J_bar, which is
// exactly the element's volume change, where the mean of ln J_q would not be):
// eps_bar = ln U_q + (theta_bar - theta_q) / 3 I, theta_q = ln J_q, and with
// b_a(q) = d theta_q / d x_a = F_q^-T grad N_a + hoop_a / l_t e_x (current gradients),
// d theta_bar / d x_a = sum_q w_q J_q b_a(q) / (W J_bar). detmin: the smallest J_q.
template <class Law>
inline double quad_kernel_log(const double* g, const double* u, Law& law, bool bbar_on, double* fl,
                              double& detmin, double* sig)
{
  double F[4][4], cq[4], sq[4], lt[4], L[4][3], gt[4], th[4], Jq[4], jf[4];
  double W = 0, WJ = 0;
  detmin = 1e300;
  for (int q = 0; q < 4; ++q) {
    const double* gq = g + q * kQuadPoint;
    point_gradient(gq, gq + 9, u, 4, F[q], lt[q]);
    jf[q] = F[q][0] * F[q][3] - F[q][1] * F[q][2];
    Jq[q] = jf[q] * lt[q];
    detmin = std::min(detmin, Jq[q]);
    rotation2d(F[q], cq[q], sq[q]);
    Stretch2(F[q], cq[q], sq[q]).log(L[q]);
    lt[q] = std::max(lt[q], kMinStretch);
    jf[q] = std::max(jf[q], kMinStretch);
    gt[q] = std::log(lt[q]);
    th[q] = L[q][0] + L[q][1] + gt[q];
    W += gq[8];
    WJ += gq[8] * Jq[q];
  }
  WJ = std::max(WJ, kMinStretch * W);
  const double thbar = std::log(WJ / W);
  for (int k = 0; k < 8; ++k)
    fl[k] = 0;
  double bbar[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  double psum = 0, energy = 0;
  if (sig) sig[0] = sig[1] = sig[2] = sig[3] = 0;
  for (int q = 0; q < 4; ++q) {
    const double* gq = g + q * kQuadPoint;
    const double* dN = gq;
    const double w = gq[8];
    const double* hoop = gq + 9;
    const double c = cq[q], s = sq[q], *Fq = F[q];
    const double d = bbar_on ? (thbar - th[q]) / 3.0 : 0.0;
    const double eps[6] = {L[q][0] + d, L[q][1] + d, gt[q] + d, 2 * L[q][2], 0, 0};
    double t[6];
    const double w2 = law(eps, bbar_on ? thbar : th[q], q, t);
    const double p = bbar_on ? (t[0] + t[1] + t[2]) / 3.0 : 0.0;
    double M[4];
    Stretch2(Fq, c, s).force_stress(t[0], t[1], t[3], M);
    const double sth = t[2] / lt[q];
    const double P0 = c * M[0] - s * M[2], P1 = c * M[1] - s * M[3];
    const double P2 = s * M[0] + c * M[2], P3 = s * M[1] + c * M[3];
    for (int a = 0; a < 4; ++a) {
      const double dx = dN[2 * a], dy = dN[2 * a + 1];
      const double bx = (Fq[3] * dx - Fq[2] * dy) / jf[q] + hoop[a] / lt[q];
      const double by = (-Fq[1] * dx + Fq[0] * dy) / jf[q];
      fl[2 * a] -= w * (P0 * dx + P1 * dy + sth * hoop[a] - p * bx);
      fl[2 * a + 1] -= w * (P2 * dx + P3 * dy - p * by);
      bbar[2 * a] += w * Jq[q] * bx;
      bbar[2 * a + 1] += w * Jq[q] * by;
    }
    psum += w * p;
    energy += 0.5 * w * w2;
    if (sig) add_cauchy_2d(c, s, t, 0.25 / std::max(bbar_on ? WJ / W : Jq[q], 1e-300), sig);
  }
  const double pw = psum / WJ;
  for (int k = 0; k < 8; ++k)
    fl[k] -= pw * bbar[k];
  return energy;
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

enum class Geo { Ok, Inverted, Degenerate };

// Fills one element block g from local node coordinates p (3 per node). measure: volume / area;
// value: the offending signed measure when not Ok.
Geo element_geometry(ElemType t, const double* p, bool axisym, double thickness, double* g,
                     double& measure, double& value)
{
  if (t == ElemType::Tet4) {
    double J[9]; // columns: edges from node 0
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i)
        J[3 * i + k] = p[3 * (k + 1) + i] - p[i];
    double h2 = 0; // longest edge, squared
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        double l2 = 0;
        for (int i = 0; i < 3; ++i)
          l2 += (p[3 * a + i] - p[3 * b + i]) * (p[3 * a + i] - p[3 * b + i]);
        h2 = std::max(h2, l2);
      }
    const double det = det3(J);
    const double V = det / 6.0;
    measure = value = V;
    const double tol = 1e-14 * h2 * std::sqrt(h2);
    if (!(std::fabs(V) >= tol) || h2 == 0) return Geo::Degenerate;
    if (V < 0) return Geo::Inverted;
    // rows of J^-1 are dN_k/dX for k = 1..3; dN_0 = -sum
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
      for (int k = 0; k < 3; ++k)
        g[3 * (k + 1) + j] = inv[3 * k + j];
    }
    g[12] = V;
    return Geo::Ok;
  }
  if (t == ElemType::Tri3) {
    const double x0 = p[0], y0 = p[1], x1 = p[3], y1 = p[4], x2 = p[6], y2 = p[7];
    const double A2 = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
    const double h2 = std::max({(x1 - x0) * (x1 - x0) + (y1 - y0) * (y1 - y0),
                                (x2 - x0) * (x2 - x0) + (y2 - y0) * (y2 - y0),
                                (x2 - x1) * (x2 - x1) + (y2 - y1) * (y2 - y1)});
    const double A = 0.5 * A2;
    measure = value = A;
    const double r = (x0 + x1 + x2) / 3.0;
    if (!(std::fabs(A) >= 1e-14 * h2) || h2 == 0) return Geo::Degenerate;
    if (A < 0) return Geo::Inverted;
    if (axisym && !(r > 0)) return Geo::Degenerate; // all three nodes on the axis
    g[0] = (y1 - y2) / A2;
    g[1] = (x2 - x1) / A2;
    g[2] = (y2 - y0) / A2;
    g[3] = (x0 - x2) / A2;
    g[4] = (y0 - y1) / A2;
    g[5] = (x1 - x0) / A2;
    if (axisym) {
      g[6] = 2 * kPi * r * A;
      for (int a = 0; a < 3; ++a)
        g[7 + a] = 1.0 / (3.0 * r);
    } else {
      g[6] = A * thickness;
      for (int a = 0; a < 3; ++a)
        g[7 + a] = 0;
    }
    g[10] = r;
    return Geo::Ok;
  }
  // Quad4
  double h2 = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) {
      const double dx = p[3 * a] - p[3 * b], dy = p[3 * a + 1] - p[3 * b + 1];
      h2 = std::max(h2, dx * dx + dy * dy);
    }
  double area = 0;
  Geo status = Geo::Ok;
  value = 1e300;
  for (int q = 0; q < 4; ++q) {
    double N[4], dNdxi[4][2];
    quad_shape(kQuadXi[q][0], kQuadXi[q][1], N, dNdxi);
    double J[4] = {0, 0, 0, 0}, r = 0;
    for (int a = 0; a < 4; ++a) {
      const double xa = p[3 * a], ya = p[3 * a + 1];
      J[0] += xa * dNdxi[a][0];
      J[1] += xa * dNdxi[a][1];
      J[2] += ya * dNdxi[a][0];
      J[3] += ya * dNdxi[a][1];
      r += N[a] * xa;
    }
    const double det = J[0] * J[3] - J[1] * J[2]; // = area / 4 at this point for a parallelogram
    area += det;
    value = std::min(value, det);
    if (!(std::fabs(det) >= 0.25e-14 * h2) || h2 == 0) {
      status = Geo::Degenerate;
      continue;
    }
    if (det < 0) {
      if (status == Geo::Ok) status = Geo::Inverted;
      continue;
    }
    if (axisym && !(r > 0)) {
      status = Geo::Degenerate;
      continue;
    }
    double* gp = g + q * kQuadPoint;
    for (int a = 0; a < 4; ++a) {
      gp[2 * a] = (J[3] * dNdxi[a][0] - J[2] * dNdxi[a][1]) / det;
      gp[2 * a + 1] = (-J[1] * dNdxi[a][0] + J[0] * dNdxi[a][1]) / det;
    }
    if (axisym) {
      gp[8] = 2 * kPi * r * det;
      for (int a = 0; a < 4; ++a)
        gp[9 + a] = N[a] / r;
    } else {
      gp[8] = det * thickness;
      for (int a = 0; a < 4; ++a)
        gp[9 + a] = 0;
    }
    gp[13] = r;
  }
  measure = area;
  return status;
}

std::string elem_msg(int e, const std::string& what)
{
  std::ostringstream os;
  os << "fracdem: element " << e << " " << what;
  return os.str();
}

// One element: gathers its nodal displacements, runs its kernel. fl: local forces (3 per node for
// tets, 2 per node in 2D); sig (optional): Voigt 6 (tet) or 4 (2D: xx, yy, zz|hoop, xy).
// The laws that see the logarithmic strain under `model corotational` (the others keep U - I:
// elastic and Rankine bodies are small-strain laws in the corotated frame).
template <class Law> constexpr bool kLogStrain = std::is_same_v<Law, PlasticLaw>;

template <bool Corot, class Law>
double element_kernel(ElemType t, const int* c, const double* g, const double* X, const double* x,
                      Law& law, bool bbar_on, double* fl, double& detF, double* sig)
{
  constexpr bool kLog = Corot && kLogStrain<Law>;
  if (t == ElemType::Tet4) {
    double u[12];
    for (int a = 0; a < 4; ++a) {
      const int n = 3 * c[a];
      u[3 * a + 0] = x[n + 0] - X[n + 0];
      u[3 * a + 1] = x[n + 1] - X[n + 1];
      u[3 * a + 2] = x[n + 2] - X[n + 2];
    }
    if constexpr (kLog) return tet_kernel_log(g, u, law, fl, detF, sig);
    return tet_kernel<Corot>(g, u, law, fl, detF, sig);
  }
  const int nn = t == ElemType::Tri3 ? 3 : 4;
  double u[8];
  for (int a = 0; a < nn; ++a) {
    const int n = 3 * c[a];
    u[2 * a] = x[n] - X[n];
    u[2 * a + 1] = x[n + 1] - X[n + 1];
  }
  if constexpr (kLog) {
    if (t == ElemType::Tri3) return tri_kernel_log(g, u, law, fl, detF, sig);
    return quad_kernel_log(g, u, law, bbar_on, fl, detF, sig);
  }
  if (t == ElemType::Tri3) return tri_kernel<Corot>(g, u, law, fl, detF, sig);
  return quad_kernel<Corot>(g, u, law, bbar_on, fl, detF, sig);
}

// The element loop, instantiated per kinematics and law so the hot path has no model branches.
template <bool Corot, class Law>
double forces_loop(const Mesh& mesh, const double* geo, const int* offset, const double* x, int eb,
                   int ee, Law& law, bool bbar_on, double* f, double* elem_energy,
                   int* first_inverted)
{
  const double* X = mesh.X.data();
  const std::uint8_t* active = mesh.active.data();
  const ElemType* etype = mesh.etype.data();
  const std::array<int, 4>* conn = mesh.conn.data();
  double energy = 0;
  int inverted_first = -1;
  for (int e = eb; e < ee; ++e) {
    if (!active[e]) {
      if (elem_energy) elem_energy[e] = 0;
      continue;
    }
    const int* c = conn[e].data();
    law.bind(e, conn[e]);
    double fl[12], detF;
    const double en =
        element_kernel<Corot>(etype[e], c, geo + offset[e], X, x, law, bbar_on, fl, detF, nullptr);
    if (etype[e] == ElemType::Tet4) {
      for (int a = 0; a < 4; ++a) {
        double* fa = f + 3 * c[a];
        fa[0] += fl[3 * a];
        fa[1] += fl[3 * a + 1];
        fa[2] += fl[3 * a + 2];
      }
    } else {
      const int nn = etype[e] == ElemType::Tri3 ? 3 : 4;
      for (int a = 0; a < nn; ++a) {
        f[3 * c[a]] += fl[2 * a];
        f[3 * c[a] + 1] += fl[2 * a + 1];
      }
    }
    if (!(detF > 0) && inverted_first < 0) inverted_first = e;
    if (elem_energy) elem_energy[e] = en;
    energy += en;
  }
  if (first_inverted && inverted_first >= 0 && *first_inverted < 0)
    *first_inverted = inverted_first;
  return energy;
}

} // namespace

/* ---------------------------------------------------------------------- */

void FeSpace::build(const Mesh& mesh, const Material& mat)
{
  const std::string bad = material_setup_error(mat, mesh.dim);
  if (!bad.empty()) throw std::invalid_argument("fracdem: " + bad);
  mat_ = mat;
  log_strain_ = mat.kinematics == Kinematics::Corotational && mat.plastic_model();
  dim_ = mesh.dim;
  axisym_ = mesh.dim == 2 && mat.plane == PlaneMode::Axisymmetric;
  const int ne = mesh.num_elems();
  offset_.assign(ne + 1, 0);
  for (int e = 0; e < ne; ++e)
    offset_[e + 1] = offset_[e] + block_size(mesh.etype[e]);
  geo_.assign(offset_[ne], 0.0);
  measure_.assign(ne, 0.0);
  const int per_point = material_model_info(mat.model).state_per_point;
  state_offset_.assign(ne + 1, 0);
  for (int e = 0; e < ne; ++e)
    state_offset_[e + 1] = state_offset_[e] + per_point * points_per_elem(mesh.etype[e]);
  const double* X = mesh.X.data();
  const int nn = mesh.num_nodes();
  for (int e = 0; e < ne; ++e) {
    const ElemType t = mesh.etype[e];
    const int n = nodes_per_elem(t);
    if (elem_dim(t) != mesh.dim)
      throw FeError(
          e, elem_msg(e, "has the wrong dimension for a " + std::to_string(mesh.dim) + "D mesh"));
    double p[12];
    for (int a = 0; a < n; ++a) {
      const int node = mesh.conn[e][a];
      if (node < 0 || node >= nn)
        throw FeError(e, elem_msg(e, "refers to a missing node " + std::to_string(node)));
      for (int i = 0; i < 3; ++i)
        p[3 * a + i] = X[3 * node + i];
      if (axisym_ && X[3 * node] < 0) {
        std::ostringstream os;
        os << "has node " << node << " at r = x = " << X[3 * node]
           << " < 0 (axisymmetric meshes need x >= 0)";
        throw FeError(e, elem_msg(e, os.str()));
      }
    }
    double value = 0;
    const Geo st =
        element_geometry(t, p, axisym_, mat.thickness, &geo_[offset_[e]], measure_[e], value);
    if (st != Geo::Ok) {
      std::ostringstream os;
      if (st == Geo::Inverted)
        os << "is inverted: negative "
           << (t == ElemType::Tet4   ? "volume "
               : t == ElemType::Tri3 ? "area "
                                     : "Jacobian ")
           << value
           << (t == ElemType::Tet4 ? "; reorder its nodes" : "; order its nodes counter-clockwise");
      else
        os << "is degenerate: "
           << (t == ElemType::Tet4   ? "volume "
               : t == ElemType::Tri3 ? "area "
                                     : "Jacobian ")
           << value << " is too small for its size";
      throw FeError(e, elem_msg(e, os.str()));
    }
  }
}

void FeSpace::set_element(const Mesh& mesh, int e)
{
  const int held = static_cast<int>(measure_.size());
  const ElemType t = mesh.etype[e];
  if (e < 0 || e > held || (e < held && offset_[e + 1] - offset_[e] != block_size(t)))
    throw FeError(e, elem_msg(e, "cannot be set: no such element slot of its type"));
  double p[12], block[kQuadBlock], measure = 0, value = 0;
  for (int a = 0; a < nodes_per_elem(t); ++a)
    for (int i = 0; i < 3; ++i)
      p[3 * a + i] = mesh.X[3 * mesh.conn[e][a] + i];
  if (element_geometry(t, p, axisym_, mat_.thickness, block, measure, value) != Geo::Ok)
    throw FeError(e, elem_msg(e, "is inverted or degenerate after a cut (measure " +
                                     std::to_string(value) + ")"));
  if (e == held) {
    offset_.push_back(offset_.back() + block_size(t));
    geo_.resize(offset_.back(), 0.0);
    measure_.push_back(0.0);
    const int per_point = material_model_info(mat_.model).state_per_point;
    state_offset_.push_back(state_offset_.back() + per_point * points_per_elem(t));
  }
  std::copy(block, block + block_size(t), geo_.begin() + offset_[e]);
  measure_[e] = measure;
}

/* ---------------------------------------------------------------------- */

void FeSpace::element_masses(const Mesh& mesh, int e, double me[4]) const
{
  const double rho = mat_.rho;
  const double* g = &geo_[offset_[e]];
  const auto& c = mesh.conn[e];
  me[0] = me[1] = me[2] = me[3] = 0;
  switch (mesh.etype[e]) {
  case ElemType::Tet4:
    for (int a = 0; a < 4; ++a)
      me[a] = rho * g[12] / 4.0;
    break;
  case ElemType::Tri3:
    if (axisym_) {
      // exact row sums of the r-weighted consistent mass: 2 pi rho A (2 r_a + r_b + r_c) / 12
      const double* X = mesh.X.data();
      const double rs = X[3 * c[0]] + X[3 * c[1]] + X[3 * c[2]];
      for (int a = 0; a < 3; ++a)
        me[a] = 2 * kPi * rho * measure_[e] * (rs + X[3 * c[a]]) / 12.0;
    } else {
      for (int a = 0; a < 3; ++a)
        me[a] = rho * g[6] / 3.0;
    }
    break;
  case ElemType::Quad4:
    // row sums sum_q w_q N_a(q): exact for r N_a det J (cubic) with 2x2 Gauss
    for (int q = 0; q < 4; ++q) {
      double N[4], dNdxi[4][2];
      quad_shape(kQuadXi[q][0], kQuadXi[q][1], N, dNdxi);
      const double w = g[q * kQuadPoint + 8];
      for (int a = 0; a < 4; ++a)
        me[a] += rho * w * N[a];
    }
    break;
  }
}

void FeSpace::lumped_masses(const Mesh& mesh, std::vector<double>& m) const
{
  m.assign(mesh.num_nodes(), 0.0);
  for (int e = 0; e < mesh.num_elems(); ++e) {
    if (!mesh.active[e]) continue;
    double me[4];
    element_masses(mesh, e, me);
    const int n = nodes_per_elem(mesh.etype[e]);
    for (int a = 0; a < n; ++a)
      m[mesh.conn[e][a]] += me[a];
  }
}

/* ---------------------------------------------------------------------- */

StressMode stress_mode(const Material& mat, int dim)
{
  return dim == 3                               ? StressMode::Solid
         : mat.plane == PlaneMode::PlaneStress  ? StressMode::PlaneStress
         : mat.plane == PlaneMode::Axisymmetric ? StressMode::Axisymmetric
                                                : StressMode::PlaneStrain;
}

// Runs fn(law) with the body's constitutive law (the elastic one needs no state). may_soften:
// the softening mask (FeSpace::set_softening_mask; null: all may). dt: see PlasticLaw.
template <class Fn>
auto with_law(const Material& mat, int dim, const Mesh& mesh, const int* state_offset,
              double* state, double dt, const std::uint8_t* may_soften, Fn&& fn)
{
  if (mat.model == MaterialModel::Rankine) {
    RankineLaw law{mat.rankine(), stress_mode(mat, dim), mesh.X.data(), state_offset, state, {}, 0,
                   nullptr};
    law.may_soften = may_soften;
    return fn(law);
  }
  if (mat.plastic_model()) {
    J2Params jp = mat.plasticity();
    jp.log_strain = mat.kinematics == Kinematics::Corotational; // see kLogStrain
    PlasticLaw law{jp, stress_mode(mat, dim), dt, state_offset, state};
    return fn(law);
  }
  ElasticLaw law{mat.in_plane_lambda(dim), mat.mu(),
                 dim == 2 && mat.plane == PlaneMode::PlaneStress};
  return fn(law);
}

double FeSpace::add_internal_forces(const Mesh& mesh, const double* x, int e_begin, int e_end,
                                    double* f, double* elem_energy, int* first_inverted,
                                    double* state, int* damaged_points, double dt,
                                    std::vector<int>* damaged_elems,
                                    std::vector<int>* failed_elems,
                                    std::vector<int>* overstressed_elems) const
{
  if (damaged_elems) damaged_elems->clear();
  if (failed_elems) failed_elems->clear();
  if (overstressed_elems) overstressed_elems->clear();
  e_begin = std::max(e_begin, 0);
  e_end = std::min(e_end, mesh.num_elems());
  if (state_offset_.back() > 0 && !state)
    throw std::invalid_argument("FeSpace: this material needs its per-point state");
  const bool bbar = !(dim_ == 2 && mat_.plane == PlaneMode::PlaneStress);
  const bool corot = mat_.kinematics == Kinematics::Corotational;
  return with_law(
      mat_, dim_, mesh, state_offset_.data(), state, dt, softening_mask(), [&](auto& law) {
        if constexpr (std::is_same_v<std::decay_t<decltype(law)>, RankineLaw>) {
          law.damaged_elems = damaged_elems;
          law.failed_elems = failed_elems;
          law.overstressed = overstressed_elems;
        }
        const double energy =
            corot ? forces_loop<true>(mesh, geo_.data(), offset_.data(), x, e_begin, e_end, law,
                                      bbar, f, elem_energy, first_inverted)
                  : forces_loop<false>(mesh, geo_.data(), offset_.data(), x, e_begin, e_end, law,
                                       bbar, f, elem_energy, first_inverted);
        if (damaged_points) *damaged_points = law.damaged;
        return energy;
      });
}

/* ---------------------------------------------------------------------- */

// Element e alone on a copy of its state (output and erosion never advance the material
// history): returns its strain energy, its stress (Voigt 6 or 4, see element_kernel) into s.
double FeSpace::evaluate_copy(const Mesh& mesh, const double* x, int e, const double* state,
                              double s[6]) const
{
  double scratch[4 * kMaxStatePerPoint];
  const int ns = state_offset_[e + 1] - state_offset_[e];
  if (ns > 0) std::copy(state + state_offset_[e], state + state_offset_[e + 1], scratch);
  const int shift[1] = {0};
  const bool bbar = !(dim_ == 2 && mat_.plane == PlaneMode::PlaneStress);
  const bool corot = mat_.kinematics == Kinematics::Corotational;
  const ElemType t = mesh.etype[e];
  return with_law(mat_, dim_, mesh, shift, scratch, 0.0, nullptr, [&](auto& law) {
    law.bind(0, mesh.conn[e]);
    if constexpr (std::is_same_v<std::decay_t<decltype(law)>, RankineLaw>)
      law.held = !may_soften_.empty() && !may_soften_[e]; // bound as element 0 of the copy
    double fl[12], detF;
    const double* g = &geo_[offset_[e]];
    if (corot)
      return element_kernel<true>(t, mesh.conn[e].data(), g, mesh.X.data(), x, law, bbar, fl, detF,
                                  s);
    return element_kernel<false>(t, mesh.conn[e].data(), g, mesh.X.data(), x, law, bbar, fl, detF,
                                 s);
  });
}

void FeSpace::element_stress(const Mesh& mesh, const double* x, int e, double sigma[6],
                             const double* state) const
{
  for (int k = 0; k < 6; ++k)
    sigma[k] = 0;
  double s[6] = {0, 0, 0, 0, 0, 0};
  evaluate_copy(mesh, x, e, state, s);
  if (mesh.etype[e] == ElemType::Tet4) {
    std::copy(s, s + 6, sigma);
    return;
  }
  sigma[0] = s[0];
  sigma[1] = s[1];
  sigma[2] = s[2]; // plane strain: sigma_zz = lambda tr(eps) = nu (sxx + syy); axisymmetric: hoop
  sigma[3] = s[3];
}

double FeSpace::element_energy(const Mesh& mesh, const double* x, int e, const double* state) const
{
  if (!mesh.active[e]) return 0.0;
  double s[6] = {0, 0, 0, 0, 0, 0};
  return evaluate_copy(mesh, x, e, state, s);
}

double FeSpace::point_weight(const Mesh& mesh, int e, int q) const
{
  const double* g = &geo_[offset_[e]];
  switch (mesh.etype[e]) {
  case ElemType::Tet4:
    return g[12];
  case ElemType::Tri3:
    return g[6];
  case ElemType::Quad4:
    return g[q * kQuadPoint + 8];
  }
  return 0.0;
}

double FeSpace::von_mises(const double s[6])
{
  const double a = s[0] - s[1], b = s[1] - s[2], c = s[2] - s[0];
  return std::sqrt(0.5 * (a * a + b * b + c * c) + 3 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
}

/* ----------------------------------------------------------------------
   bulk viscosity
------------------------------------------------------------------------- */

namespace
{

// Weighted current-configuration gradients of element block g: bw[3a + i] = sum_q w_q b_a,i(q)
// with b_a = grad N_a (+ N_a / r e_x, the hoop part, in axisymmetric runs), so that
// sum_a bw_a . v_a = W div v and the forces q bw_a do the work q W div v. Returns W = sum_q w_q.
double weighted_gradients(ElemType t, const double* g, double bw[12])
{
  for (int k = 0; k < 12; ++k)
    bw[k] = 0;
  if (t == ElemType::Tet4) {
    for (int k = 0; k < 12; ++k)
      bw[k] = g[12] * g[k];
    return g[12];
  }
  const int n = t == ElemType::Tri3 ? 3 : 4;
  const int npts = t == ElemType::Tri3 ? 1 : 4;
  const int stride = t == ElemType::Tri3 ? kTriBlock : kQuadPoint;
  double W = 0;
  for (int q = 0; q < npts; ++q) {
    const double* gq = g + q * stride;
    const double w = gq[2 * n];
    const double* hoop = gq + 2 * n + 1;
    for (int a = 0; a < n; ++a) {
      bw[3 * a] += w * (gq[2 * a] + hoop[a]);
      bw[3 * a + 1] += w * gq[2 * a + 1];
    }
    W += w;
  }
  return W;
}

} // namespace

double FeSpace::element_damage(const Mesh& mesh, int e, const double* state) const
{
  if (mat_.model != MaterialModel::Rankine || !state) return 0.0;
  const int per = material_model_info(mat_.model).state_per_point;
  double d = 0, normal[3];
  for (int q = 0; q < points_per_elem(mesh.etype[e]); ++q)
    d = std::max(d, point_failure(mat_, state + state_offset_[e] + q * per, normal));
  return std::min(d, 1.0);
}

void FeSpace::add_viscous_forces(const Mesh& mesh, const double* x, const double* v, int e_begin,
                                 int e_end, const BulkViscosity& bv, const double* state, double* f,
                                 double* force_scale, double* rate) const
{
  e_begin = std::max(e_begin, 0);
  e_end = std::min(e_end, mesh.num_elems());
  const double c = mat_.dilatational_wave_speed();
  for (int e = e_begin; e < e_end; ++e) {
    force_scale[e] = rate[e] = 0;
    if (!mesh.active[e]) continue;
    const ElemType t = mesh.etype[e];
    const int n = nodes_per_elem(t);
    const int* conn = mesh.conn[e].data();
    double g[kQuadBlock];
    // An inverted element has no current gradients; it stops the run (or is eroded) anyway.
    if (!current_geometry(mesh, x, e, g)) continue;
    double bw[12], bw0[12];
    const double W = weighted_gradients(t, g, bw);
    const double W0 = weighted_gradients(t, &geo_[offset_[e]], bw0);
    double div = 0; // W div v
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < 3; ++i)
        div += bw[3 * a + i] * v[3 * conn[a] + i];
    const double D = div / W;
    rate[e] = D;
    if (!(D < 0)) continue;
    // The characteristic length of the stable-step bound, in the current configuration too.
    const double w2 = omega2_of(mesh, e, g);
    if (!(w2 > 0)) continue;
    const double l = c * 2.0 / std::sqrt(w2);
    const double rho = mat_.rho * W0 / W; // current density: mass conservation
    const double q =
        bulk_viscosity_pressure(bv, rho, c, l, D) * (1.0 - element_damage(mesh, e, state));
    force_scale[e] = q * W;
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < 3; ++i)
        f[3 * conn[a] + i] += q * bw[3 * a + i];
  }
}

void FeSpace::add_given_viscous_forces(const Mesh& mesh, const double* x, int e_begin, int e_end,
                                       const double* force_scale, double* f) const
{
  e_begin = std::max(e_begin, 0);
  e_end = std::min(e_end, mesh.num_elems());
  for (int e = e_begin; e < e_end; ++e) {
    if (!mesh.active[e] || force_scale[e] == 0) continue;
    const ElemType t = mesh.etype[e];
    const int n = nodes_per_elem(t);
    const int* conn = mesh.conn[e].data();
    double g[kQuadBlock];
    if (!current_geometry(mesh, x, e, g)) continue;
    double bw[12];
    const double q = force_scale[e] / weighted_gradients(t, g, bw);
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < 3; ++i)
        f[3 * conn[a] + i] += q * bw[3 * a + i];
  }
}

/* ---------------------------------------------------------------------- */

// Provable upper bound of lambda_max(M_e^-1 K_e) for element e (lumped, diagonal M_e).
// For the assembled mesh omega_max^2 = max_u u^T K u / u^T M u <= max_e lambda_max(M_e^-1 K_e)
// (sum of element Rayleigh quotients), and lambda_max(M_e^-1 K_e) <= lambda_max(K_e) / min_a m_a.
// At an integration point 2W = lambda' theta^2 + 2 mu |eps|^2 with theta = sum_a u_a . b_a and
// eps = sym(sum_a u_a (x) grad N_a) (+ hoop strain); Cauchy-Schwarz gives theta^2 <= |u|^2 T1,
// |eps|^2 <= |u|^2 T2 with T1 = sum_a |b_a|^2, T2 = sum_a (|grad N_a|^2 + hoop_a^2). Hence
// lambda_max(K_e) <= sum_q w_q (lambda' T1 + 2 mu T2). lambda' = lambda, or lambda + 2mu/3 for
// the B-bar quad (Jensen: the averaged dilatation has no more energy than the pointwise one).
// For a tet this is omega^2 <= 4 c^2 sum_a 1/h_a^2 (h_a: altitudes), i.e. characteristic
// length l = 2 / sqrt(4 sum_a h_a^-2) >= h_min / 2... the usual "min altitude" length divided by
// a shape-aware factor. Corotational K = R K0 R^T has the same eigenvalues as K0 (geometric
// stiffness neglected, as in all explicit codes); the bound is also taken with the geometry of
// the current configuration x so strongly deformed elements are covered, and the larger wins.
double FeSpace::omega2_bound(const Mesh& mesh, const double* x, int e) const
{
  if (!x) return omega2_of(mesh, e, nullptr);
  double g[kQuadBlock];
  return omega2_of(mesh, e, current_geometry(mesh, x, e, g) ? g : nullptr);
}

bool FeSpace::current_geometry(const Mesh& mesh, const double* x, int e, double* g) const
{
  const ElemType t = mesh.etype[e];
  double p[12], meas, value;
  for (int a = 0; a < nodes_per_elem(t); ++a)
    for (int i = 0; i < 3; ++i)
      p[3 * a + i] = x[3 * mesh.conn[e][a] + i];
  return element_geometry(t, p, axisym_, mat_.thickness, g, meas, value) == Geo::Ok;
}

double FeSpace::omega2_of(const Mesh& mesh, int e, const double* g_current) const
{
  const ElemType t = mesh.etype[e];
  const int n = nodes_per_elem(t);
  const double lam = mat_.lambda(), mu = mat_.mu();
  const double lamv = t == ElemType::Quad4 ? lam + 2.0 * mu / 3.0 : lam;
  double me[4];
  element_masses(mesh, e, me);
  double mmin = 1e300;
  for (int a = 0; a < n; ++a)
    mmin = std::min(mmin, me[a]);
  if (!(mmin > 0)) return 0;

  auto bound_of = [&](const double* g) {
    if (t == ElemType::Tet4) {
      double T = 0;
      for (int k = 0; k < 12; ++k)
        T += g[k] * g[k];
      return g[12] * (lamv + 2 * mu) * T;
    }
    const int npts = t == ElemType::Tri3 ? 1 : 4;
    const int stride = t == ElemType::Tri3 ? kTriBlock : kQuadPoint;
    double C = 0;
    for (int q = 0; q < npts; ++q) {
      const double* gq = g + q * stride;
      const double* hoop = gq + 2 * n + 1;
      double T1 = 0, T2 = 0;
      for (int a = 0; a < n; ++a) {
        const double dx = gq[2 * a], dy = gq[2 * a + 1];
        T1 += (dx + hoop[a]) * (dx + hoop[a]) + dy * dy;
        T2 += dx * dx + dy * dy + hoop[a] * hoop[a];
      }
      C += gq[2 * n] * (lamv * T1 + 2 * mu * T2);
    }
    return C;
  };

  double C = bound_of(&geo_[offset_[e]]);
  if (g_current) {
    double Cc = bound_of(g_current);
    // Logarithmic-strain kernels: the stiffness of tau (per unit REFERENCE volume) in the current
    // gradients is that of the current geometry times W0 / W = 1 / J (grows under compression).
    if (log_strain_) {
      double bw[12];
      const double W0 = weighted_gradients(t, &geo_[offset_[e]], bw);
      Cc *= std::max(1.0, W0 / weighted_gradients(t, g_current, bw));
    }
    C = std::max(C, Cc);
  }
  return C / mmin;
}

double FeSpace::characteristic_length(const Mesh& mesh, const double* x, int e) const
{
  const double w2 = omega2_bound(mesh, x, e);
  return w2 > 0 ? 2.0 / std::sqrt(w2) * mat_.dilatational_wave_speed() : 1e300;
}

double FeSpace::element_time_step(const Mesh& mesh, const double* x, int e, const BulkViscosity& bv,
                                  double rate) const
{
  const double dt0 = element_time_step(mesh, x, e);
  if (!bv.on || dt0 >= 1e300) return dt0;
  const double c = mat_.dilatational_wave_speed();
  return dt0 * damped_time_step_factor(bulk_viscosity_damping_ratio(bv, c, c * dt0, rate));
}

double FeSpace::stable_time_step(const Mesh& mesh, const double* x, const BulkViscosity* bv,
                                 const double* rate) const
{
  if (bv && bv->on) {
    double dt = 1e300;
    for (int e = 0; e < mesh.num_elems(); ++e)
      if (mesh.active[e]) dt = std::min(dt, element_time_step(mesh, x, e, *bv, rate ? rate[e] : 0));
    return dt;
  }
  double w2max = 0;
  for (int e = 0; e < mesh.num_elems(); ++e)
    if (mesh.active[e]) w2max = std::max(w2max, omega2_bound(mesh, x, e));
  return w2max > 0 ? 2.0 / std::sqrt(w2max) : 1e300;
}

void quad_point_positions(const double* X, const std::array<int, 4>& conn, double xy[4][2])
{
  for (int q = 0; q < 4; ++q) {
    double N[4], dNdxi[4][2];
    quad_shape(kQuadXi[q][0], kQuadXi[q][1], N, dNdxi);
    xy[q][0] = xy[q][1] = 0;
    for (int a = 0; a < 4; ++a)
      for (int d = 0; d < 2; ++d)
        xy[q][d] += N[a] * X[3 * conn[a] + d];
  }
}

} // namespace fracdem
