// Nodal fracture (paper section 2.2): failure map, assessment, and the topological update that
// turns a smeared crack into a physical one by splitting nodes along element boundaries.
#pragma once

#include <functional>
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
// point is taken from its most failed element when it is split (fracture_plan.h).
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

// One crack through an element (fracture nodal min_size): the star element crossed at crack
// point `node`, its edge uw bisected at t, the new node and the new elements (the first is
// elem's other child; the rest, those of the neighbours around the edge).
struct CutEvent {
  int node, elem, u, w;
  double t;
  int new_node;
  std::vector<int> new_elems;
};

// Stage (iii) without the erosion: plan_fracture (fracture_plan.h: the check's rules, stated
// there) on `points`, applied at once. Splits (crack splits and partings, these with a zero
// normal) are returned, cuts (min_size > 0) go to *cuts; pieces (if given) keeps the body's
// face-connected pieces between checks.
struct FacePieces;
std::vector<SplitEvent> insert_cracks(Body& body, const std::vector<int>& points,
                                      double min_size = 0, std::vector<CutEvent>* cuts = nullptr,
                                      FacePieces* pieces = nullptr);

// The face-connected pieces of a body (active elements joined through shared facets), which the
// separation of pinched nodes reads at every check once a crack exists: taken again only when
// the topology changed (a split or a cut adds nodes, an erosion deactivates elements), so a
// check without a change costs no walk over the body.
struct FacePieces {
  long key[3] = {-1, -1, -1};   // nodes, elements, active elements when taken
  std::vector<int> piece;       // per element, its piece (-1 inactive), numbered by lowest element
  std::vector<int> start, elems; // the elements of piece p: elems[start[p] .. start[p + 1])
  std::vector<double> size;      // per piece, its measure in mesh elements (piece_fraction)
  std::vector<int> joint_nodes;  // the nodes whose stars hold two or more pieces, ascending
  int count() const { return static_cast<int>(size.size()); }
};
// Brings `pieces` up to date with the body's topology and returns it.
const FacePieces& face_pieces(const Body& body, FacePieces& pieces);

// Per node: whether a split put it on a physical crack (a split copy, or the node it was split
// from).
std::vector<char> split_nodes(const Body& body);

// The split nodes and every node of an element around one, ascending: a surface node at a
// crack's mouth, or one between two cracks, can be pinched without being split. The separation
// at the end of a check parts the split ones among them at once and judges every node
// that joins two groups of pieces; with none (no crack yet) it does nothing.
std::vector<int> pinch_candidates(const Body& body);

// Whether the separation may part a pinched node of the body at a later check without a topology
// change first: a split node whose star holds pieces at once, and the joints between two groups
// that are the last bond between them (no chip), which wait on their force.
bool pinch_may_separate(const Body& body, FacePieces& pieces);

// Whether two face-connected pieces of the body touch at a node (a joint, or debris at its
// owner): only then can a piece turning to debris (its last element failing completely, without
// a topology change) make the separation part a joint (the forecast of a distributed body).
// pieces: as pinch_may_separate's.
bool pieces_touch_at_nodes(const Body& body, FacePieces& pieces);

// The elements of `failed` that a crack has reached: at least one of their nodes is split (a
// split node or its copy). `erode_cracked` removes only these: erosion opens the body as a split
// does, so it waits for the crack to arrive; one removed while the check still holds its
// nodes back (an element they would separate still softens) would open the crack early.
std::vector<int> elements_on_crack(const Body& body, const std::vector<int>& failed);

// Mass of every fragment (connected piece of active elements; a node's lumped mass counts with the
// piece of its elements), largest first.
std::vector<double> fragment_masses(const Body& body);

} // namespace fracdem
