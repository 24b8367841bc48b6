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

} // namespace fracdem
