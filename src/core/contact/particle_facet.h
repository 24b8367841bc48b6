// Particle-facet contact between host particles and a body's boundary surface: search, closest
// points, Voronoi resolution, Hertz patch and the reaction spread onto the nodes.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "contact/contact_resolution.h"
#include "contact/contact_search.h"
#include "contact/contact_spread.h"
#include "contact/geometry.h"
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
  // Box length per periodic dimension (0: not periodic): images of a particle across a periodic
  // boundary touch the body as the particle itself would.
  double period[3] = {0, 0, 0};
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

// A contact is resolved in time when a particle approaches the surface by at most this fraction
// of its Hertz maximum approach (its impact's penetration) per step. Sphere on a rigid block at
// 3000 m/s: energy kept to 0.1 % at 0.26, lost to 1.1 % at 0.52 (docs/fix_fem_body.md).
constexpr double kMaxApproachPerStep = 0.3;

struct ParticleFacetResult {
  int contacts = 0;
  bool history_exhausted = false; // a particle had more contacts than history slots
  // Fastest approach (normal speed) of a contact that the time step does not resolve, and the
  // largest time step that would resolve it (0 / infinity when every contact is resolved).
  double unresolved_speed = 0;
  double resolving_dt = std::numeric_limits<double>::infinity();
  // hertz_patch: the widest surface patch a contact gathered, in radii of its particle (the
  // facet ghosts of a distributed body reach 4; a deeper contact needs more).
  double patch_radii = 0;

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
  // A surface given as facets (nodes 0 .. nnodes-1) with what rebuild_surface derives from a
  // mesh: outward reference normals (3 per facet), piece labels (per facet; equal labels: one
  // connected piece) and reference surface areas (per node). key_nodes: the node numbers that
  // history keys use (per node; a part of a larger surface keys its contacts by the whole
  // surface's numbers, so a particle's history stays valid when the part changes).
  void set_surface(std::vector<Facet> facets, int nnodes, std::vector<double> ref_normals,
                   std::vector<int> pieces, std::vector<double> node_area,
                   std::vector<int> key_nodes);
  void invalidate_search() { search_stale_ = true; }
  // Lumped masses of the surface's nodes (nullptr: a rigid surface, infinitely heavy; a node of
  // mass 0 is held, infinitely heavy too). A contact
  // damps the relative motion of its particle and the surface point it touches, so its dashpot
  // works on their reduced mass: the particle's alone would over-damp a light node (a split
  // node's copy, a small fragment) and the explicit step would amplify its motion instead.
  void set_node_masses(const double* mass) { node_mass_ = mass; }
  // Per node, 1 where an element at it has begun to fail (nullptr: none has): a contact whose
  // Hertz patch reaches such a node acts at its point (see patch_touches_inelastic).
  void set_inelastic_nodes(const std::vector<char>* flags) { inelastic_nodes_ = flags; }
  // hold: the evaluations read the tangential history but do not advance it: the host's set-up
  // evaluation, at the positions of the last step, as the host's granular pair styles and walls
  // do in set-up (LIGGGHTS and LAMMPS: no shear update), so that a run that goes on (a second
  // 'run', read_restart) keeps the springs of the last step.
  void hold_history(bool hold) { hold_history_ = hold; }
  const ParticleFacetOptions& options() const { return opt_; }
  // What rebuild_surface derived (set_surface's inputs for parts of this surface).
  const std::vector<double>& reference_normals() const { return facet_ref_normal_; }
  const std::vector<int>& pieces() const { return facet_piece_; }
  const std::vector<double>& node_areas() const { return node_area_; }

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
  void reference_normals(const Mesh& mesh);
  void surface_pieces();
  bool search_is_stale(const ParticleArrays& p, const double* x, int nnodes);
  void rebuild_search(const ParticleArrays& p, const double* x, int nnodes);
  void search_spheres(const ParticleArrays& p, const std::vector<Aabb>& boxes);
  void gather_hits(const ParticleArrays& p, int i, const double q[3], const double* x, size_t& c);
  void bound_facets(const double* x, int nnodes);
  void prune_candidates();
  void hit_normals(double r, const double* x);
  int particle_contacts(const ParticleArrays& p, int i, const double* X, const double* x,
                        const double* v, double dt, double* f_nodes, ParticleFacetResult& res);
  void check_time_resolution(const ContactMaterial& mat, const ContactInput& in,
                             ParticleFacetResult& res) const;
  double contact_mass(double particle_mass, const FacetHit& lead, bool spread) const;
  bool patch_touches_inelastic() const;
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
  std::vector<double> search_shift_;  // 3 per search sphere: its periodic image shift
  bool search_stale_ = true;
  bool hold_history_ = false;
  int nrebuilds_ = 0;
  const double* node_mass_ = nullptr;
  const std::vector<char>* inelastic_nodes_ = nullptr;
  // Plane and bounding ball of every facet at the last search build, and the largest node
  // displacement since then: gather_hits culls with them before any closest point.
  std::vector<FacetBound> facet_bounds_;
  std::vector<Facet> bounded_facets_; // the facets facet_bounds_ were taken of
  double node_shift_ = 0;
  // Per search sphere s, entries near_start_[s] .. near_start_[s + 1] (the same index range as
  // its block of candidates): (distance bound from the build-time centre, facet), nearest first.
  std::vector<size_t> near_start_;
  std::vector<std::pair<double, int>> near_;
  std::vector<int> near_picked_; // scratch of gather_hits
  // per-evaluation scratch
  std::vector<FacetHit> hits_, image_hits_;
  std::vector<double> hit_centres_; // 3 per hit: the particle centre (or image) that made it
  std::vector<double> normals_, overlaps_, region_normals_;
  std::vector<double> facet_ref_normal_; // 3 per facet: outward normal in the reference state
  std::vector<int> facet_piece_;         // per facet: connected component of the surface
  std::vector<int> key_nodes_;           // per node: its number in history keys (empty: itself)
  std::vector<int> hit_pieces_;          // per hit: its facet's piece (scratch)
  std::vector<char> touched_;
  std::vector<int> checks_, contacts_;
  // Hertz patch
  std::vector<double> node_area_, indentation_disp_, patch_weights_;
  SurfacePatch patch_;
  double patch_reach_ = 0; // radius of the last contact's patch (both passes' widest)
};

} // namespace fracdem
