// Precomputed reference-configuration element data and the explicit FE kernels (forces, stress,
// dt).
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>
#include <cstddef>
#include <vector>

#include "materials/bulk_viscosity.h"
#include "materials/material.h"
#include "fem/mesh.h"

namespace fracdem
{

// Set-up error that names the offending element (0-based index) in its message and in `elem`.
struct FeError : std::runtime_error {
  FeError(int e, const std::string& what) : std::runtime_error(what), elem(e) {}
  int elem;
};

// Element formulations (all linear isotropic elastic, see fe_space.cpp for details):
//   Tet4  : constant strain, one point.
//   Tri3  : constant strain, one point (axisymmetric: hoop strain at the centroid).
//   Quad4 : bilinear, 2x2 Gauss, B-bar (volume-averaged dilatation) against volumetric locking.
// Kinematics::Corotational: polar rotation R of F per element / Gauss point, P = R sigma(R^T F -
// I); exactly invariant under rigid rotation and f = -dE/dx exactly (isotropic material).
// Plastic laws (Material::plastic_model) under Corotational see the logarithmic strain ln U of
// U = R^T F instead and return the rotated Kirchhoff stress tau (Cauchy = R tau R^T / J), so that
// isochoric plastic flow keeps the volume at finite strain; quad4 then takes its B-bar dilatation
// from the element's volume ratio (ln of the mean J). SmallStrain ("model elastic") feeds every
// law the small strain sym(grad u): a small-strain / small-rotation model only.
class FeSpace
{
public:
  // Precomputes shape-function gradients, integration weights and measures. Throws FeError on
  // inverted or degenerate elements, on elements of the wrong dimension, and for axisymmetric
  // meshes with an element node at r = x < 0; std::invalid_argument for a plastic material or
  // EOS that material_setup_error refuses (e.g. plane stress).
  void build(const Mesh& mesh, const Material& mat);

  // (Re)computes element e's precomputed data from mesh.X after a cut changed its nodes; e ==
  // the number of elements held appends a block (and its material-state slot) for a new element.
  // Throws FeError when the element is inverted or degenerate (nothing is appended then).
  void set_element(const Mesh& mesh, int e);

  // Lumped nodal masses (one per node, inactive elements skipped): rho * volume (3D),
  // rho * area * thickness (plane strain), rho * 2 pi * integral of r dA (axisymmetric, full ring,
  // r-weighted consistent row sums).
  void lumped_masses(const Mesh& mesh, std::vector<double>& m) const;
  // Element e's contribution to the lumped masses of its nodes (node order of conn).
  void element_nodal_masses(const Mesh& mesh, int e, double me[4]) const
  {
    element_masses(mesh, e, me);
  }

  // Adds the restoring internal forces of active elements in [e_begin, e_end) into f (3 per node)
  // so that m a = f + f_ext. x: current coordinates (3 per node). Returns the strain energy of
  // those elements; per-element energies go to elem_energy[e] if given (0 for inactive ones).
  // An element with det F <= 0 sets *first_inverted (if non-null and still < 0); never throws.
  // state: the material's per-point history (state_size() doubles, element e's points from
  // state_offset(e)), advanced by this call; may be null for materials without state.
  // damaged_points (optional): the number of points with damage > 0 after the call;
  // overstressed_elems (optional): elements held elastic by the softening mask whose stress
  // reached the strength, ascending.
  // damaged_elems (optional): the elements with such a point, ascending (read while each point's
  // state is in cache, so the fracture check need not sweep every element's state again).
  // dt: time since the previous evaluation, for rate-dependent materials (0: none known, the
  // material reuses the rate it stored; elastic and Rankine ignore it).
  double add_internal_forces(const Mesh& mesh, const double* x, int e_begin, int e_end, double* f,
                             double* elem_energy, int* first_inverted, double* state = nullptr,
                             int* damaged_points = nullptr, double dt = 0.0,
                             std::vector<int>* damaged_elems = nullptr,
                             std::vector<int>* failed_elems = nullptr,
                             std::vector<int>* overstressed_elems = nullptr) const;

  // Cauchy stress of element e (Voigt xx, yy, zz, xy, yz, zx; the zz slot is the hoop stress in
  // axisymmetric runs), averaged over Gauss points. Small-strain stress rotated by R
  // (corotational); plastic corotational: R tau R^T / J (J: the element's volume ratio for quad4
  // with B-bar, the point's otherwise).
  // state: as for add_internal_forces; read only (evaluated on a copy).
  void element_stress(const Mesh& mesh, const double* x, int e, double sigma[6],
                      const double* state = nullptr) const;
  static double von_mises(const double s[6]);
  // Strain energy of element e now (0 if inactive), as add_internal_forces counts it, evaluated
  // on a copy of its state (the history is not advanced). state: as for element_stress.
  double element_energy(const Mesh& mesh, const double* x, int e,
                        const double* state = nullptr) const;

  // Bulk viscosity (materials/bulk_viscosity.h) of the active elements in [e_begin, e_end): adds
  // the forces of each element's viscous pressure q, acting in the current configuration x with
  // nodal velocities v, into f. Per element (0 where inactive or inverted): force_scale[e] = q W
  // (W: current volume, or area times thickness / 2 pi r in 2D) and rate[e] = D, the element's
  // volumetric strain rate, so the viscous forces do work q W D per unit time (<= 0). q is scaled
  // by 1 - d with d the element's failure measure (Rankine damage), so a crack does not take
  // viscous work on top of its fracture energy. state: as for add_internal_forces.
  void add_viscous_forces(const Mesh& mesh, const double* x, const double* v, int e_begin,
                          int e_end, const BulkViscosity& bv, const double* state, double* f,
                          double* force_scale, double* rate) const;

  // The viscous forces of given pressures: for each active element q = force_scale[e] / W at
  // the current configuration x (force_scale of an earlier evaluation at the same x), into f.
  void add_given_viscous_forces(const Mesh& mesh, const double* x, int e_begin, int e_end,
                                const double* force_scale, double* f) const;

  // Critical central-difference time step 2 / omega_max, with omega_max bounded from above
  // element by element by a provable bound of lambda_max(M_e^-1 K_e) (see fe_space.cpp), taken
  // over both the reference and the current configuration x. Returns 1e300 for no active elements.
  // With bulk viscosity (bv on; rate: each element's last volumetric strain rate, or null for 0)
  // each element's step is reduced by damped_time_step_factor of its damping ratio.
  double stable_time_step(const Mesh& mesh, const double* x, const BulkViscosity* bv = nullptr,
                          const double* rate = nullptr) const;
  double element_time_step(const Mesh& mesh, const double* x, int e) const
  {
    const double w2 = mesh.active[e] ? omega2_bound(mesh, x, e) : 0.0;
    return w2 > 0 ? 2.0 / std::sqrt(w2) : 1e300;
  }
  double element_time_step(const Mesh& mesh, const double* x, int e, const BulkViscosity& bv,
                           double rate) const;
  // Same bound for one element, expressed as characteristic length l_e = c * dt_e.
  double characteristic_length(const Mesh& mesh, const double* x, int e) const;

  double reference_measure(int e) const { return measure_[e]; }
  // Material history: doubles in all, and where element e's points start.
  int state_size() const { return state_offset_.back(); }
  int state_offset(int e) const { return state_offset_[e]; }
  // Integration weight (volume it stands for) of point q of element e.
  double point_weight(const Mesh& mesh, int e, int q) const;
  bool axisymmetric() const { return axisym_; }
  const Material& material() const { return mat_; }
  // Crack tracking (fracture/crack_tracking.h): per element, whether its points may soften. An
  // element at 0 whose points are undamaged is evaluated elastically (rankine_held_stress), in
  // the force loop and on copies alike. Empty (default): every element may soften. Kept by value
  // (a copied space holds its own), one byte per element; set again when the marks change.
  void set_softening_mask(const std::vector<std::uint8_t>& may_soften) { may_soften_ = may_soften; }
  const std::uint8_t* softening_mask() const
  {
    return may_soften_.empty() ? nullptr : may_soften_.data();
  }

  // Bytes of the precomputed element data (capacities of its arrays).
  std::size_t memory_bytes() const
  {
    return offset_.capacity() * sizeof(int) + geo_.capacity() * sizeof(double) +
           measure_.capacity() * sizeof(double) + state_offset_.capacity() * sizeof(int);
  }

private:
  double evaluate_copy(const Mesh& mesh, const double* x, int e, const double* state,
                       double s[6]) const;
  double omega2_bound(const Mesh& mesh, const double* x, int e) const;
  // Element e's geometry block at the positions x into g (kQuadBlock doubles); false where it is
  // inverted or degenerate there.
  bool current_geometry(const Mesh& mesh, const double* x, int e, double* g) const;
  // The same bound from the reference block and, if not null, element e's block g_current of
  // the current configuration.
  double omega2_of(const Mesh& mesh, int e, const double* g_current) const;
  // Element e's failure measure (0 intact .. 1 no tension left; 0 for materials that do not fail).
  double element_damage(const Mesh& mesh, int e, const double* state) const;
  void element_masses(const Mesh& mesh, int e, double me[4]) const;

  Material mat_;
  std::vector<std::uint8_t> may_soften_;
  bool log_strain_ = false; // plastic law under `model corotational`: ln U (see fe_space.cpp)
  bool axisym_ = false;
  int dim_ = 3;
  std::vector<int> offset_;          // start of element e's block in geo_
  std::vector<double> geo_;          // per element: see fe_space.cpp for the block layouts
  std::vector<double> measure_;      // reference volume (3D) or area (2D)
  std::vector<int> state_offset_{0}; // start of element e's material state
};

// Reference positions (x, y) of the four integration points of a quad4 with nodes conn (X: 3
// coordinates per node), in the order of its material-state points (cracks through elements map
// a parent's point states to its children's points by these).
void quad_point_positions(const double* X, const std::array<int, 4>& conn, double xy[4][2]);

} // namespace fracdem
