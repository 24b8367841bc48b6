// Host-independent set-up of fix fem/body's Body from a BodySpec, node sets, step and vector texts.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "fem/body.h"
#include "body/body_partition.h"
#include "body/body_spec.h"
#include "body/facet_ghosts.h"

namespace fracdem
{

// The body of the spec for a run of `dimension`: mesh read, placed, checked, built, with its
// motion, bulk viscosity, fixed and prescribed nodes; initial-velocity sets checked. Throws
// SpecError (mesh errors name the fix).
void build_body(const BodySpec& spec, int dimension, Body& body);
// The spec's mesh, read for a run of `dimension` and placed by scale/move/rotate; throws
// SpecError. build_body(spec, d, b) is build_body_from_mesh(spec, placed_body_mesh(spec, d), b).
Mesh placed_body_mesh(const BodySpec& spec, int dimension);
void build_body_from_mesh(const BodySpec& spec, Mesh mesh, Body& body);

// parallel distributed: rank 0 alone reads and places the whole mesh, partitions its elements
// (partition_elements), derives the whole surface once (global_surface, packed by pack_surface)
// and sends each rank its set-up message (part_message): the body's node and element counts,
// the rank's part (extract_part: the same part as if the rank had partitioned the mesh itself)
// and the surface. The rank builds its part's body from it (build_body_part), which counts only
// the nodes it owns; its masses at shared nodes are its own elements' share until the host sums
// them.
std::vector<double> pack_surface(const GlobalSurface& surface);
GlobalSurface unpack_surface(const std::vector<double>& in, std::size_t& at);
std::vector<double> part_message(const Mesh& whole, const std::vector<int>& elem_part,
                                 const std::vector<double>& packed_surface, int rank);
// Returns the part; global_nodes / global_elems: the whole body's counts; surface (optional):
// the whole body's surface and its facets' parts (particle contact); end (optional): where the
// message goes on after the surface (the state of a broken body's part). Throws SpecError.
MeshPart build_body_part(const BodySpec& spec, const std::vector<double>& message, Body& body,
                         int& global_nodes, int& global_elems, GlobalSurface* surface = nullptr,
                         std::size_t* end = nullptr);
// All of the above in one process (rank `rank` of `nprocs` reads the mesh itself).
MeshPart build_body_part(const BodySpec& spec, int dimension, int rank, int nprocs, Body& body,
                         int& global_nodes, int& global_elems, GlobalSurface* surface = nullptr);

// parallel by size (no 'parallel' keyword): a body is distributed over the ranks when it has more
// than this many elements and uses nothing distributed bodies refuse (distributed_refusal), else
// replicated. Measured with bench/distributed_body.py (docs/benchmarks.md): from about 12 000
// elements on the distributed step is faster at 2 ranks; below, neither wins consistently and a
// replicated body keeps every feature.
constexpr int kDistributedMinElements = 20000;
// Why the body of spec, with `elements` elements, is replicated or distributed when the spec
// leaves it to the size ("" when the spec chose); distributed: the choice.
std::string parallel_choice(const BodySpec& spec, long long elements, bool& distributed);

// A node set of the built body: "all" or a physical group of the mesh; keyword: the keyword that
// names it (error messages). Throws SpecError.
std::vector<int> body_node_set(const Body& body, const BodySpec& spec, const std::string& name,
                               const std::string& keyword);
// Shares a replicated body's element work among `nprocs` ranks when its elements carry no
// history (material state, bulk viscosity) and `replicated` does not ask otherwise; returns
// whether it did. Rank `rank` gets an even range.
bool split_element_work(Body& body, int rank, int nprocs, bool replicated = false);

// Log text "stable FE time step S, host time step H (P%)" and, when the host step exceeds the
// stable one, the error/warning text (else ""). The host writes "fix fem/body ID: " before.
std::string time_step_line(double dt_stable, double dt);
std::string time_step_violation(double dt_stable, double dt, const std::string& mesh_file);

// The global vector of fix fem/body (docs/fix_fem_body.md); reactions follow, 3 per group.
enum BodyVectorIndex {
  kVecKinetic = 0,
  kVecStrain,
  kVecExternalWork,
  kVecContactWork,
  kVecNodes,
  kVecElements,
  kVecContacts,
  kVecForceX,
  kVecForceY,
  kVecForceZ,
  kVecStableDt,
  kVecSearchRebuilds,
  kVecMomentumX,
  kVecMomentumY,
  kVecMomentumZ,
  kVecDissipated,
  kVecSplitNodes,
  kVecFragments,
  kVecBoundaryWork,
  kVecSize
};
// Entry i of the vector from the body alone (reactions included, ngroups of them); false for the
// host's entries (contacts, stable step, search rebuilds) and beyond.
bool body_vector_entry(const Body& body, int i, int ngroups, double& value);
int split_node_count(const Body& body);
int fragment_count(const Body& body);

// The host's simulation box as the body-in-box check needs it (bounds of a triclinic box).
struct HostBox {
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  bool periodic[3] = {false, false, false};
  bool fixed[3][2] = {{false, false}, {false, false}, {false, false}}; // per face: 'f' boundary
  int dimension = 3; // 2D: z is periodic by rule and the body lies in z = 0
  double slack = 0;  // the contact search buffer
};
// Particles live inside the box. Beyond a fixed face they are lost, so the body's surface must
// lie inside the fixed faces. Across a periodic boundary the particles' images (one period
// away) meet the body, so it may cross the boundary, but not be longer than the period (it
// would overlap its own image) nor lie more than a period outside. A shrink-wrapped face follows
// the particles to wherever the body is. Only the surface (facets) counts: nothing else can be
// hit (the free nodes of eroded elements may fly anywhere). Returns "" or the message
// "the body (x .. to .., ...) in the box (...) <why>".
std::string body_box_violation(const std::vector<Facet>& facets, const double* x,
                               const HostBox& box);

} // namespace fracdem
