// Edge-to-edge penalty contact between 3D body surfaces (two bodies, or the pieces of one).
#pragma once

#include <array>
#include <functional>
#include <utility>
#include <vector>

#include "contact/contact_search.h"
#include "contact/surface_contact.h"

namespace fracdem
{

// Two tet4 surfaces whose edges cross (box edge on box edge) can pass through each other with
// node-to-facet contact alone: no node ever lies behind a facet. Edge contact takes the feature
// edges of the surfaces (ContactSurface::edges: convex, facets at least 30 deg apart; flat and
// concave edges are left to node-to-facet) and, for a pair (edge of A, edge of B):
// * closest points pA = a0 + s (a1 - a0), pB = b0 + t (b1 - b0) of the two lines, both s and t
//   strictly inside (0, 1) (an end is a node: node-to-facet's); edges closer to parallel than
//   kParallelSin (sine of their angle) are left out (their normal is ill-defined);
// * normal n along (a1 - a0) x (b1 - b0), oriented by B's outward edge normal (normalised sum of
//   its two facets' normals), and A's outward edge normal must face B (n . N_A < 0);
// * penetration g = (pB - pA) . n > 0, accepted up to the pair's reach: the smaller of the two
//   edges' reaches (half the altitude of the elements over their facets, as SurfaceContact);
// * self contact: edges of one surface neighbourhood (one edge has a node on the other's facets:
//   edges that share a node or a facet, or that a single facet joins) are never a contact;
//   each unordered pair is taken once (the rule is symmetric in A and B). A node here stands
//   for its site (ContactSurface::site: a split node and its copies are one): the two faces of
//   a crack coincide where it opened, so an edge of one face and an edge of the other that end
//   at a split node and its copy meet at that point; the closest points of their lines stay at
//   it (s -> 1, t -> 0, inside (0, 1) as soon as the twins move apart), n = (edge A) x (edge B)
//   is the normal of the plane of the two edges, not of the crack, and the "penetration" is the
//   twins' relative displacement along n: opening or sliding of the crack taken as penetration
//   for half the directions, made by the step's own motion so not offset, and pushed back in
//   full. That held the crack faces of a breaking tet4 body shut (test_fracture_cut's torn bar:
//   every one of the 195893 edge contacts of 4000 steps was such a pair). Node-to-facet contact
//   keeps the crack's faces apart; edge pairs around other sites are still taken.
// Force: k g' n on A at pA, the opposite on B at pB, with k = penalty_scale * E * (mean square
// root of the areas of B's two facets): SurfaceContact's 3D rule with B's edge in place of the
// facet; g' is g less the offset of a penetration the step's approach cannot explain
// (SurfaceContact's rule, kept per edge pair). Coulomb friction from the relative tangential
// velocity of pA and pB, capped so that it cannot reverse that velocity within the step (the
// effective mass of the two points under the spread). Spread to the four nodes by (1 - s, s)
// and (1 - t, t): linear momentum exact. The two points lie g apart along n, so the tangential
// force makes a couple g n x f; it is cancelled by a pair of equal and opposite normal forces
// on each edge's ends (zero net force, moments along n x (a1 - a0) and n x (b1 - b0), which span
// the plane normal to n): angular momentum exact too.
struct EdgeTouch {
  int ea = -1, eb = -1; // edges of A and B (indices in ContactSurface::edges)
  double s = 0, t = 0;  // segment parameters of the closest points
  double depth = 0, normal[3] = {0, 0, 0}, pa[3], pb[3];
  double vr[3]; // velocity of pA relative to pB
};

// The contact rule above for one pair at positions xa, xb (no self exclusion): true when A's
// edge penetrates B's edge, t then holds parameters, depth, normal and points.
bool edge_touch(const ContactSurface& a, int ea, const double* xa, const ContactSurface& b, int eb,
                const double* xb, EdgeTouch& t);

// Self contact: whether edges e and f of s are neighbours (a node of one on the other's facets).
bool edges_adjacent(const ContactSurface& s, int e, int f);

class EdgeContact
{
public:
  static constexpr double kParallelSin = 0.01;
  void configure(const SurfaceContactOptions& options) { opt_ = options; }
  const SurfaceContactOptions& options() const { return opt_; }
  // After any topology change of either side: the search starts afresh.
  void invalidate() { stale_ = true; }
  // The search takes only these edges of a and of b (ascending surface edge indices; the feature
  // ones among them) and watches only their nodes' travel: a distributed body's part, whose
  // pairs all have an edge of its own and one whose facets it knows (body/piece_ghosts.h), need
  // not search the whole surface. Starts the search afresh.
  void restrict_search(std::vector<int> edges_a, std::vector<int> edges_b);
  // Adds the edge contact forces between a's and b's feature edges (self: the same surface,
  // a = b). keep (edge of a, edge of b), when given, picks the candidate pairs this caller
  // evaluates (a distributed body's pieces: each pair on one rank, body/piece_ghosts.h); the
  // state then holds those pairs only. Returns the number of contacts.
  int evaluate(const ContactSurface& a, const ContactBodyState& sa, const ContactSurface& b,
               const ContactBodyState& sb, bool self, double dt,
               const std::function<bool(int, int)>& keep = nullptr);
  // Contacts of the last evaluation (tests).
  const std::vector<EdgeTouch>& touches() const { return touches_; }
  // Candidate pairs of the search in use, (edge of a, edge of b) (tests).
  std::vector<std::pair<int, int>> candidates() const;
  // Per contacting pair (its four nodes, penetration, offset), as SurfaceContact::pack_state;
  // a multiple of 6 doubles.
  void pack_state(std::vector<double>& out) const;
  void unpack_state(const double* in, size_t n);

private:
  struct Record {
    std::array<int, 4> key; // a0, a1, b0, b1
    double depth, offset;
    bool operator<(const Record& o) const { return key < o.key; }
  };
  bool needs_rebuild(const ContactSurface& a, const double* xa, const ContactSurface& b,
                     const double* xb) const;
  void rebuild_search(const ContactSurface& a, const double* xa, const ContactSurface& b,
                      const double* xb);
  double effective_depth(const std::array<int, 4>& key, const EdgeTouch& t, double dt);
  static void spread(const EdgeTouch& t, const double* const* x, const double* force,
                     double (&f)[4][3]);
  void apply(const EdgeTouch& t, const ContactSurface& a, const ContactBodyState& sa,
             const ContactSurface& b, const ContactBodyState& sb, double dt) const;

  SurfaceContactOptions opt_;
  BufferedSearch search_{0.0};
  std::vector<int> feat_a_, feat_b_; // feature edges of each side, search index -> edge
  std::vector<double> xa0_, xb0_;    // watched node positions at the search's build
  bool restricted_ = false;          // restrict_search: only_a_ / only_b_, their nodes watched
  std::vector<int> only_a_, only_b_, watch_a_, watch_b_;
  double reach_ = 0;                 // deepest accepted pair: the rebuild threshold
  bool stale_ = true;
  std::vector<EdgeTouch> touches_;
  std::vector<Record> last_, next_; // contacts of the last evaluation, sorted by key
};

} // namespace fracdem
