// Crack tracking for localised damage in plane bodies: the elements a crack band may soften in.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "fem/mesh.h"

namespace fracdem
{

// The scheme (after Cervera & Chiumenti 2006; Cervera, Pela & Chiumenti 2010), in the reference
// configuration of a 2D mesh (tri3, quad4):
//  * Only marked elements may soften; the others stay elastic (FeSpace::set_softening_mask).
//  * Nucleation: an unmarked element whose stress reached the strength starts a crack when no
//    marked element and no crack tip lies within the exclusion radius of its centroid (by
//    default the tracking length L). Candidates are taken by decreasing largest principal stress,
//    so the most stressed starts first and excludes its neighbourhood. The element is marked and
//    gets two tips at its centroid, pointing both ways along the crack direction.
//  * Crack direction: perpendicular (in the plane) to the major principal direction of the
//    stress averaged, weighted by area, over the active elements whose centroids lie within L
//    of the point (not one point's stress: the band does not follow one element's noise).
//  * Propagation: from the tip point the straight line along the crack direction (oriented as
//    the tip's previous direction) leaves the tip element through one edge; the element across
//    that edge is marked and becomes the tip element, the exit point the tip point, when the tip
//    element is damaged or an unmarked element within L of the tip point is held at the strength
//    (material failing near a tip makes the tip grow, where the exclusion forbids a new crack;
//    a tip that waited would hold that region elastic above the strength). A tip stops at the
//    boundary, at an eroded element and where it meets a marked element (cracks join).
// Neighbours are found through the nodes' roots (a split copy's parent chain), so a split
// behind the tip does not cut the band's adjacency.

struct TrackTip {
  int elem = -1;
  double p[2] = {0, 0};   // tip point (reference coordinates)
  double dir[2] = {0, 0}; // unit direction of growth
};

// What the tracker keeps between checks (a body's restart state).
struct CrackTrackState {
  std::vector<std::uint8_t> marked; // per element: 1 = may soften
  std::vector<TrackTip> tips;       // live tips
  int cracks = 0;                   // cracks started so far
};

// Reference geometry the tracker reads, from the mesh (rebuild when the element count changes).
struct TrackGeometry {
  std::vector<double> centroid;              // 2 per element
  std::vector<double> area;                  // per element
  std::vector<std::array<int, 4>> neighbour; // across local edge k (nodes k, k+1); -1: none
};
// parents: per node, the node it was split from (-1: none); empty: no splits.
TrackGeometry track_geometry(const Mesh& mesh, const std::vector<int>& parents);

// Cauchy stress of element e now (Voigt xx, yy, zz, xy, yz, zx).
using ElementStressFn = std::function<void(int e, double sigma[6])>;

struct TrackInput {
  const std::vector<int>* damaged = nullptr;      // elements with damage > 0, ascending
  const std::vector<int>* overstressed = nullptr; // unmarked elements at the strength
  ElementStressFn stress;
  double length = 0;    // L: averaging radius
  double exclusion = 0; // nucleation exclusion radius (<= 0: L)
};

struct TrackEvents {
  int nucleated = 0, advanced = 0, stopped = 0;
  std::vector<int> started; // the elements where cracks started, in order
};

// Sizes state.marked to the mesh (new elements of cuts take their parent's mark: parent_of(e),
// or unmarked where it returns -1), then one round: each tip advances at most one element,
// then the candidates nucleate. The lists in `in` are ascending.
TrackEvents track_cracks(const Mesh& mesh, const TrackGeometry& geo, const TrackInput& in,
                         CrackTrackState& state, const std::function<int(int)>& parent_of = {});

// In-plane unit major principal direction of the stress averaged over radius L around p; false
// when no active element lies within L (n untouched).
bool averaged_failure_normal(const Mesh& mesh, const TrackGeometry& geo,
                             const ElementStressFn& stress, const double p[2], double L,
                             double n[2]);

// Mean element extent (element_diameter) of the active elements: the floor of L is two of them.
double mean_element_size(const Mesh& mesh);

// Restart: the state as doubles (count-prefixed), and back; unpack returns the end of its record.
void pack_track_state(const CrackTrackState& state, std::vector<double>& buf);
const double* unpack_track_state(const double* p, CrackTrackState& state);

} // namespace fracdem
