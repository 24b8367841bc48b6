// Isotropic linear elastic material and the 2D formulation choice shared by all element kernels.
#pragma once

#include <cmath>
#include <cstdint>

namespace fracdem
{

enum class Kinematics : std::uint8_t { SmallStrain, Corotational };
enum class PlaneMode : std::uint8_t { PlaneStrain, Axisymmetric }; // only for 2D elements

struct Material {
  double E = 0, nu = 0, rho = 0;
  Kinematics kinematics = Kinematics::SmallStrain;
  PlaneMode plane = PlaneMode::PlaneStrain;
  double thickness = 1.0; // plane strain out-of-plane thickness

  double lambda() const { return E * nu / ((1 + nu) * (1 - 2 * nu)); }
  double mu() const { return E / (2 * (1 + nu)); }
  // P-wave speed: governs the explicit stability limit of solid elements.
  double dilatational_wave_speed() const { return std::sqrt((lambda() + 2 * mu()) / rho); }
};

} // namespace fracdem
