// The one table of constitutive models.
#include "materials/material_table.h"

namespace fracdem
{

const std::vector<MaterialModelInfo>& material_models()
{
  static const std::vector<MaterialModelInfo> table = {
      {"elastic", MaterialModel::Elastic, 0, false, ""},
      {"rankine", MaterialModel::Rankine, kRankineStateSize, true,
       "strength FT fracture_energy GF [softening linear|exponential]"},
  };
  return table;
}

const MaterialModelInfo* find_material_model(const std::string& keyword)
{
  for (const MaterialModelInfo& m : material_models())
    if (keyword == m.keyword) return &m;
  return nullptr;
}

const MaterialModelInfo& material_model_info(MaterialModel model)
{
  for (const MaterialModelInfo& m : material_models())
    if (m.model == model) return m;
  return material_models().front();
}

double point_failure(const Material& mat, const double* state, double normal[3])
{
  normal[0] = normal[1] = normal[2] = 0;
  if (mat.model != MaterialModel::Rankine) return 0.0;
  const double* n = rankine_crack_normal(state);
  for (int d = 0; d < 3; ++d)
    normal[d] = n[d];
  return rankine_cracked(mat.rankine(), state) ? 1.0 : rankine_damage(state);
}

double point_dissipation(const Material& mat, const double* state)
{
  return mat.model == MaterialModel::Rankine ? rankine_dissipated(state) : 0.0;
}

} // namespace fracdem
