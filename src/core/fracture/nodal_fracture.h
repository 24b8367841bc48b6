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

// One crack through an element (fracture nodal min_size): the star element crossed at crack
// point `node`, its edge uw bisected at t, the new node and the new elements (the first is
// elem's other child; the rest, those of the neighbours around the edge).
struct CutEvent {
  int node, elem, u, w;
  double t;
  int new_node;
  std::vector<int> new_elems;
};

// Stage (iii): at each crack point, in ascending order, a failure plane through the node with
// the failure direction of its most failed element (still smeared) as normal; the node is split and
// the crack opens along the element boundaries between the two sides of the plane (no element is
// cut, so no sliver is made and the stable time step of the elements is unchanged). Points whose
// star lies on one side of the plane (already split, or a surface node with a tangent plane) are
// left alone, and so are points whose failed element already borders a crack on its far side (one
// crack per band, no sliver fragments). Then a node whose star fell into pieces that touch only
// at it is split into one node per piece (event with a zero normal). A point also waits while an
// element the split would separate is still softening under tension across the plane (it would
// be cut loose with fracture energy left: nodal_fracture.cpp). Every replica that calls
// this on the same body and points makes the same splits.
// With min_size > 0 (fracture nodal min_size), before a point's split, the failure plane may
// first cut through elements of its star (fracture/element_cut.h, Body::bisect_edge) where it
// is better aligned than the element boundaries and both pieces keep at least min_size of the
// parent's measure; the split then opens along the cut. Cuts go to *cuts (if given).
// pieces (if given) keeps the body's face-connected pieces between checks (FacePieces).
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

// Whether insert_cracks(body, points, min_size) would change anything at crack point v (cut an
// element of its star, or split it) when it comes to v with the body as it is now: the same
// decisions on the same helpers (driving element, band already cracked, tension across the
// opening, split plan, element cut), read only. on_crack: per node, whether it lies on a physical
// crack, as insert_cracks marks them (a split node or its copy; with min_size > 0 also a node made
// by a cut). fraction: each element's measure as a fraction of its mesh element
// (Body::piece_fraction); null takes 1, an upper bound, with which a cut is found wherever one
// would be with the true fractions (the answer stays a superset). So is a body that holds only
// part of v's neighbourhood (a part of a distributed body) as long as it holds v's whole star:
// fewer elements around an edge only relax the cut's guards.
// The chip rule (no split that cuts loose a piece of completely failed elements) too: whole_star
// (per node, whether its element star is in this body; null: the whole body) stops its walks
// where a part ends, and the point then counts as one that may split.
bool crack_point_may_split(const Body& body, int v, const std::vector<char>& on_crack,
                           double min_size = 0,
                           const std::function<double(int)>& fraction = nullptr,
                           const std::vector<char>* whole_star = nullptr);

// Per node: whether a split put it on a physical crack (a split copy, or the node it was split
// from).
std::vector<char> split_nodes(const Body& body);

// The split nodes and every node of an element around one, ascending: a surface node at a
// crack's mouth, or one between two cracks, can be pinched without being split. The separation
// at the end of insert_cracks parts the split ones among them at once and judges every node
// that joins two groups of pieces; with none (no crack yet) it does nothing.
std::vector<int> pinch_candidates(const Body& body);

// Whether the separation may take a pinched node of the body apart at a later check without a
// topology change first: a split node at once, the joints between two groups (face-connected
// pieces, debris with the piece that owns it) once they are the last bond between them and no
// chip, which then waits on their force (a state that changes from step to step). False when
// every pinched node is held until the topology changes (or a piece turns to debris: its last
// element fails, which only a check that changes the topology sees). pieces: the body's
// face-connected pieces, taken here if they are not up to date (face_pieces).
bool pinch_may_separate(const Body& body, FacePieces& pieces);

// Whether two face-connected pieces of the body touch at a node (a joint, or debris at its
// owner): only then can a piece turning to debris (its last element failing completely, without
// a topology change) make the separation part a joint (the forecast of a distributed body).
// pieces: as pinch_may_separate's.
bool pieces_touch_at_nodes(const Body& body, FacePieces& pieces);

// The elements of `failed` that a crack has reached: at least one of their nodes is split (a
// split node or its copy). `erode_cracked` removes only these: erosion opens the body as a split
// does, so it waits for the crack to arrive; one removed while insert_cracks still holds its
// nodes back (an element they would separate still softens) would open the crack early.
std::vector<int> elements_on_crack(const Body& body, const std::vector<int>& failed);

// Mass of every fragment (connected piece of active elements; a node's lumped mass counts with the
// piece of its elements), largest first.
std::vector<double> fragment_masses(const Body& body);

} // namespace fracdem
