// Material of a body: elasticity, the constitutive model from the material table, and the 2D
// formulation choice shared by all element kernels.
#pragma once

#include <cmath>
#include <cstdint>

#include "materials/eos.h"
#include "materials/plasticity.h"
#include "materials/rankine.h"

namespace fracdem
{

enum class Kinematics : std::uint8_t { SmallStrain, Corotational };
// Only for 2D elements. Plane stress: sigma_zz = 0 (thin plates, Brazilian discs).
enum class PlaneMode : std::uint8_t { PlaneStrain, Axisymmetric, PlaneStress };
// Constitutive models of the material table (materials/material_table.h).
enum class MaterialModel : std::uint8_t { Elastic, Rankine, J2, JohnsonCook, ZerilliArmstrong };

struct Material {
  double E = 0, nu = 0, rho = 0;
  Kinematics kinematics = Kinematics::SmallStrain;
  PlaneMode plane = PlaneMode::PlaneStrain;
  double thickness = 1.0; // out-of-plane thickness (plane strain and plane stress)
  MaterialModel model = MaterialModel::Elastic;
  // Rankine rotating crack: tensile strength, fracture energy, softening law.
  double ft = 0, gf = 0;
  Softening softening = Softening::Linear;
  // Plastic models (J2, JohnsonCook, ZerilliArmstrong): flow-stress constants and the equation
  // of state of their pressure (materials/plasticity.h, materials/eos.h).
  PlasticParams plastic;
  EosParams eos;

  bool plastic_model() const
  {
    return model == MaterialModel::J2 || model == MaterialModel::JohnsonCook ||
           model == MaterialModel::ZerilliArmstrong;
  }
  double lambda() const { return E * nu / ((1 + nu) * (1 - 2 * nu)); }
  double mu() const { return E / (2 * (1 + nu)); }
  // The first Lame constant that the in-plane stress sees: lambda, or the plane-stress reduced
  // 2 lambda mu / (lambda + 2 mu) = E nu / (1 - nu^2).
  double in_plane_lambda(int dim) const
  {
    if (dim == 2 && plane == PlaneMode::PlaneStress) return E * nu / (1 - nu * nu);
    return lambda();
  }
  // P-wave speed: governs the explicit stability limit of solid elements (an upper bound in
  // plane stress, where the in-plane P-wave is slower).
  double dilatational_wave_speed() const { return std::sqrt((lambda() + 2 * mu()) / rho); }
  RankineParams rankine() const
  {
    RankineParams p;
    p.E = E;
    p.nu = nu;
    p.ft = ft;
    p.gf = gf;
    p.softening = softening;
    return p;
  }
  J2Params plasticity() const
  {
    J2Params p;
    p.E = E;
    p.nu = nu;
    p.rho = rho;
    p.plastic = plastic;
    // The table's model decides the flow-stress family, whatever plastic.model holds.
    p.plastic.model = model == MaterialModel::JohnsonCook        ? YieldModel::JohnsonCook
                      : model == MaterialModel::ZerilliArmstrong ? YieldModel::ZerilliArmstrong
                                                                 : YieldModel::J2;
    p.eos = eos;
    return p;
  }
};

} // namespace fracdem
