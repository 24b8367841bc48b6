// The one table of constitutive models: keyword, per-point state size, syntax, argument parsing.
#pragma once

#include <cstddef>
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

// Largest state_per_point of the table (scratch buffers of one element's points).
constexpr int kMaxStatePerPoint =
    kPlasticStateSize > kRankineStateSize ? kPlasticStateSize : kRankineStateSize;

const std::vector<MaterialModelInfo>& material_models();
// nullptr when no model has this keyword.
const MaterialModelInfo* find_material_model(const std::string& keyword);
const MaterialModelInfo& material_model_info(MaterialModel model);
// The named options of a model's arguments, read from its syntax ("strength", "fracture_energy",
// "softening" for rankine): the words a misspelt option is compared with.
std::vector<std::string> material_options(MaterialModel model);

// Reads the words after `material` (words[0] is the model keyword) into mat: model, and the
// model's constants (Rankine strength etc., flow-stress constants); E, nu, rho are not touched.
// Returns "" on success, else an error text naming the keyword and what was expected. With
// `consumed` null every word must belong to the material; otherwise parsing stops at the first
// word that cannot continue it (a host keyword) and *consumed gets the number of words used.
// Sign checks of single constants happen here; material_setup_error checks the whole.
std::string parse_material_arguments(const std::vector<std::string>& words, Material& mat,
                                     std::size_t* consumed = nullptr);
// The same for the words after `eos`: `linear` or `mie_gruneisen C0 S GAMMA0`.
std::string parse_eos_arguments(const std::vector<std::string>& words, Material& mat,
                                std::size_t* consumed = nullptr);
// Set-up check of a complete material for a mesh of dimension dim (E, nu, rho given): "" or the
// reason, naming the keyword. Checks the plastic models and the EOS (plane stress is refused for
// both; `eos mie_gruneisen` needs a plastic model); elastic and Rankine bodies pass (Rankine has
// rankine_check).
std::string material_setup_error(const Material& mat, int dim);

// Failure measure of one integration point (0 intact .. 1 carries no more tension) and, where it
// has failed at all, its failure direction (crack normal) in `normal` (zeros otherwise).
double point_failure(const Material& mat, const double* state, double normal[3]);
// Whether the point has started to fail at all (a cheap test before point_failure).
inline bool point_damaged(const Material& mat, const double* state)
{
  return mat.model == MaterialModel::Rankine && rankine_damage(state) > 0;
}
// Energy dissipated so far per unit volume at one integration point (cracking, plastic work).
double point_dissipation(const Material& mat, const double* state);

} // namespace fracdem
