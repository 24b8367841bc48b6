// Host-independent set-up of fix fem/body's Body from a BodySpec, node sets, step and vector texts.
#pragma once

#include <string>
#include <vector>

#include "fem/body.h"
#include "fem/body_spec.h"

namespace fracdem
{

// The body of the spec for a run of `dimension`: mesh read, placed, checked, built, with its
// motion, bulk viscosity, fixed and prescribed nodes; initial-velocity sets checked. Throws
// SpecError (mesh errors name the fix).
void build_body(const BodySpec& spec, int dimension, Body& body);
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

} // namespace fracdem
