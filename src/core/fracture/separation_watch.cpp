// A distributed part's memory of the separation between gathered fracture checks.
#include "fracture/separation_watch.h"

#include <algorithm>

namespace fracdem
{

namespace
{
int inactive_elements(const Mesh& mesh)
{
  return static_cast<int>(std::count(mesh.active.begin(), mesh.active.end(), 0));
}
} // namespace

bool SeparationWatch::due(const Body& part)
{
  note_erosion(part);
  return outlook_.pinch_left || eroded_ || (outlook_.pieces_touch && failed_since(part));
}

void SeparationWatch::checked(const Body& part, const SeparationOutlook& outlook)
{
  outlook_ = outlook;
  eroded_ = false;
  take(part);
}

void SeparationWatch::adopted(const Body& part) { take(part); }

void SeparationWatch::note_erosion(const Body& part)
{
  if (inactive_ >= 0 && inactive_elements(part.mesh()) != inactive_) eroded_ = true;
}

// A piece of the crack turns to debris only when its last element fails completely.
bool SeparationWatch::failed_since(const Body& part) const
{
  if (!part.failed_elements()) return true; // the last evaluation saw part of the elements
  for (int e : *part.failed_elements())
    if (part.mesh().active[e] && (e >= static_cast<int>(failed_.size()) || !failed_[e]))
      return true;
  return false;
}

void SeparationWatch::take(const Body& part)
{
  inactive_ = inactive_elements(part.mesh());
  double n[3];
  failed_.assign(part.mesh().num_elems(), 0);
  for (int e = 0; e < part.mesh().num_elems(); ++e)
    failed_[e] = part.element_failure(e, n) >= 1.0 ? 1 : 0;
}

} // namespace fracdem
