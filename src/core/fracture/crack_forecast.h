// Forecast of a fracture check: whether the check on the whole body can change anything, decided
// from what one body holds (the whole body, or one part of a distributed body).
#pragma once

#include <functional>
#include <vector>

#include "fem/body.h"

namespace fracdem
{

// Per node of a body, what it knows of the whole body's cracks (a part of a distributed body has
// it from the scatter: part_restart.h, part_crack_nodes).
struct CrackNodes {
  std::vector<char> split;      // a split node or its copy (elements_on_crack's test)
  std::vector<char> on_crack;   // as insert_cracks marks them: split, and with min_size cut nodes
  std::vector<char> whole_star; // the node's whole element star is in this body (not shared)
};
// Those of a whole body (every star whole).
CrackNodes whole_crack_nodes(const Body& whole, double min_size);

// The fracture check's settings (BodyDriver::crack_body).
struct FractureCheckRule {
  double min_size = 0;        // fracture nodal min_size (> 0: cracks through elements)
  bool erode_cracked = false; // erode_cracked: failed elements on a crack are eroded
  double dt = 0;              // host step: a failed element below it is eroded
};

// Whether the fracture check on the whole body (crack points of the failed elements,
// insert_cracks, the erosion of collapsed failed elements) may change anything at the failed
// elements this body holds and their nodes. True whenever it would split, cut or erode there
// (a superset: each crack point decided by crack_point_may_split, a point whose star is not whole
// here counts as a change, and so does a body whose last evaluation covered part of it); false
// when none of its elements failed. The check changes nothing at all when this is false for every
// part and no pinched node is left (pinch_may_separate): every change of the check starts, in
// ascending order, from the body as it is. fraction: as crack_point_may_split's.
bool check_may_change(const Body& body, const CrackNodes& nodes, const FractureCheckRule& rule,
                      const std::function<double(int)>& fraction = nullptr);

} // namespace fracdem
