// Hertz/Hooke normal laws with Coulomb-limited tangential springs, matching LIGGGHTS 3.8 walls.
#include "contact/granular_law.h"

#include <cmath>

namespace fracdem
{

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
  if (mat.model == NormalModel::Hertz) {
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
  const double cr = in.radius - 0.5 * deltan;
  // relative tangential velocity of the contact points: vt - cr * (omega x n)
  const double w[3] = {cr * in.omega[0], cr * in.omega[1], cr * in.omega[2]};
  const double vtr[3] = {vt[0] - (w[1] * en[2] - w[2] * en[1]),
                         vt[1] - (w[2] * en[0] - w[0] * en[2]),
                         vt[2] - (w[0] * en[1] - w[1] * en[0])};

  const double Fn = kn * deltan - gamman * vn; // limitForce off (LIGGGHTS default)

  double Ft[3];
  if (mat.tangential_history) {
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
