// Rankine rotating-crack material point with crack-band (fracture-energy) regularised softening.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace fracdem
{

// Model (small strain, isotropic, one integration point at a time; no host types involved):
//
//  * Trial stress sigma_tr = C : eps with lambda = E nu / ((1+nu)(1-2nu)), mu = E / (2(1+nu)).
//  * Principal decomposition sigma_tr = sum_i s_i n_i n_i^T, s_1 >= s_2 >= s_3, by cyclic Jacobi
//    to machine precision (deterministic: the same input gives the same bits). Ties keep the
//    coordinate order; each n_i is signed so that its largest-magnitude component is positive.
//    C is isotropic, so the n_i are the principal directions of the strain as well.
//  * Equivalent strain kappa = max over history of s_1 / E (never decreases; below f_t / E,
//    where a Gershgorin bound already proves s_1 < f_t, it is not updated). kappa0 = ft / E.
//  * Softening curve f(kappa), the stress still carried across the crack for kappa > kappa0:
//      Linear     : f = ft (1 - (kappa - kappa0) / (kappa_f - kappa0)), kappa_f = 2 gf / (ft h),
//                   f = 0 for kappa >= kappa_f;
//      Exponential: f = ft exp(-(kappa - kappa0) / kappa_e), kappa_e = gf / (h ft) - kappa0 / 2.
//      Bilinear   : Petersson (1981) in crack-band form. The law in the crack opening w is
//                   sigma(w) linear from ft at w = 0 to ft / 3 at w1 = 0.8 gf / ft, then linear
//                   to 0 at wc = 3.6 gf / ft (area gf). With w = h (kappa - f / E), the
//                   opening of a band of width h, f is piecewise linear in kappa through
//                   (kappa0, ft), (kappa_1, ft / 3) and (kappa_c, 0):
//                   kappa_1 = kappa0 / 3 + w1 / h, kappa_c = wc / h; f = 0 for kappa >= kappa_c.
//    All three dissipate exactly gf / h per unit volume in uniaxial tension (nu = 0) taken to
//    complete failure, so the energy per unit crack area is gf whatever the element size (crack
//    band). Linear in kappa is linear in w as well (w1 = wc = 2 gf / ft).
//  * h (crack-band width) is fixed once, at onset (first call with kappa > kappa0), as the extent
//    of the element across the major principal direction n_1 at that moment:
//      h = max_a (n_1 . X_a) - min_a (n_1 . X_a)   over the element's reference nodes X_a.
//  * Damage d = 1 - f(kappa) / (E kappa), clamped to [0, 1], never decreasing.
//  * Stress: Miehe's spectral strain split, a rotating crack derived from a potential. With the
//    principal strains eps_i (tensor strain) along n_i, eps+ = sum <eps_i>+ n_i n_i^T and
//    eps- = eps - eps+,
//      psi(eps, d) = (1 - d) psi+ + psi-,  psi+ = lambda/2 <tr eps>+^2 + mu sum_i <eps_i>+^2,
//                                          psi- = lambda/2 <tr eps>-^2 + mu sum_i <eps_i>-^2,
//      sigma = d psi / d eps = (1 - d) sigma+ + sigma-,  sigma+ = lambda <tr eps>+ I + 2 mu eps+,
//    computed as sigma_tr - d sigma+ (sigma_tr = sigma+ + sigma-). Tensile strain is degraded
//    along its current directions (the crack rotates); compression, all eps_i <= 0, crosses a
//    crack elastically. Unloading at fixed d is secant: psi+ and psi- are homogeneous of degree
//    2, so 0.5 sigma : eps = psi. While d = 0 the trial stress is returned as it is (bit for bit).
//    Why a potential: at fixed d the law is hyperelastic, so no closed strain loop gains or loses
//    work. The earlier law (every tensile principal STRESS scaled by 1 - d) has a non-symmetric
//    tangent for nu != 0; strain loops at fixed d returned up to ~16 % more work than they took,
//    and fragments rattling in contact drove such loops without bound.
//    With nu = 0 (lambda = 0) both laws coincide; uniaxial tension gives sigma = (1 - d) E eps.
//    A difference for nu > 0: the lateral (tensile) strains of uniaxial compression are degraded
//    too, so a failed point (d = 1) under uniaxial compressive stress expands sideways freely and
//    has the modulus 2 mu = E / (1 + nu) instead of E.
//  * Dissipated energy density D = integral of psi+ dd, the release rate -d psi / d d = psi+ >= 0
//    times d's growth: each call with d growing adds 0.5 (d - d_prev) sigma+(eps) : eps_prev, a
//    second-order quadrature of psi+ over the step (clamped at 0 for a step so large that eps_prev
//    lies on the compressive side of sigma+). D never decreases, and calls at fixed d add exactly
//    nothing. work = psi + D holds to the accuracy of the caller's quadrature of the work: on the
//    piecewise quadratic psi a trapezoidal sum of sigma : d eps has its own O(step^2) error where
//    the strain path bends or a principal strain changes sign. (The earlier bookkeeping,
//    D += 0.5 (sigma_prev : eps - sigma : eps_prev), is this increment plus exactly that error,
//    so it went down, e.g., by 0.5 d E |eps_prev eps| whenever a step reopened a crack.)
//
// Stress modes (the 3x3 strain/stress in Voigt order xx, yy, zz, xy, yz, zx):
//   Solid        : full 3D.
//   PlaneStrain  : eps_zz = 0 and yz = zx = 0 are enforced (whatever the input holds there);
//                  sigma_zz = lambda (eps_xx + eps_yy) follows and enters the principal stresses.
//                  The split is the 3D one with eps_zz = 0 as a principal strain of its own.
//   PlaneStress  : in-plane stress from lambda* = 2 lambda mu / (lambda + 2 mu) and mu; eps_zz is
//                  ignored, sigma_zz = sigma_yz = sigma_zx = 0 are returned. The split is that of
//                  the condensed 2D energy lambda*/2 (tr eps)^2 + mu sum eps_i^2 over the two
//                  in-plane principal strains (lambda* in psi+- and sigma+-).
//   Axisymmetric : the zz slot is the hoop component (a principal direction and principal
//                  strain of its own); yz = zx = 0 are enforced.
//
// Limits the caller must respect (the kernel does not check them, it runs per point per step):
//  * Validate the parameters once with rankine_check.
//  * Snap-back: for h >= rankine_snapback_length(p) no softening branch exists: the steepest
//    slope of sigma(w), -k, needs h < E / k. Linear and exponential: 2 E gf / ft^2
//    (kappa_f <= kappa0, kappa_e <= 0); bilinear: its first branch, k = (2/3) ft / w1, gives
//    1.2 E gf / ft^2 (kappa_1 <= kappa0). Set-up must refuse such elements, e.g. every element
//    whose largest node-to-node extent (a bound on h for any direction) reaches that length. If
//    one gets through anyway, the kernel takes the limit of the law as h -> snap-back length
//    (a vertical drop: d = 1 at onset), which dissipates ft^2 / (2E) > gf / h; it never
//    produces NaN or hardening.
//  * h <= 0 at onset (all nodes on a plane normal to n_1, or elem_X == nullptr / nnodes <= 0) is
//    a programming error: the point fails at once (d = 1), again without NaN.
//
// State layout (kRankineStateSize doubles; all zeros = virgin material):
//   [0]      kappa   largest equivalent strain reached
//   [1]      h       crack-band width, fixed at onset (0 before)
//   [2]      d       damage
//   [3..5]   n       crack normal: major principal direction, updated on every call with d > 0
//                    and s_1 > 0 (kept as it was while no principal stress is tensile); 0 before
//   [6]      D       dissipated energy per unit volume
//   [7..12]  eps_prev  strain of the previous call, as used (after the mode's constraints)
//   [13..18] sig_prev  stress of the previous call (written for the layout's sake; the kernel no
//                      longer reads it)
//   [19]     reserved (stays 0)

enum class Softening : std::uint8_t { Linear, Exponential, Bilinear };
// The softening laws by keyword (`material rankine ... softening KEYWORD`), the one table the
// parser and the messages read.
struct SofteningLawInfo {
  const char* keyword;
  Softening law;
};
const std::vector<SofteningLawInfo>& softening_laws();
const SofteningLawInfo* find_softening_law(const std::string& keyword); // nullptr: unknown
const char* softening_keyword(Softening law);
std::string softening_law_choices(); // "linear, exponential or bilinear"
// Petersson's bilinear law: kink stress / ft, kink opening and final opening in units of gf / ft.
constexpr double kBilinearKinkStress = 1.0 / 3.0;
constexpr double kBilinearKinkOpening = 0.8;
constexpr double kBilinearFinalOpening = 3.6;
// How the 3x3 strain/stress is read: see the model notes above.
enum class StressMode : std::uint8_t { Solid, PlaneStrain, PlaneStress, Axisymmetric };

struct RankineParams {
  double E = 0, nu = 0;  // isotropic elastic constants
  double ft = 0, gf = 0; // tensile strength, fracture energy per unit crack area
  Softening softening = Softening::Linear;
};

constexpr int kRankineStateSize = 20;

// Stress update. eps: small strain, Voigt with ENGINEERING shear (gamma). elem_X, nnodes: the
// element's reference node coordinates (3 per node), read only on the call that reaches onset.
// state: kRankineStateSize doubles, updated in place. sigma: Cauchy stress, Voigt (out).
// Returns the recoverable (secant) strain energy density 0.5 sigma : eps.
double rankine_stress(const RankineParams& p, StressMode mode, const double eps[6],
                      const double* elem_X, int nnodes, double* state, double sigma[6]);

// The same point held elastic (crack tracking: the element is outside every tracked band, so it
// may not soften): the trial stress, kappa and d untouched, the previous strain and stress
// recorded as rankine_stress does. For an undamaged point only (d = 0). overstressed (out): its
// largest principal stress reached ft (the tracker's nucleation candidates).
double rankine_held_stress(const RankineParams& p, StressMode mode, const double eps[6],
                           double* state, double sigma[6], bool* overstressed);

double rankine_damage(const double* state);              // d in [0, 1]
double rankine_dissipated(const double* state);          // dissipated energy per unit volume
const double* rankine_crack_normal(const double* state); // unit vector, zeros before onset
double rankine_band_width(const double* state);          // h, 0 before onset
// True once the point carries no more tension: linear softening kappa >= kappa_f; bilinear
// kappa >= kappa_c; exponential: remaining strength f(kappa) <= 0.01 ft. Also true for the
// h <= 0 / snap-back failures above.
bool rankine_cracked(const RankineParams& p, const double* state);
// True while the point is on its softening curve: damaged, not yet cracked, and the strain of its
// last update reached its largest equivalent strain (kappa grew or held there). A point below
// that unloads elastically: its damage, and so its dissipation, stay where they are.
bool rankine_softening(const RankineParams& p, StressMode mode, const double* state);
// Largest crack-band width for which the softening law does not snap back: 2 E gf / ft^2
// (linear, exponential), 1.2 E gf / ft^2 (bilinear).
double rankine_snapback_length(const RankineParams& p);
// The same as a multiple of E gf / ft^2 (2 or 1.2), for messages.
double rankine_snapback_factor(Softening law);
// Softening stress f(kappa) of the law for band width h (ft at kappa0, see above); for the
// curve-shape tests and plots. kappa <= kappa0 gives ft.
double rankine_softening_stress(const RankineParams& p, double kappa, double h);
// Throws std::invalid_argument naming the parameter for E <= 0, nu outside (-1, 0.5), ft <= 0,
// gf <= 0 (NaN fails too).
void rankine_check(const RankineParams& p);

} // namespace fracdem
