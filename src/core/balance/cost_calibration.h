// Relative cost of each interaction type, measured by a micro-benchmark on the running machine.
#ifndef FRACDEM_BALANCE_COST_CALIBRATION_H
#define FRACDEM_BALANCE_COST_CALIBRATION_H

namespace fracdem::balance
{

// Work per particle is modelled as a sum over what the step did for it (paper section 5.1): a
// fixed per-particle part, a gap test per primitive wall, potential pairs checked, sphere-sphere
// contacts resolved, primitive-wall contacts, facet checks and facet contacts of deformable bodies.
// Costs are relative to one pair check.
struct InteractionCosts {
  // per particle and step, with or without neighbours: integration, force clearing, gravity,
  // binning and the stencil walk of reneighbouring (a free-flying particle costs this much)
  double particle = 1.0;
  double wall_check = 1.0; // per particle and primitive wall: the gap test
  double pair_check = 1.0;
  double sphere_contact = 1.0;
  double wall_contact = 1.0;
  double facet_check = 1.0;
  double facet_contact = 1.0;
};

// What the last step did for one particle: the terms of the work model.
struct ParticleCounts {
  int walls = 0;           // primitive walls (one gap test each)
  long pair_checks = 0;    // potential pairs in its neighbour list
  int sphere_contacts = 0; // pairs in contact
  int wall_contacts = 0, facet_checks = 0, facet_contacts = 0;
};

// Plain counts: every item costs 1.
InteractionCosts unit_costs();

// Work of one particle in one step: the per-particle term (paid by every particle, neighbours
// or not) plus every check and contact priced by c.
double particle_cost(const InteractionCosts& c, const ParticleCounts& k);

// Times each kernel on synthetic data (distance check of a neighbour pair, Hertz law with
// tangential history, a free particle's step: both halves of nve/sphere, force and torque
// clearing, gravity, and its amortised binning and stencil walk; sphere-plane gap + law,
// sphere-triangle closest point, triangle closest point + law) and returns their cost relative
// to the pair check. Runs for about
// `seconds_budget` in total; deterministic inputs, so only timer noise varies between machines.
InteractionCosts calibrate_costs(double seconds_budget = 0.05);

} // namespace fracdem::balance

#endif
