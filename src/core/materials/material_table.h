// The one table of constitutive models: keyword, per-point state size, syntax.
#pragma once

#include <string>
#include <vector>

#include "materials/material.h"

namespace fracdem
{

struct MaterialModelInfo {
  const char* keyword; // as written after `material` in fix fem/body
  MaterialModel model;
  int state_per_point; // doubles of history per integration point
  bool fractures;      // drives nodal fracture (a failure map exists)
  const char* syntax;  // arguments after the keyword, for error messages and docs
};

const std::vector<MaterialModelInfo>& material_models();
// nullptr when no model has this keyword.
const MaterialModelInfo* find_material_model(const std::string& keyword);
const MaterialModelInfo& material_model_info(MaterialModel model);

// Failure measure of one integration point (0 intact .. 1 carries no more tension) and, where it
// has failed at all, its failure direction (crack normal) in `normal` (zeros otherwise).
double point_failure(const Material& mat, const double* state, double normal[3]);
// Whether the point has started to fail at all (a cheap test before point_failure).
inline bool point_damaged(const Material& mat, const double* state)
{
  return mat.model == MaterialModel::Rankine && rankine_damage(state) > 0;
}
// Energy dissipated so far per unit volume at one integration point.
double point_dissipation(const Material& mat, const double* state);

} // namespace fracdem
