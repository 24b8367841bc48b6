// What a part of a distributed body keeps between gathered fracture checks about the separation of
// pinched nodes, which only the whole body can plan.
#pragma once

#include <vector>

#include "fem/body.h"
#include "fracture/fracture_plan.h"

namespace fracdem
{

class SeparationWatch
{
public:
  // Whether the next check must gather the whole body for the separation: at the last gathered
  // check a pinched node waited on its force (so does the first check after set-up or a
  // restart), or the part eroded an element since (which may pinch a node), or pieces touched at
  // nodes and an element of the part failed completely since (a piece may have turned to debris).
  bool due(const Body& part);
  // After a gathered check: what it said of the whole body, and the part as it is now.
  void checked(const Body& part, const SeparationOutlook& outlook);
  // After the part was built afresh (a change scattered, or a rebalance).
  void adopted(const Body& part);
  // An erosion since the last check is remembered across a rebalance, which builds the part
  // afresh: called before it.
  void note_erosion(const Body& part);

private:
  bool failed_since(const Body& part) const;
  void take(const Body& part);

  SeparationOutlook outlook_{true, false};
  bool eroded_ = false;
  int inactive_ = -1;        // the part's inactive elements at the last check (-1: none yet)
  std::vector<char> failed_; // per element of the part, failed completely at the last check
};

} // namespace fracdem
