// Host-independent set-up of fix fem/body's Body from a BodySpec, node sets, step and vector texts.
#pragma once

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
// parallel distributed: every rank reads and places the whole mesh, partitions it the same way
// (partition_elements) and builds its own part's body, which counts only the nodes it owns. The
// part's masses at shared nodes are its own elements' share until the host sums them. Returns
// the part; global_nodes / global_elems: the whole body's counts.
// surface (optional): the whole body's surface and its facets' parts (particle contact).
MeshPart build_body_part(const BodySpec& spec, int dimension, int rank, int nprocs, Body& body,
                         int& global_nodes, int& global_elems, GlobalSurface* surface = nullptr);
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
