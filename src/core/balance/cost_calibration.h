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
  double particle = 1.0;   // per particle and step: integration, binning, list traversal
  double wall_check = 1.0; // per particle and primitive wall: the gap test
  double pair_check = 1.0;
  double sphere_contact = 1.0;
  double wall_contact = 1.0;
  double facet_check = 1.0;
  double facet_contact = 1.0;
};

// Plain counts: every item costs 1.
InteractionCosts unit_costs();

// Times each kernel on synthetic data (distance check of a neighbour pair, Hertz law with
// tangential history, sphere-plane gap + law, sphere-triangle closest point, triangle closest
// point + law) and returns their cost relative to the pair check. Runs for about
// `seconds_budget` in total; deterministic inputs, so only timer noise varies between machines.
InteractionCosts calibrate_costs(double seconds_budget = 0.05);

} // namespace fracdem::balance

#endif
