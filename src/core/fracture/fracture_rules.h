// The decisions a fracture check is made of, read from a const body (the planner's building blocks).
#pragma once

#include <functional>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "fem/body.h"
#include "fracture/element_cut.h"
#include "fracture/nodal_fracture.h"

namespace fracdem
{
namespace fracture_rules
{

// The most failed element around node v (lowest index among equals), or -1 when none has
// failed completely; its crack normal goes to n.
int driving_element(const Body& body, int v, double n[3]);

// Whether a physical crack already runs along the far side of failed element e from crack point v
// (a second plane through v would cut the band out as a sliver); nodes within line_tolerance of
// the element's size of the plane continue the crack instead.
bool band_already_cracked(const Body& body, const std::vector<char>& on_crack, int e, int v,
                          const double n[3], double line_tolerance);

// Whether an element the split would separate still softens with tension across the plane.
bool opening_carries_tension(const Body& body, const SplitPlan& plan, const double n[3]);

// Whether the split would cut loose a piece of completely failed elements. whole_star (a part's):
// a walk that leaves the part counts as no chip.
bool cuts_loose_chip(const Body& body, const SplitPlan& plan,
                     const std::vector<char>* whole_star = nullptr);

// Whether a cut would split a completely failed quad4 (not made: its pieces cannot keep the
// crack strain).
bool cut_splits_failed_quad(const Body& body, const ElementCut& cut);

// The separation of pinched nodes: per element its group (debris joins its owner's group);
// whole: per piece, whether it is no debris.
std::vector<int> pinch_groups(const Body& body, const FacePieces& fp, std::vector<char>& whole);
// The classes a split node's star parts into, per star element.
std::map<int, int> star_classes(const Body& body, int v, const std::vector<int>& piece,
                                const std::vector<int>& group, const std::vector<char>& whole);
// The joints of a body: per pair of groups (lower first), the nodes whose stars hold both.
using Joints = std::map<std::pair<int, int>, std::vector<int>>;
Joints group_joints(const Body& body, const FacePieces& fp, const std::vector<int>& group);
// The pairs of groups whose joints go at this check (their force exceeds what they carry).
std::set<std::pair<int, int>> parting_pairs(const Body& body, const std::vector<int>& group,
                                            const std::vector<char>& whole, const Joints& joints);
// The classes of node w's star groups that stay joined (pairs not parting).
std::map<int, int> joined_classes(const Body& body, int w, const std::vector<int>& group,
                                  const std::set<std::pair<int, int>>& parting);
// The pieces stay those taken before a parting (it cuts no facet); the copies join the joints.
void keep_pieces_after_parting(const Body& body, int first_copy, FacePieces& fp);

} // namespace fracture_rules
} // namespace fracdem
