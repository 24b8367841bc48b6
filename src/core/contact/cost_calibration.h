// Relative cost of each interaction type of the work model, measured by a micro-benchmark of the
// contact kernels on the running machine.
#ifndef FRACDEM_CONTACT_COST_CALIBRATION_H
#define FRACDEM_CONTACT_COST_CALIBRATION_H

#include "balance/cost_model.h"

namespace fracdem
{

// Times each kernel on synthetic data (distance check of a neighbour pair, Hertz law with
// tangential history, a free particle's step: both halves of nve/sphere, force and torque
// clearing, gravity, and its amortised binning and stencil walk; sphere-plane gap + law,
// sphere-triangle closest point, triangle closest point + law, a liquid bridge's forces) and
// returns their cost relative to the pair check. Runs for about `seconds_budget` in total; deterministic inputs, so only
// timer noise varies between machines.
balance::InteractionCosts calibrate_costs(double seconds_budget = 0.05);

} // namespace fracdem

#endif
