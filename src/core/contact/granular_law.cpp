// Hertz/Hooke normal laws with Coulomb-limited tangential springs, matching LIGGGHTS 3.8 walls,
// and LAMMPS's pair granular hooke|hertz with a given stiffness.
#include "contact/granular_law.h"

#include <cmath>

namespace fracdem
{

double tsuji_damping(double cor)
{
  const double p[] = {1.2728, -4.2783, 11.087, -22.348, 27.467, -18.022, 4.8218};
  double d = 0, c = 1;
  for (double a : p) {
    d += a * c;
    c *= cor;
  }
  return d;
}

ContactMaterial given_stiffness_law(NormalModel m, double kn, double damp, DampingModel d,
                                    double kt, bool kt_times_a, double xt, double mu, bool history)
{
  ContactMaterial c;
  c.model = m;
  c.coeffFric = mu;
  c.tangential_history = history;
  GivenStiffness& g = c.given;
  g.on = true;
  g.kn = kn;
  g.damping = d;
  g.kt = kt;
  g.kt_times_a = kt_times_a;
  g.xt = xt;
  g.c = damp;
  // Hertz's equivalent modulus (F_ne = 4/3 E* a delta), for the time-resolution check.
  if (m == NormalModel::Hertz) c.Yeff = 0.75 * kn;
  if (d == DampingModel::Tsuji) g.c = tsuji_damping(damp);
  if (d == DampingModel::CoeffRestitution) {
    // The damped oscillator's restitution: exact for Hooke's linear spring; for Hertz the
    // coefficient of Tsuji et al. 1992 (sqrt(3/2) 2 sqrt(5/6) = sqrt(5)), as LAMMPS writes it.
    const double le = std::log(damp), root = std::sqrt(M_PI * M_PI + le * le);
    g.c = m == NormalModel::Hooke ? -2 * le / root : -std::sqrt(5.0) * le / root;
  }
  return c;
}

namespace
{

// The given-stiffness law's coefficients at overlap delta, contact radius a (F_ne / delta = kn).
void given_coefficients(const GivenStiffness& g, NormalModel model, double delta, double a,
                        double m, double& kn, double& kt, double& gamman, double& gammat)
{
  kn = model == NormalModel::Hooke ? g.kn : g.kn * a;
  switch (g.damping) {
  case DampingModel::None:
    gamman = 0;
    break;
  case DampingModel::Velocity:
    gamman = g.c;
    break;
  case DampingModel::MassVelocity:
    gamman = g.c * m;
    break;
  case DampingModel::Viscoelastic:
    gamman = g.c * m * a;
    break;
  default:
    gamman = g.c * std::sqrt(m * (kn * delta) / delta); // LAMMPS: sqrt(m F_ne / delta)
  }
  kt = g.kt_times_a ? g.kt * a : g.kt;
  gammat = g.xt * gamman;
}

// LAMMPS's linear_history / mindlin spring (gran_sub_mod_tangential.cpp): the history turns into
// the tangent plane keeping its length, grows by vtr dt; spring plus damping is capped at the
// Coulomb force Fscrit, and a sliding contact keeps the spring that gives the capped force with
// the damping in it.
void lammps_history_force(double kt, double gammat, double Fscrit, const double n[3],
                          const double vtr[3], double dt, double shear[3], double Ft[3])
{
  const double rsht = shear[0] * n[0] + shear[1] * n[1] + shear[2] * n[2];
  if (std::fabs(rsht) * kt > 1e-10 * Fscrit) {
    const double len = std::sqrt(shear[0] * shear[0] + shear[1] * shear[1] + shear[2] * shear[2]);
    for (int d = 0; d < 3; ++d)
      shear[d] -= rsht * n[d];
    const double proj = std::sqrt(shear[0] * shear[0] + shear[1] * shear[1] + shear[2] * shear[2]);
    const double scale = proj > 0 ? len / proj : 0.0;
    for (int d = 0; d < 3; ++d)
      shear[d] *= scale;
  }
  for (int d = 0; d < 3; ++d) {
    shear[d] += dt * vtr[d];
    Ft[d] = -kt * shear[d] - gammat * vtr[d];
  }
  const double mag = std::sqrt(Ft[0] * Ft[0] + Ft[1] * Ft[1] + Ft[2] * Ft[2]);
  if (mag <= Fscrit) return;
  const double shrmag = std::sqrt(shear[0] * shear[0] + shear[1] * shear[1] + shear[2] * shear[2]);
  for (int d = 0; d < 3; ++d) {
    Ft[d] = shrmag != 0.0 ? Ft[d] * (Fscrit / mag) : 0.0;
    if (shrmag != 0.0) shear[d] = -(Ft[d] + gammat * vtr[d]) / kt;
  }
}

} // namespace

ContactMaterial mix_materials(double E1, double nu1, double E2, double nu2, double e, double mu,
                              double char_vel, NormalModel m, bool history)
{
  ContactMaterial c;
  const double cy2 = E2 > 0 ? (1 - nu2 * nu2) / E2 : 0.0;
  const double cg2 = E2 > 0 ? 2 * (2 - nu2) * (1 + nu2) / E2 : 0.0;
  c.Yeff = 1.0 / ((1 - nu1 * nu1) / E1 + cy2);
  c.Geff = 1.0 / (2 * (2 - nu1) * (1 + nu1) / E1 + cg2);
  c.coeffRest = e;
  c.coeffFric = mu;
  c.charVel = char_vel;
  const double le = std::log(e);
  c.betaeff = le / std::sqrt(le * le + M_PI * M_PI);
  c.model = m;
  c.tangential_history = history;
  return c;
}

ContactOutput particle_surface_force(const ContactMaterial& mat, const ContactInput& in,
                                     double shear[3])
{
  const double* en = in.n;
  const double reff = in.radius, meff = in.mass; // wall: particle radius and mass
  const double deltan = in.delta;
  const double sqrtval = in.contact_radius > 0 ? in.contact_radius : std::sqrt(reff * deltan);
  double kn, kt, gamman, gammat;
  if (mat.given.on) {
    given_coefficients(mat.given, mat.model, deltan, sqrtval, meff, kn, kt, gamman, gammat);
  } else if (mat.model == NormalModel::Hertz) {
    const double Sn = 2 * mat.Yeff * sqrtval, St = 8 * mat.Geff * sqrtval;
    kn = 4.0 / 3.0 * mat.Yeff * sqrtval;
    kt = St;
    const double s56 = 0.91287092917527685576; // sqrt(5/6)
    gamman = -2 * s56 * mat.betaeff * std::sqrt(Sn * meff);
    gammat = -2 * s56 * mat.betaeff * std::sqrt(St * meff); // tangential_damping on (default)
  } else {
    kn = 16.0 / 15.0 * sqrtval * mat.Yeff *
         std::pow(15.0 * meff * mat.charVel * mat.charVel / (16.0 * sqrtval * mat.Yeff), 0.2);
    kt = kn;
    const double le = std::log(mat.coeffRest), le2 = le * le;
    gamman = std::sqrt(4 * meff * kn * le2 / (le2 + M_PI * M_PI));
    gammat = gamman;
  }

  const double* vr = in.v_rel;
  const double vn = vr[0] * en[0] + vr[1] * en[1] + vr[2] * en[2];
  const double vt[3] = {vr[0] - vn * en[0], vr[1] - vn * en[1], vr[2] - vn * en[2]};
  // LIGGGHTS puts the contact point at r - delta/2; LAMMPS's walls at r (fix wall/gran).
  const double cr = mat.given.on ? in.radius : in.radius - 0.5 * deltan;
  // relative tangential velocity of the contact points: vt - cr * (omega x n)
  const double w[3] = {cr * in.omega[0], cr * in.omega[1], cr * in.omega[2]};
  const double vtr[3] = {vt[0] - (w[1] * en[2] - w[2] * en[1]),
                         vt[1] - (w[2] * en[0] - w[0] * en[2]),
                         vt[2] - (w[0] * en[1] - w[1] * en[0])};

  const double Fn = kn * deltan - gamman * vn; // limitForce off (LIGGGHTS default)

  double Ft[3];
  if (mat.given.on && mat.tangential_history) {
    lammps_history_force(kt, gammat, mat.coeffFric * std::fabs(Fn), en, vtr, in.dt, shear, Ft);
  } else if (mat.tangential_history) {
    for (int d = 0; d < 3; ++d)
      shear[d] += vtr[d] * in.dt;
    const double rsht = shear[0] * en[0] + shear[1] * en[1] + shear[2] * en[2];
    for (int d = 0; d < 3; ++d)
      shear[d] -= rsht * en[d];
    const double shrmag =
        std::sqrt(shear[0] * shear[0] + shear[1] * shear[1] + shear[2] * shear[2]);
    for (int d = 0; d < 3; ++d)
      Ft[d] = -kt * shear[d];
    const double Ft_shear = kt * shrmag, Ft_friction = mat.coeffFric * std::fabs(Fn);
    if (Ft_shear > Ft_friction) {
      if (shrmag != 0.0) {
        const double ratio = Ft_friction / Ft_shear;
        for (int d = 0; d < 3; ++d) {
          Ft[d] *= ratio;
          shear[d] = -Ft[d] / kt;
        }
      } else {
        Ft[0] = Ft[1] = Ft[2] = 0;
      }
    } else {
      for (int d = 0; d < 3; ++d)
        Ft[d] -= gammat * vtr[d];
    }
  } else {
    // tangential no_history: viscous friction capped by Coulomb (LIGGGHTS no_history model)
    const double vrel = std::sqrt(vtr[0] * vtr[0] + vtr[1] * vtr[1] + vtr[2] * vtr[2]);
    const double Ft_damp = gammat * vrel, Ft_fric = mat.coeffFric * std::fabs(Fn);
    const double Ftm = std::fmin(Ft_damp, Ft_fric);
    for (int d = 0; d < 3; ++d)
      Ft[d] = vrel > 0 ? -Ftm * vtr[d] / vrel : 0.0;
  }

  ContactOutput out;
  for (int d = 0; d < 3; ++d)
    out.force[d] = Fn * en[d] + Ft[d];
  const double tor[3] = {en[1] * Ft[2] - en[2] * Ft[1], en[2] * Ft[0] - en[0] * Ft[2],
                         en[0] * Ft[1] - en[1] * Ft[0]};
  for (int d = 0; d < 3; ++d)
    out.torque[d] = -cr * tor[d];
  out.fn = Fn;
  return out;
}

HertzImpact hertz_impact(double Estar, double R, double m, double v)
{
  HertzImpact h;
  h.max_overlap = std::pow(15.0 * m * v * v / (16.0 * Estar * std::sqrt(R)), 0.4);
  h.peak_force = 4.0 / 3.0 * Estar * std::sqrt(R) * std::pow(h.max_overlap, 1.5);
  h.duration = 2.868 * std::pow(m * m / (R * Estar * Estar * v), 0.2);
  return h;
}

} // namespace fracdem
