// The fracture check as a plan and its application: what a check does, decided from a const body.
#pragma once

#include <functional>
#include <vector>

#include "fem/body.h"
#include "fracture/element_cut.h"
#include "fracture/nodal_fracture.h"

namespace fracdem
{

// Per node of a body, what it knows of the whole body's cracks. A whole body takes them from its
// own split and cut records (whole_crack_nodes); a part of a distributed body from the scatter
// (part_restart.h, part_crack_nodes).
struct CrackNodes {
  std::vector<char> split;      // a split node or its copy
  std::vector<char> on_crack;   // split, and with min_size the nodes made by cuts
  std::vector<char> whole_star; // the node's whole element star is in this body (not shared)
};
CrackNodes whole_crack_nodes(const Body& whole, double min_size);

// The fracture check's settings (fix fem/body ... fracture nodal).
struct FractureCheckRule {
  double min_size = 0;        // min_size > 0: cracks through elements
  bool erode = true;          // the check erodes collapsed failed elements (its last stage)
  bool erode_cracked = false; // erode_cracked yes: failed elements on a crack are eroded
  bool remove_mass = false;   // the erosion takes the elements' mass off their nodes
  double dt = 0;              // host step: a failed element whose stable step is below it erodes
};

// One change a check makes, in the order it makes it.
struct FractureStep {
  enum class Kind {
    Cut,       // bisect an edge of the crack point's star (cut)
    Split,     // split `node` along the failure plane (sides; normal)
    Part,      // part pinched `node`: sides.side_b takes a copy (no failure plane)
    Erode,     // erode `elements`
    Undecided, // a part of a distributed body cannot decide crack point `node` alone
  };
  Kind kind = Kind::Undecided;
  int node = -1;
  double normal[3] = {0, 0, 0};
  SplitPlan sides;
  ElementCut cut;
  std::vector<int> elements;
};

// What the body looks like to the next checks once a whole body's plan is applied: whether a
// pinched node may still part without a topology change first (its joints wait on their force),
// and whether two face-connected pieces touch at a node (a piece turning to debris, its last
// element failing, can then make a joint part). A distributed body gathers for these.
struct SeparationOutlook {
  bool pinch_left = false;
  bool pieces_touch = false;
};

struct FracturePlan {
  std::vector<FractureStep> steps;
  SeparationOutlook outlook; // with FracturePlanInput::outlook
  bool remove_mass = false;  // the rule's, for the Erode step
  bool empty() const { return steps.empty(); }
};

struct FracturePlanInput {
  std::vector<int> points; // crack points, ascending (crack_points)
  std::vector<int> failed; // active elements at failure measure 1, ascending (erosion candidates)
  FractureCheckRule rule;
  // A part of a distributed body: its crack marks. Its plan only says whether the whole body's
  // check may change anything here: it ends at its first step, a point whose star is not whole
  // here is Undecided, and the separation of pinched nodes (which needs the whole body) is left
  // to the gathered check.
  const CrackNodes* part = nullptr;
  // Element e's measure as a fraction of its mesh element (null: the body's piece_fraction).
  std::function<double(int)> fraction;
  FacePieces* pieces = nullptr; // kept between checks; describes the body after the plan
  bool outlook = false;         // fill FracturePlan::outlook (a whole body)
};

// The plan of one check (paper section 2.2, stage (iii), and the erosion of collapsed failed
// elements), the body left unchanged. At each crack point, in ascending order, on the body as the
// plan's earlier steps left it: the failure plane from the point's most failed element; cuts
// through the star where the plane is better aligned than the element boundaries (min_size); the
// split along the plane unless the band is already cracked, the opening still carries tension,
// or the split would cut loose a chip of failed material. Then pinched nodes part, then collapsed
// failed elements erode. Every replica plans the same steps from the same body.
FracturePlan plan_fracture(const Body& body, const FracturePlanInput& in);

// What applying a plan did, for the log.
struct FractureOutcome {
  std::vector<SplitEvent> splits; // crack splits and partings (zero normal), in order
  std::vector<CutEvent> cuts;
  std::vector<int> eroded;
  bool changed() const { return !splits.empty() || !cuts.empty() || !eroded.empty(); }
};

// Applies the steps of a plan made on this body (or an identical one) in order.
FractureOutcome apply_fracture_plan(Body& body, const FracturePlan& plan);

} // namespace fracdem
