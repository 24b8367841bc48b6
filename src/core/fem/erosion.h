// Element erosion: the criteria of `fix fem/body ... erosion` and the choice of the elements that
// meet them (Body::erode removes them and keeps the accounts).
#pragma once

#include <string>
#include <vector>

#include "materials/material.h"

namespace fracdem
{

class Body;

// A criterion is off at 0. An element leaves when it meets any criterion that is on.
struct ErosionCriteria {
  double plastic_strain = 0; // element mean of the equivalent plastic strain >= this
  double damage = 0;         // element failure measure (Rankine damage, 1: no tension) >= this
  double min_dt = 0;         // the element's own stable time step < this
  bool remove_mass = false;  // erosion_mass remove: the element's mass leaves with it
  bool on() const { return plastic_strain > 0 || damage > 0 || min_dt > 0; }
};

// Why an element left; Inverted: det F <= 0 (any erosion criterion on turns this into erosion).
enum class ErosionCause { PlasticStrain = 0, Damage, MinDt, Inverted };
constexpr int kErosionCauses = 4;
const char* erosion_cause_name(ErosionCause cause);

// "" or why the criteria cannot be used with this material (the message names the keyword): a
// value out of range, or a criterion that could never trigger (plastic_strain without a plastic
// material, damage without a damaging one), or a rigid body.
std::string erosion_setup_error(const ErosionCriteria& c, const Material& material, bool rigid);

// The body's active elements that meet a criterion of c, ascending, and for each the first
// criterion met (in the order plastic_strain, damage, min_dt). Reads the state of the last force
// evaluation and the current positions; every replica chooses the same elements.
void select_eroding(const Body& body, const ErosionCriteria& c, std::vector<int>& elems,
                    std::vector<ErosionCause>& causes);

// Mean equivalent plastic strain of element e over its integration points (0 for non-plastic
// materials).
double element_plastic_strain(const Body& body, int e);

// The body's stable time step once the elements below c.min_dt have left (they do at the next
// force evaluation); the plain stable step when min_dt is off.
double stable_time_step_after_erosion(const Body& body, const ErosionCriteria& c);

} // namespace fracdem
