// Nodal fracture (paper section 2.2): failure map, assessment, and the topological update that
// turns a smeared crack into a physical one by splitting nodes along element boundaries.
#pragma once

#include <vector>

#include "fem/body.h"

namespace fracdem
{

// Stage (i): the failure map. Per element, the failure measure of its most failed integration
// point (0 intact .. 1 carries no more tension) and that point's crack normal (the failure
// direction: the maximum failure strain direction of the rotating crack). A node's measure is the
// largest of its active elements'; only nodes at measure 1 become crack points, and those are the
// nodes of the completely failed elements. So the map keeps those elements alone: the force loop
// lists them as it updates the material (Body::failed_elements), and the crack normal of a crack
// point is taken from its most failed element when it is split (insert_cracks).
struct FailureMap {
  std::vector<int> failed;             // active elements at measure 1, ascending
  int damaged = 0;                     // > 0 when any point is damaged (0: an intact body)
  std::vector<double> measure, normal; // scratch of the fallback (element_failures)
};
// Returns map.damaged.
int build_failure_map(const Body& body, FailureMap& map);

// Stage (ii): nodes whose measure reached 1 (the nodes of the failed elements), ascending.
std::vector<int> crack_points(const Mesh& mesh, const FailureMap& map);

// One applied split, for the log.
struct SplitEvent {
  int node, copy;
  double normal[3];
  int elements_moved;
};

// Stage (iii): at each crack point, in ascending order, a failure plane through the node with
// the failure direction of its most failed element (still smeared) as normal; the node is split and
// the crack opens along the element boundaries between the two sides of the plane (no element is
// cut, so no sliver is made and the stable time step of the elements is unchanged). Points whose
// star lies on one side of the plane (already split, or a surface node with a tangent plane) are
// left alone, and so are points whose failed element already borders a crack on its far side (one
// crack per band, no sliver fragments). Then a node whose star fell into pieces that touch only
// at it is split into one node per piece (event with a zero normal). Every replica that calls
// this on the same body and points makes the same splits.
std::vector<SplitEvent> insert_cracks(Body& body, const std::vector<int>& points);

// Mass of every fragment (connected piece of active elements; a node's lumped mass counts with the
// piece of its elements), largest first.
std::vector<double> fragment_masses(const Body& body);

} // namespace fracdem
