// Element erosion criteria: validation and the selection of the elements that meet them.
#include "fem/erosion.h"

#include <algorithm>

#include "fem/body.h"
#include "materials/material_table.h"
#include "materials/plasticity.h"

namespace fracdem
{

const char* erosion_cause_name(ErosionCause cause)
{
  switch (cause) {
  case ErosionCause::PlasticStrain:
    return "plastic_strain";
  case ErosionCause::Damage:
    return "damage";
  case ErosionCause::MinDt:
    return "min_dt";
  case ErosionCause::Inverted:
    return "inverted";
  }
  return "?";
}

std::string erosion_setup_error(const ErosionCriteria& c, const Material& material, bool rigid)
{
  if (rigid) return "erosion: a rigid body neither deforms nor loses elements";
  if (c.plastic_strain < 0 || c.damage < 0 || c.min_dt < 0 || !c.on())
    return "erosion: expects one or more of 'plastic_strain EPS' (EPS > 0), 'damage D' (0 < D "
           "<= 1), 'min_dt DT' (DT > 0)";
  if (c.damage > 1) return "erosion damage: D must lie in (0, 1] (1: no tension left)";
  // A criterion that can never trigger is a mistake in the input, not a silent no-op.
  if (c.plastic_strain > 0 && !material.plastic_model())
    return "erosion plastic_strain: this body's material never yields, so the criterion could "
           "never trigger; it needs a plastic material (j2, johnson_cook, zerilli_armstrong)";
  if (c.damage > 0 && !material_model_info(material.model).fractures)
    return "erosion damage: this body's material does not damage, so the criterion could never "
           "trigger; it needs a damaging material (material rankine ...)";
  return "";
}

double element_plastic_strain(const Body& body, int e)
{
  if (!body.material().plastic_model()) return 0.0;
  const FeSpace& space = body.space();
  const Mesh& mesh = body.mesh();
  double sum = 0, weight = 0;
  for (int q = 0; q < points_per_elem(mesh.etype[e]); ++q) {
    const double w = space.point_weight(mesh, e, q);
    sum += w * plastic_equivalent_strain(
                   &body.material_state()[space.state_offset(e) + q * kPlasticStateSize]);
    weight += w;
  }
  return weight > 0 ? sum / weight : 0.0;
}

// The first criterion of c that element e meets, or -1.
static int first_cause(const Body& body, const ErosionCriteria& c, int e)
{
  if (c.plastic_strain > 0 && element_plastic_strain(body, e) >= c.plastic_strain)
    return static_cast<int>(ErosionCause::PlasticStrain);
  double normal[3];
  if (c.damage > 0 && body.element_failure(e, normal) >= c.damage)
    return static_cast<int>(ErosionCause::Damage);
  if (c.min_dt > 0 && body.element_time_step(e) < c.min_dt)
    return static_cast<int>(ErosionCause::MinDt);
  return -1;
}

void select_eroding(const Body& body, const ErosionCriteria& c, std::vector<int>& elems,
                    std::vector<ErosionCause>& causes)
{
  elems.clear();
  causes.clear();
  if (!c.on() || body.rigid()) return;
  const Mesh& mesh = body.mesh();
  for (int e = 0; e < mesh.num_elems(); ++e) {
    if (!mesh.active[e]) continue;
    const int cause = first_cause(body, c, e);
    if (cause < 0) continue;
    elems.push_back(e);
    causes.push_back(static_cast<ErosionCause>(cause));
  }
}

double stable_time_step_after_erosion(const Body& body, const ErosionCriteria& c)
{
  if (c.min_dt <= 0) return body.stable_time_step();
  double dt = 1e300;
  for (int e = 0; e < body.mesh().num_elems(); ++e) {
    const double dte = body.element_time_step(e); // 1e300 when inactive
    if (dte >= c.min_dt) dt = std::min(dt, dte);
  }
  return dt;
}

} // namespace fracdem
