// Precomputed reference-configuration element data and the explicit FE kernels (forces, stress, dt).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "fem/material.h"
#include "fem/mesh.h"

namespace fracdem {

// Set-up error that names the offending element (0-based index).
struct FeError : std::runtime_error {
  FeError(int e, const std::string& what) : std::runtime_error(what), elem(e) {}
  int elem;
};

class FeSpace {
public:
  // Precomputes shape-function gradients and measures. Throws FeError on inverted or
  // degenerate elements, and for axisymmetric meshes with nodes at r = x < 0.
  void build(const Mesh& mesh, const Material& mat);

  // Lumped (row-sum) nodal masses: rho * volume (3D), rho * area * thickness (plane strain),
  // rho * 2 pi * integral of r dA (axisymmetric, full ring).
  void lumped_masses(const Mesh& mesh, std::vector<double>& m) const;

  // Adds the restoring internal forces of active elements in [e_begin, e_end) into f (3 per node)
  // so that m a = f + f_ext. x: current coordinates (3 per node). Returns the strain energy of
  // those elements; per-element energies go to elem_energy if given. An element with
  // det F <= 0 sets *first_inverted (if it is still -1); the hot loop never throws.
  double add_internal_forces(const Mesh& mesh, const double* x, int e_begin, int e_end, double* f,
                             double* elem_energy, int* first_inverted) const;

  // Cauchy stress of element e (Voigt xx, yy, zz, xy, yz, zx; the zz slot is the hoop stress in
  // axisymmetric runs), averaged over Gauss points.
  void element_stress(const Mesh& mesh, const double* x, int e, double sigma[6]) const;
  static double von_mises(const double s[6]);

  // Critical central-difference time step: 2 / omega_max with omega_max bounded from above
  // element by element (Gershgorin bound of M_e^-1 K_e, which bounds the assembled system).
  double stable_time_step(const Mesh& mesh, const double* x) const;

  double reference_measure(int e) const { return measure_[e]; }
  bool axisymmetric() const { return axisym_; }
  const Material& material() const { return mat_; }

private:
  Material mat_;
  bool axisym_ = false;
  int dim_ = 3;
  std::vector<int> offset_;      // start of element e's block in geo_
  std::vector<double> geo_;      // per element: see fe_space.cpp for the block layouts
  std::vector<double> measure_;  // reference volume (3D) or area (2D)
};

} // namespace fracdem
