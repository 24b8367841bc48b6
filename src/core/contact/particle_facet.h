// Particle-facet contact between host particles and a body's boundary surface: search, closest
// points, Voronoi resolution, Hertz patch and the reaction spread onto the nodes.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "contact/contact_resolution.h"
#include "contact/contact_search.h"
#include "contact/contact_spread.h"
#include "contact/granular_law.h"
#include "fem/mesh.h"

namespace fracdem
{

// The host's particles as plain arrays (the layout LAMMPS-family hosts use: one row per particle).
struct ParticleArrays {
  int n = 0; // local particles
  double** x = nullptr;
  double** v = nullptr;
  double** omega = nullptr;
  double** f = nullptr;      // forces are added
  double** torque = nullptr; // torques are added
  const double* radius = nullptr;
  const double* rmass = nullptr;
  const int* type = nullptr;
  const int* mask = nullptr; // particles with (mask & groupbit) take part
  int groupbit = ~0;
  // Tangential history: per particle, `slots` records of kHistorySlotDoubles (nullptr: none).
  double** history = nullptr;
  int slots = 0;
};

// Doubles per history record: feature key (two exact 32-bit halves) + shear[3].
constexpr int kHistorySlotDoubles = 5;
// The record of feature `key` in a particle's history row (slots records), or a new one when
// `create` (nullptr when all slots are taken). Free records have key halves -1.
double* history_slot(double* row, int slots, std::uint64_t key, bool create, bool* exhausted);
void clear_history_row(double* row, int slots);

struct ParticleFacetOptions {
  NormalModel model = NormalModel::Hertz;
  bool tangential_history = true;
  // Deformable body carrying its own compliance with a Hertz law: a resolved contact gets
  // Hertz's radius from the total approach and spreads its reaction as Hertz pressure.
  bool hertz_patch = false;
  double buffer = 0; // search buffer (host skin)
};

struct ParticleFacetResult {
  int contacts = 0;
  bool history_exhausted = false; // a particle had more contacts than history slots
};

class ParticleFacetContact
{
public:
  void configure(const ParticleFacetOptions& options);
  // Per atom type (index 0 unused): the mixed contact law of a particle of that type with this
  // surface.
  void set_materials(std::vector<ContactMaterial> per_type) { materials_ = std::move(per_type); }
  // Re-derives the boundary facets, their adjacency and the nodal surface areas from the mesh
  // (after any topology change); the next evaluation rebuilds the search.
  void rebuild_surface(const Mesh& mesh);
  void invalidate_search() { search_stale_ = true; }

  // Contact forces of the particles with the surface at node positions x and velocities v:
  // added to the particles' f / torque and, as reactions, to f_nodes (3 per node). X: reference
  // node positions (the Hertz patch measures indentation from them).
  ParticleFacetResult evaluate(const ParticleArrays& p, const double* X, const double* x,
                               const double* v, double dt, double* f_nodes);

  const std::vector<Facet>& facets() const { return facets_; }
  int search_rebuilds() const { return nrebuilds_; }
  // Facet checks and resolved facet contacts per local particle in the last evaluation.
  const std::vector<int>& checks() const { return checks_; }
  const std::vector<int>& contacts() const { return contacts_; }

private:
  bool search_is_stale(const ParticleArrays& p, const double* x, int nnodes);
  void rebuild_search(const ParticleArrays& p, const double* x, int nnodes);
  void gather_hits(const ParticleArrays& p, int i, const double* x, size_t& c);
  void hit_normals(const double q[3], double r, const double* x);
  int particle_contacts(const ParticleArrays& p, int i, const double* X, const double* x,
                        const double* v, double dt, double* f_nodes, ParticleFacetResult& res);
  bool hertz_contact_patch(const FacetHit& lead, const double* X, const double* x, ContactInput& in,
                           double radius);

  ParticleFacetOptions opt_;
  std::vector<ContactMaterial> materials_;
  int nnodes_ = 0;
  std::vector<Facet> facets_;
  SurfaceTopology topology_;
  std::unique_ptr<BufferedSearch> search_;
  std::vector<int> search_atoms_;     // search sphere index -> local particle index
  std::vector<double> search_sphere_; // x,y,z,r per search sphere at build time
  bool search_stale_ = true;
  int nrebuilds_ = 0;
  // per-evaluation scratch
  std::vector<FacetHit> hits_;
  std::vector<double> normals_, overlaps_, sx_;
  std::vector<char> touched_;
  std::vector<int> checks_, contacts_;
  // Hertz patch
  std::vector<double> node_area_, indentation_disp_, patch_weights_;
  SurfacePatch patch_;
};

} // namespace fracdem
