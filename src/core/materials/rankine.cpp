// Rankine rotating-crack stress update, crack-band softening laws and their bookkeeping.
#include "materials/rankine.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fracdem
{

namespace
{

// State slots (see rankine.h).
constexpr int kKappa = 0;
constexpr int kBand = 1;
constexpr int kDamage = 2;
constexpr int kNormal = 3;
constexpr int kDissipated = 6;
constexpr int kEpsPrev = 7;
constexpr int kSigPrev = 13;

// Voigt double contraction with engineering shear in eps: the shear terms count once.
inline double voigt_dot(const double a[6], const double b[6])
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] + a[4] * b[4] + a[5] * b[5];
}

// The strain the mode actually uses, so that the stored previous strain and the energies agree
// with the stress that was computed from it.
void effective_strain(StressMode mode, const double in[6], double e[6])
{
  for (int k = 0; k < 6; ++k)
    e[k] = in[k];
  if (mode == StressMode::Solid) return;
  e[4] = e[5] = 0;
  if (mode != StressMode::Axisymmetric) e[2] = 0; // plane strain: given; plane stress: ignored
}

// Lame constants of the mode. Plane stress: eliminating eps_zz from sigma_zz = 0 gives lambda* =
// 2 lambda mu / (lambda + 2 mu) = E nu / (1 - nu^2) for the in-plane law.
void lame(const RankineParams& p, StressMode mode, double& lam, double& mu)
{
  mu = p.E / (2 * (1 + p.nu));
  lam = mode == StressMode::PlaneStress ? p.E * p.nu / (1 - p.nu * p.nu)
                                        : p.E * p.nu / ((1 + p.nu) * (1 - 2 * p.nu));
}

void trial_stress(const RankineParams& p, StressMode mode, const double e[6], double s[6])
{
  double lam, mu;
  lame(p, mode, lam, mu);
  const double tr = e[0] + e[1] + e[2]; // plane stress: e[2] is 0, the 2D trace
  for (int k = 0; k < 3; ++k)
    s[k] = lam * tr + 2 * mu * e[k];
  for (int k = 3; k < 6; ++k)
    s[k] = mu * e[k];
  if (mode == StressMode::PlaneStress) s[2] = 0;
}

// One Jacobi rotation annihilating a[p][q] (Numerical Recipes' stable form), accumulated into v.
void jacobi_rotate(double a[3][3], double v[3][3], int p, int q)
{
  const double apq = a[p][q];
  const double g = 100.0 * std::fabs(apq);
  // Negligible next to both diagonal entries: the rotation could not change any of them.
  const double app = std::fabs(a[p][p]), aqq = std::fabs(a[q][q]);
  if (app + g == app && aqq + g == aqq) {
    a[p][q] = a[q][p] = 0;
    return;
  }
  const double hd = a[q][q] - a[p][p];
  double t;
  if (std::fabs(hd) + g == std::fabs(hd)) {
    t = apq / hd; // theta^2 would overflow: t = 1 / (2 theta)
  } else {
    const double theta = 0.5 * hd / apq;
    t = 1.0 / (std::fabs(theta) + std::sqrt(1.0 + theta * theta));
    if (theta < 0) t = -t;
  }
  const double c = 1.0 / std::sqrt(1 + t * t), s = t * c, tau = s / (1 + c);
  a[p][p] -= t * apq;
  a[q][q] += t * apq;
  a[p][q] = a[q][p] = 0;
  const int r = 3 - p - q;
  const double arp = a[r][p], arq = a[r][q];
  a[r][p] = a[p][r] = arp - s * (arq + tau * arp);
  a[r][q] = a[q][r] = arq + s * (arp - tau * arq);
  for (int k = 0; k < 3; ++k) {
    const double vp = v[k][p], vq = v[k][q];
    v[k][p] = vp - s * (vq + tau * vp);
    v[k][q] = vq + s * (vp - tau * vq);
  }
}

// Principal values of a symmetric Voigt tensor, descending (ties keep coordinate order), and unit
// vectors n[i] signed so that their largest-magnitude component is positive: a fixed sequence of
// operations, hence bitwise reproducible.
void principal(const double t[6], double val[3], double n[3][3])
{
  double a[3][3] = {{t[0], t[3], t[5]}, {t[3], t[1], t[4]}, {t[5], t[4], t[2]}};
  double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  // Quadratic convergence: a handful of sweeps reach exact zeros; 50 is only a safety net.
  for (int sweep = 0; sweep < 50; ++sweep) {
    if (a[0][1] == 0 && a[0][2] == 0 && a[1][2] == 0) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q)
        if (a[p][q] != 0) jacobi_rotate(a, v, p, q);
  }
  int idx[3] = {0, 1, 2};
  for (int i = 1; i < 3; ++i) // stable insertion sort, descending
    for (int j = i; j > 0 && a[idx[j]][idx[j]] > a[idx[j - 1]][idx[j - 1]]; --j)
      std::swap(idx[j], idx[j - 1]);
  for (int i = 0; i < 3; ++i) {
    val[i] = a[idx[i]][idx[i]];
    int big = 0;
    for (int k = 1; k < 3; ++k)
      if (std::fabs(v[k][idx[i]]) > std::fabs(v[big][idx[i]])) big = k;
    const double sign = v[big][idx[i]] < 0 ? -1.0 : 1.0;
    for (int k = 0; k < 3; ++k)
      n[i][k] = sign * v[k][idx[i]];
  }
}

// Extent of the element across direction n; 0 for a missing element (treated as degenerate).
double band_width(const double n[3], const double* X, int nnodes)
{
  if (X == nullptr || nnodes <= 0) return 0;
  double lo = 0, hi = 0;
  for (int a = 0; a < nnodes; ++a) {
    const double x = n[0] * X[3 * a] + n[1] * X[3 * a + 1] + n[2] * X[3 * a + 2];
    if (a == 0 || x < lo) lo = x;
    if (a == 0 || x > hi) hi = x;
  }
  return hi - lo;
}

// Bilinear law in kappa: the strains at the kink and at the end for band width h > 0.
struct BilinearStrains {
  double k1, kc;
};
BilinearStrains bilinear_strains(const RankineParams& p, double h)
{
  const double w = p.gf / p.ft; // the unit of the openings
  return {kBilinearKinkStress * p.ft / p.E + kBilinearKinkOpening * w / h,
          kBilinearFinalOpening * w / h};
}

double bilinear_stress(const RankineParams& p, double kappa, double h)
{
  const double k0 = p.ft / p.E;
  const BilinearStrains b = bilinear_strains(p, h);
  if (!(b.k1 > k0) || kappa >= b.kc) return 0;
  if (kappa <= b.k1) return p.ft * (1 - (1 - kBilinearKinkStress) * (kappa - k0) / (b.k1 - k0));
  return kBilinearKinkStress * p.ft * (b.kc - kappa) / (b.kc - b.k1);
}

// Stress f(kappa) still carried across the crack, kappa > kappa0. No softening branch (h <= 0 or
// snap-back) means the limit of the law: a vertical drop to zero.
double softening_stress(const RankineParams& p, double kappa, double h)
{
  const double k0 = p.ft / p.E;
  if (!(h > 0)) return 0;
  switch (p.softening) {
  case Softening::Linear: {
    const double kf = 2 * p.gf / (p.ft * h);
    if (!(kf > k0) || kappa >= kf) return 0;
    return p.ft * std::max(0.0, 1 - (kappa - k0) / (kf - k0));
  }
  case Softening::Exponential: {
    const double ke = p.gf / (h * p.ft) - 0.5 * k0;
    if (!(ke > 0)) return 0;
    return p.ft * std::exp(-(kappa - k0) / ke);
  }
  case Softening::Bilinear:
    return bilinear_stress(p, kappa, h);
  }
  return 0;
}

// Updates kappa, h (at onset) and d from the major principal trial stress s1 along n1.
void update_damage(const RankineParams& p, double s1, const double n1[3], const double* X,
                   int nnodes, double* st)
{
  const double k0 = p.ft / p.E;
  const double kappa_old = st[kKappa];
  const double kappa = std::max(kappa_old, s1 / p.E);
  st[kKappa] = kappa;
  if (!(kappa > k0)) return;
  if (!(kappa_old > k0)) st[kBand] = band_width(n1, X, nnodes); // onset: fix h once
  const double d = 1 - softening_stress(p, kappa, st[kBand]) / (p.E * kappa);
  st[kDamage] = std::max(st[kDamage], std::min(1.0, std::max(0.0, d)));
}

// Tensile part of the stress, sigma+ = d psi+ / d eps = lambda <tr eps>+ I + 2 mu eps+ (Miehe's
// spectral strain split; e: engineering shear). The principal strains are taken along n, the trial
// stress's principal directions: isotropic elasticity (mu > 0) makes them the strain's as well,
// so no second eigen-solve is needed. In the plane modes one n is e_z, with strain 0 there.
void tensile_part(double lam, double mu, const double e[6], const double n[3][3], double sp[6])
{
  const double tr = std::max(0.0, e[0] + e[1] + e[2]);
  for (int k = 0; k < 3; ++k)
    sp[k] = lam * tr;
  for (int k = 3; k < 6; ++k)
    sp[k] = 0;
  for (int i = 0; i < 3; ++i) {
    const double* v = n[i];
    const double ei = v[0] * v[0] * e[0] + v[1] * v[1] * e[1] + v[2] * v[2] * e[2] +
                      v[0] * v[1] * e[3] + v[1] * v[2] * e[4] + v[2] * v[0] * e[5];
    if (!(ei > 0)) continue;
    const double c = 2 * mu * ei;
    sp[0] += c * v[0] * v[0];
    sp[1] += c * v[1] * v[1];
    sp[2] += c * v[2] * v[2];
    sp[3] += c * v[0] * v[1];
    sp[4] += c * v[1] * v[2];
    sp[5] += c * v[2] * v[0];
  }
}

} // namespace

double rankine_stress(const RankineParams& p, StressMode mode, const double eps_in[6],
                      const double* elem_X, int nnodes, double* state, double sigma[6])
{
  double eps[6], str[6], s[3], n[3][3];
  effective_strain(mode, eps_in, eps);
  trial_stress(p, mode, eps, str);
  // Virgin point whose largest principal stress cannot reach f_t (Gershgorin bound): elastic,
  // no eigen-solve (most points of a body, most of the time).
  const double s1_bound = std::max({str[0] + std::fabs(str[3]) + std::fabs(str[5]),
                                    str[1] + std::fabs(str[3]) + std::fabs(str[4]),
                                    str[2] + std::fabs(str[5]) + std::fabs(str[4])});
  if (state[kDamage] == 0 && s1_bound < p.ft && !(state[kKappa] > p.ft / p.E)) {
    std::copy(str, str + 6, sigma);
    std::copy(eps, eps + 6, state + kEpsPrev);
    std::copy(sigma, sigma + 6, state + kSigPrev);
    return 0.5 * voigt_dot(sigma, eps);
  }
  principal(str, s, n);
  const double d_old = state[kDamage];
  update_damage(p, s[0], n[0], elem_X, nnodes, state);
  const double d = state[kDamage];
  for (int k = 0; k < 6; ++k)
    sigma[k] = str[k];
  if (d > 0) {
    // sigma = (1 - d) sigma+ + sigma- = sigma_tr - d sigma+: the derivative of psi at fixed d.
    double lam, mu, sp[6];
    lame(p, mode, lam, mu);
    tensile_part(lam, mu, eps, n, sp);
    for (int k = 0; k < 6; ++k)
      sigma[k] -= d * sp[k];
    if (s[0] > 0) std::copy(n[0], n[0] + 3, state + kNormal);
    if (mode == StressMode::PlaneStress) sigma[2] = 0; // exact zeros, not round-off
    if (mode != StressMode::Solid) sigma[4] = sigma[5] = 0;
    // Dissipation psi+ dd, psi+ by 0.5 sigma+(eps) : eps_prev (second order, see rankine.h).
    // A step so large that eps_prev lies on the compressive side of sigma+ gives no sign: the
    // rate psi+ dd/dt is never negative, so neither is the increment.
    const double dd = d - d_old;
    if (dd > 0) state[kDissipated] += std::max(0.0, 0.5 * dd * voigt_dot(sp, state + kEpsPrev));
  }
  std::copy(eps, eps + 6, state + kEpsPrev);
  std::copy(sigma, sigma + 6, state + kSigPrev);
  return 0.5 * voigt_dot(sigma, eps);
}

double rankine_held_stress(const RankineParams& p, StressMode mode, const double eps_in[6],
                           double* state, double sigma[6], bool* overstressed)
{
  double eps[6], str[6];
  effective_strain(mode, eps_in, eps);
  trial_stress(p, mode, eps, str);
  const double s1_bound = std::max({str[0] + std::fabs(str[3]) + std::fabs(str[5]),
                                    str[1] + std::fabs(str[3]) + std::fabs(str[4]),
                                    str[2] + std::fabs(str[5]) + std::fabs(str[4])});
  *overstressed = false;
  if (s1_bound >= p.ft) {
    double s[3], n[3][3];
    principal(str, s, n);
    *overstressed = s[0] >= p.ft;
  }
  std::copy(str, str + 6, sigma);
  std::copy(eps, eps + 6, state + kEpsPrev);
  std::copy(sigma, sigma + 6, state + kSigPrev);
  return 0.5 * voigt_dot(sigma, eps);
}

double rankine_damage(const double* state)
{
  return state[kDamage];
}
double rankine_dissipated(const double* state)
{
  return state[kDissipated];
}
const double* rankine_crack_normal(const double* state)
{
  return state + kNormal;
}
double rankine_band_width(const double* state)
{
  return state[kBand];
}

bool rankine_cracked(const RankineParams& p, const double* state)
{
  const double kappa = state[kKappa], h = state[kBand];
  const double k0 = p.ft / p.E;
  if (!(kappa > k0)) return false;
  switch (p.softening) {
  case Softening::Linear: {
    if (!(h > 0)) return true;
    const double kf = 2 * p.gf / (p.ft * h);
    return !(kf > k0) || kappa >= kf;
  }
  case Softening::Bilinear: {
    if (!(h > 0)) return true;
    const BilinearStrains b = bilinear_strains(p, h);
    return !(b.k1 > k0) || kappa >= b.kc;
  }
  case Softening::Exponential:
    break;
  }
  return softening_stress(p, kappa, h) <= 0.01 * p.ft;
}

bool rankine_softening(const RankineParams& p, StressMode mode, const double* state)
{
  if (!(state[kDamage] > 0) || rankine_cracked(p, state)) return false;
  // The same trial stress and eigen-solve as the last update, so a point that was loading
  // compares equal to its kappa bit for bit.
  double str[6], s[3], n[3][3];
  trial_stress(p, mode, state + kEpsPrev, str);
  principal(str, s, n);
  return s[0] / p.E >= state[kKappa];
}

double rankine_snapback_factor(Softening law)
{
  // h < E / k for the steepest slope -k of sigma(w): ft / wc with wc = 2 gf / ft (linear; the
  // exponential law in kappa loses its branch at the same h), the first branch of the bilinear.
  if (law == Softening::Bilinear) return kBilinearKinkOpening / (1 - kBilinearKinkStress);
  return 2;
}

double rankine_snapback_length(const RankineParams& p)
{
  return rankine_snapback_factor(p.softening) * p.E * p.gf / (p.ft * p.ft);
}

double rankine_softening_stress(const RankineParams& p, double kappa, double h)
{
  return kappa > p.ft / p.E ? softening_stress(p, kappa, h) : p.ft;
}

const std::vector<SofteningLawInfo>& softening_laws()
{
  static const std::vector<SofteningLawInfo> table = {
      {"linear", Softening::Linear},
      {"exponential", Softening::Exponential},
      {"bilinear", Softening::Bilinear},
  };
  return table;
}

const SofteningLawInfo* find_softening_law(const std::string& keyword)
{
  for (const SofteningLawInfo& s : softening_laws())
    if (keyword == s.keyword) return &s;
  return nullptr;
}

const char* softening_keyword(Softening law)
{
  for (const SofteningLawInfo& s : softening_laws())
    if (s.law == law) return s.keyword;
  return "?";
}

std::string softening_law_choices()
{
  const std::vector<SofteningLawInfo>& t = softening_laws();
  std::string out;
  for (std::size_t i = 0; i < t.size(); ++i)
    out += std::string(i == 0 ? "" : i + 1 == t.size() ? " or " : ", ") + t[i].keyword;
  return out;
}

void rankine_check(const RankineParams& p)
{
  auto fail = [](const char* what, double v) {
    throw std::invalid_argument(std::string("Rankine material: parameter ") + what + " (got " +
                                std::to_string(v) + ")");
  };
  // Negated comparisons so that NaN fails as well.
  if (!(p.E > 0)) fail("E must be > 0", p.E);
  if (!(p.nu > -1 && p.nu < 0.5)) fail("nu must lie in (-1, 0.5)", p.nu);
  if (!(p.ft > 0)) fail("ft (tensile strength) must be > 0", p.ft);
  if (!(p.gf > 0)) fail("gf (fracture energy) must be > 0", p.gf);
}

} // namespace fracdem
