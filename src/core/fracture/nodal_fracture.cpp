// Nodal fracture's rules: failure map, crack points and the decisions of a check (fracture_rules.h).
#include "fracture/nodal_fracture.h"

#include "fracture/element_cut.h"
#include "fracture/fracture_rules.h"
#include "materials/material_table.h"
#include "materials/rankine.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <utility>

namespace fracdem
{
using namespace fracture_rules;

int build_failure_map(const Body& body, FailureMap& map)
{
  map.failed.clear();
  map.damaged = body.damaged_points();
  if (const std::vector<int>* failed = body.failed_elements()) {
    for (int e : *failed)
      if (body.mesh().active[e]) map.failed.push_back(e); // one eroded since is left out
    return map.damaged;
  }
  // Element work shared among ranks: the last evaluation saw a range only.
  map.damaged = body.element_failures(map.measure, map.normal);
  const int ne = static_cast<int>(map.measure.size());
  for (int e = 0; e < ne; ++e)
    if (map.measure[e] >= 1.0) map.failed.push_back(e);
  return map.damaged;
}

std::vector<int> crack_points(const Mesh& mesh, const FailureMap& map)
{
  std::vector<int> points;
  for (int e : map.failed)
    for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
      points.push_back(mesh.conn[e][a]);
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  return points;
}

namespace fracture_rules
{
// The most failed element around node v (lowest index among equals), or -1 when none has
// failed completely. Its crack normal goes to n.
int driving_element(const Body& body, int v, double n[3])
{
  int best = -1;
  double worst = 0;
  for (const int* e = body.stars().begin(v); e != body.stars().end(v); ++e) {
    double ne[3];
    const double m = body.element_failure(*e, ne);
    if (m >= 1.0 && m > worst) {
      worst = m;
      best = *e;
      std::copy(ne, ne + 3, n);
    }
  }
  return best;
}

// A crack band is one element wide: once a physical crack runs along one side of a failed
// element (one of its nodes lies on a crack), a plane through a node on the element's other
// side would open a second, parallel crack and cut the band out as a sliver fragment. Nodes
// on the same crack line (within a third of the element's size of the plane) continue it.
bool band_already_cracked(const Body& body, const std::vector<char>& on_crack, int e, int v,
                          const double n[3], double line_tolerance)
{
  const Mesh& mesh = body.mesh();
  const double* x = body.positions().data();
  const double tol = element_diameter(mesh, e) * line_tolerance;
  for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a) {
    const int w = mesh.conn[e][a];
    if (w == v || !on_crack[w]) continue;
    double dist = 0;
    for (int d = 0; d < 3; ++d)
      dist += (x[3 * w + d] - x[3 * v + d]) * n[d];
    if (dist > tol || dist < -tol) return true;
  }
  return false;
}

// A crack point opens only once the material it would separate has no fracture energy left to
// give at once: no element that borders the opening face (shares a face through v with an
// element of the plan's other side) may still be on its softening curve with more than
// kOpenTension f_t across the failure plane (normal n). A split unloads those elements; one
// still softening at strength f has f / f_t of its fracture energy left, and a split would send
// that into vibration instead (splitting at the first failed element, the notched beam of
// docs/validation.md dissipated 0.84 of G_f (D - a) t). Elements that would not dissipate more
// if the split waited never hold it back: intact ones, those unloading elastically (the column
// beside a band that localised), cracked ones, compressed ones, and those the split does not
// separate (beside a notch or behind the tip, touching the other side at v only). The limit
// keeps the residual tension of a body whose load has fallen from holding its last rows shut.
constexpr double kOpenTension = 0.12;

bool shares_face(const Mesh& mesh, int e, int f)
{
  int common = 0;
  for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
    for (int b = 0; b < nodes_per_elem(mesh.etype[f]); ++b)
      common += mesh.conn[e][a] == mesh.conn[f][b];
  return common >= elem_dim(mesh.etype[e]);
}

bool bonded_across(const Mesh& mesh, int e, const std::vector<int>& other)
{
  for (int f : other)
    if (shares_face(mesh, e, f)) return true;
  return false;
}

// The stress mode of the body's points (as FeSpace reads strains).
StressMode point_stress_mode(const Body& body)
{
  const Material& mat = body.material();
  return body.mesh().dim == 3                   ? StressMode::Solid
         : mat.plane == PlaneMode::PlaneStress  ? StressMode::PlaneStress
         : mat.plane == PlaneMode::Axisymmetric ? StressMode::Axisymmetric
                                                : StressMode::PlaneStrain;
}

bool element_softening(const Body& body, int e)
{
  const Material& mat = body.material();
  if (mat.model != MaterialModel::Rankine) return false;
  const StressMode mode = point_stress_mode(body);
  const double* st = body.material_state().data() + body.space().state_offset(e);
  for (int q = 0; q < points_per_elem(body.mesh().etype[e]); ++q)
    if (rankine_softening(mat.rankine(), mode, st + q * kRankineStateSize)) return true;
  return false;
}

bool opening_carries_tension(const Body& body, const SplitPlan& plan, const double n[3])
{
  const double limit = kOpenTension * body.material().ft;
  for (int side = 0; side < 2; ++side) {
    const std::vector<int>& mine = side == 0 ? plan.side_a : plan.side_b;
    const std::vector<int>& other = side == 0 ? plan.side_b : plan.side_a;
    for (int e : mine) {
      if (!bonded_across(body.mesh(), e, other) || !element_softening(body, e)) continue;
      double s[6]; // Voigt xx, yy, zz, xy, yz, zx
      body.element_stress(e, s);
      const double t = n[0] * n[0] * s[0] + n[1] * n[1] * s[1] + n[2] * n[2] * s[2] +
                       2 * (n[0] * n[1] * s[3] + n[1] * n[2] * s[4] + n[2] * n[0] * s[5]);
      if (t > limit) return true;
    }
  }
  return false;
}

// The mesh node (as built or made by a cut) that node w is a split copy of, w itself if none.
int split_root(const Body& body, int w)
{
  while (body.parents()[w] >= 0)
    w = body.parents()[w];
  return w;
}

// A facet of element e through node v: its other nodes (the second -1 in 2D) as they are now,
// and the same nodes' split roots sorted, which two elements share exactly when they shared
// the facet before a crack opened it.
struct FacetAt {
  int other[2];
  std::pair<int, int> root_key;
};

void facets_at(const Body& body, int e, int v, std::vector<FacetAt>& facets)
{
  std::vector<std::array<int, 2>> others;
  facets_through(body.mesh(), e, v, others);
  facets.clear();
  for (const auto& o : others)
    facets.push_back(
        {{o[0], o[1]},
         o[1] < 0 ? std::make_pair(split_root(body, o[0]), -1)
                  : std::pair<int, int>(std::minmax(split_root(body, o[0]), split_root(body, o[1])))});
}

// The edges of facet f from v in the current configuration, and their cross product (2D: the
// edge and z, about which it turns; the product is then the edge turned, as long as the edge).
void facet_edges(const Body& body, int v, const FacetAt& f, double a[3], double c[3])
{
  const double* x = body.positions().data();
  double b[3] = {0, 0, 1};
  for (int d = 0; d < 3; ++d)
    a[d] = x[3 * f.other[0] + d] - x[3 * v + d];
  if (f.other[1] >= 0)
    for (int d = 0; d < 3; ++d)
      b[d] = x[3 * f.other[1] + d] - x[3 * v + d];
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

// Unit normal of facet f through v, in the current configuration.
void facet_normal(const Body& body, int v, const FacetAt& f, double n[3])
{
  double a[3];
  facet_edges(body, v, f, a, n);
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int d = 0; d < 3; ++d)
    n[d] = len > 0 ? n[d] / len : 0;
}

// Area of facet f through node v in the current configuration (2D: edge length times thickness).
double facet_area(const Body& body, int v, const FacetAt& f)
{
  double a[3], c[3];
  facet_edges(body, v, f, a, c);
  if (f.other[1] < 0)
    return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) * body.material().thickness;
  return 0.5 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

// A facet that a crack opened through a plan's node: shared by element a of side a and element b
// of side b before it opened (the same split roots); f as element a holds it.
struct OpenedFacet {
  int a, b;
  FacetAt f;
};

// The facets a crack opened between the two sides of plan, by side-a element, side-b element and
// facet, in the plan's order.
std::vector<OpenedFacet> opened_facets(const Body& body, const SplitPlan& plan)
{
  std::vector<OpenedFacet> out;
  std::vector<FacetAt> fa, fb;
  for (int a : plan.side_a) {
    facets_at(body, a, plan.node, fa);
    for (int b : plan.side_b) {
      facets_at(body, b, plan.node, fb);
      for (const FacetAt& f : fa)
        for (const FacetAt& g : fb)
          if (f.root_key == g.root_key) out.push_back({a, b, f});
    }
  }
  return out;
}

// Centroid of element e in the current configuration.
void element_centroid(const Body& body, int e, double c[3])
{
  const Mesh& mesh = body.mesh();
  const double* x = body.positions().data();
  const int k = nodes_per_elem(mesh.etype[e]);
  c[0] = c[1] = c[2] = 0;
  for (int a = 0; a < k; ++a)
    for (int d = 0; d < 3; ++d)
      c[d] += x[3 * mesh.conn[e][a] + d] / k;
}

// The direction from side a to side b of a pinched node's plan: the mean normal of the facets
// that a crack opened through the node (shared by an element of each side before it opened:
// the same split roots), each turned to point from its side-a element to its side-b element;
// the line between the sides' mean centroids if none. Returns false when both vanish.
bool joint_direction(const Body& body, const SplitPlan& plan, double dir[3])
{
  dir[0] = dir[1] = dir[2] = 0;
  for (const OpenedFacet& o : opened_facets(body, plan)) {
    double n[3], ca[3], cb[3];
    facet_normal(body, plan.node, o.f, n);
    element_centroid(body, o.a, ca);
    element_centroid(body, o.b, cb);
    const double sign =
        n[0] * (cb[0] - ca[0]) + n[1] * (cb[1] - ca[1]) + n[2] * (cb[2] - ca[2]) < 0 ? -1 : 1;
    for (int d = 0; d < 3; ++d)
      dir[d] += sign * n[d];
  }
  double len = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
  if (len == 0) {
    for (int side = 0; side < 2; ++side) {
      const std::vector<int>& elems = side == 0 ? plan.side_a : plan.side_b;
      for (int e : elems) {
        double c[3];
        element_centroid(body, e, c);
        for (int d = 0; d < 3; ++d)
          dir[d] += (side == 0 ? -c[d] : c[d]) / static_cast<double>(elems.size());
      }
    }
    len = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
  }
  if (len == 0) return false;
  for (int d = 0; d < 3; ++d)
    dir[d] /= len;
  return true;
}

// The internal forces that elements exert on the nodes of joints, taken again from the positions
// and the body's material state (the history is not advanced), so they read only what a
// whole-body gather carries. One copy of the state and one force array serve all the joints of
// a check: each evaluated element's state and forces are put back after use.
class JointForces
{
public:
  explicit JointForces(const Body& body)
      : body_(body), state_(body.material_state()),
        force_(3 * static_cast<size_t>(body.num_nodes()), 0.0)
  {
  }

  // The compression the node of plan transmits between the plan's two sides (N; < 0: the sides
  // pull on each other): half the difference of the forces that each side's elements exert on
  // the node, along the direction from side a to side b. Side a pushes the node towards side b
  // when pressed against it, side b back towards side a.
  double compression(const SplitPlan& plan)
  {
    double dir[3];
    if (!joint_direction(body_, plan, dir)) return 0;
    double fa[3], fb[3];
    force_on(plan.side_a, plan.node, fa);
    force_on(plan.side_b, plan.node, fb);
    double c = 0;
    for (int d = 0; d < 3; ++d)
      c += 0.5 * (fa[d] - fb[d]) * dir[d];
    return c;
  }

private:
  // The force that the elements `elems` exert on node v (restoring: m a = f).
  void force_on(const std::vector<int>& elems, int v, double out[3])
  {
    const Mesh& mesh = body_.mesh();
    double* state = state_.empty() ? nullptr : state_.data();
    for (int e : elems)
      body_.space().add_internal_forces(mesh, body_.positions().data(), e, e + 1, force_.data(),
                                        nullptr, nullptr, state);
    std::copy(force_.begin() + 3 * v, force_.begin() + 3 * v + 3, out);
    const std::vector<double>& kept = body_.material_state();
    for (int e : elems) {
      if (state) {
        const int from = body_.space().state_offset(e), to = body_.space().state_offset(e + 1);
        std::copy(kept.begin() + from, kept.begin() + to, state_.begin() + from);
      }
      for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
        std::fill_n(force_.begin() + 3 * mesh.conn[e][a], 3, 0.0);
    }
  }

  const Body& body_;
  std::vector<double> state_, force_;
};

// Walks the elements side s (1: plan.side_a, 2: plan.side_b) stays joined to once plan.node is
// split (across plan.node only within the side). Returns 1 when the walk reaches the other side
// (the separation frees no piece), 2 when the side is a piece of completely failed elements
// only, else 0; with stop_at_intact the walk ends (0) at the first element not failed.
int walk_side(const Body& body, const SplitPlan& plan, char s, bool stop_at_intact,
              const std::vector<char>* whole_star = nullptr)
{
  const Mesh& mesh = body.mesh();
  const NodeStars& stars = body.stars();
  std::vector<char> side(mesh.num_elems(), 0), seen(mesh.num_elems(), 0);
  for (int e : plan.side_a)
    side[e] = 1;
  for (int e : plan.side_b)
    side[e] = 2;
  std::vector<int> queue(s == 1 ? plan.side_a : plan.side_b);
  for (int e : queue)
    seen[e] = 1;
  bool failed_only = true;
  for (size_t h = 0; h < queue.size(); ++h) {
    double n[3];
    if (failed_only && body.element_failure(queue[h], n) < 1.0) {
      failed_only = false;
      if (stop_at_intact) return 0;
    }
    for (int a = 0; a < nodes_per_elem(mesh.etype[queue[h]]); ++a) {
      const int w = mesh.conn[queue[h]][a];
      if (whole_star && !(*whole_star)[w] && w != plan.node) return 3; // beyond this part
      for (const int* f = stars.begin(w); f != stars.end(w); ++f) {
        if (seen[*f] || (w == plan.node && side[*f] != s)) continue;
        if (side[*f] == 3 - s) return 1;
        seen[*f] = 1;
        queue.push_back(*f);
      }
    }
  }
  return failed_only ? 2 : 0;
}

// A split that would cut loose a piece of completely failed elements (a chip of the band, or a
// failed min_size piece of a cut element: it carries nothing and would fly off) waits.
bool cuts_loose_chip(const Body& body, const SplitPlan& plan, const std::vector<char>* whole_star)
{
  return walk_side(body, plan, 2, true, whole_star) == 2 ||
         walk_side(body, plan, 1, true, whole_star) == 2;
}

// Whether node w's star holds elements of two or more face-connected pieces.
bool joins_pieces(const Body& body, const FacePieces& fp, int w)
{
  for (const int* f = body.stars().begin(w); f != body.stars().end(w); ++f)
    if (fp.piece[*f] != fp.piece[*body.stars().begin(w)]) return true;
  return false;
}

// Takes the face-connected pieces of the body afresh (FacePieces, but its key): a walk through
// shared facets from each element not yet reached, in ascending order.
void take_face_pieces(const Body& body, FacePieces& fp)
{
  const Mesh& mesh = body.mesh();
  std::vector<int>& piece = fp.piece;
  piece.assign(mesh.num_elems(), -1);
  fp.start.assign(1, 0);
  fp.elems.clear();
  fp.size.clear();
  for (int e = 0; e < mesh.num_elems(); ++e) {
    if (!mesh.active[e] || piece[e] >= 0) continue;
    const int id = fp.count();
    const size_t first = fp.elems.size();
    piece[e] = id;
    fp.elems.push_back(e);
    for (size_t h = first; h < fp.elems.size(); ++h) {
      const int g = fp.elems[h];
      for (int a = 0; a < nodes_per_elem(mesh.etype[g]); ++a) {
        const int w = mesh.conn[g][a];
        for (const int* f = body.stars().begin(w); f != body.stars().end(w); ++f)
          if (piece[*f] < 0 && shares_face(mesh, g, *f)) {
            piece[*f] = id;
            fp.elems.push_back(*f);
          }
      }
    }
    std::sort(fp.elems.begin() + static_cast<long>(first), fp.elems.end());
    double size = 0;
    for (size_t h = first; h < fp.elems.size(); ++h)
      size += body.piece_fraction(fp.elems[h]);
    fp.size.push_back(size);
    fp.start.push_back(static_cast<int>(fp.elems.size()));
  }
  fp.joint_nodes.clear();
  for (int w = 0; w < body.num_nodes(); ++w)
    if (joins_pieces(body, fp, w)) fp.joint_nodes.push_back(w);
}

// The distinct values of key[e] over node w's star, ascending.
std::vector<int> star_keys(const Body& body, int w, const std::vector<int>& key)
{
  std::vector<int> out;
  for (const int* e = body.stars().begin(w); e != body.stars().end(w); ++e)
    out.push_back(key[*e]);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// Debris owners, one round: each piece without a group yet (owner < 0) that touches a piece with
// one takes the group it shares most nodes with (lowest among equals), as the groups stood at the
// start of the round. Returns whether any piece was placed.
bool place_debris(const Body& body, const FacePieces& fp, std::vector<int>& owner)
{
  std::map<std::pair<int, int>, int> shared; // (debris piece, group) -> nodes they share
  for (int w : fp.joint_nodes) { // a node inside one piece joins none
    const std::vector<int> pieces = star_keys(body, w, fp.piece);
    std::vector<int> groups;
    for (int p : pieces)
      if (owner[p] >= 0) groups.push_back(owner[p]);
    std::sort(groups.begin(), groups.end());
    groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
    for (int d : pieces)
      if (owner[d] < 0)
        for (int g : groups)
          ++shared[{d, g}];
  }
  std::vector<int> best(owner.size(), 0), placed(owner);
  for (const auto& entry : shared) { // ascending (piece, group): the lowest group wins ties
    const int d = entry.first.first;
    if (entry.second <= best[d]) continue;
    best[d] = entry.second;
    placed[d] = entry.first.second;
  }
  const bool any = placed != owner;
  owner = placed;
  return any;
}

// Debris is a piece whose elements have all failed, or one smaller than kDebrisSize mesh
// elements and than kDebrisShare of the body (a piece of a cut element left between two cracks:
// the material around it failed; the share keeps a body of a few elements out).
constexpr double kDebrisSize = 2.0, kDebrisShare = 0.01;

// The groups the separation of never-split pinched nodes judges a body's pieces by, per element
// (-1 inactive): each face-connected piece is a group, but debris (a chip of the band, pieces of
// cut elements inside a rough crack) joins the group of the neighbouring piece it shares most
// nodes with, so it stays with that side. fp: the body's face-connected pieces (face_pieces);
// whole: per piece, whether it is no debris (a group is named by its owner piece; one that is not
// whole is a chip that touches debris only).
std::vector<int> pinch_groups(const Body& body, const FacePieces& fp, std::vector<char>& whole)
{
  const int count = fp.count();
  const double small =
      std::min(kDebrisSize, kDebrisShare * std::accumulate(fp.size.begin(), fp.size.end(), 0.0));
  std::vector<int> owner(count);
  whole.assign(count, 0);
  double n[3];
  for (int p = 0; p < count; ++p) {
    bool failed = true; // a large piece meets an intact element early in its list
    for (int k = fp.start[p]; k < fp.start[p + 1] && failed; ++k)
      failed = body.element_failure(fp.elems[k], n) >= 1.0;
    whole[p] = !failed && fp.size[p] >= small;
    owner[p] = whole[p] ? p : -1; // debris waits for a neighbour's group
  }
  while (place_debris(body, fp, owner)) {
  }
  std::vector<int> group(fp.piece.size(), -1);
  for (size_t e = 0; e < fp.piece.size(); ++e)
    if (fp.piece[e] >= 0) group[e] = owner[fp.piece[e]] >= 0 ? owner[fp.piece[e]] : fp.piece[e];
  return group;
}

// The plan that takes the elements of group gb off node w, away from those of group ga (both
// lists from w's star, sorted).
SplitPlan group_plan(const Body& body, int w, const std::vector<int>& group, int ga, int gb)
{
  SplitPlan plan;
  plan.node = w;
  for (const int* e = body.stars().begin(w); e != body.stars().end(w); ++e)
    if (group[*e] == ga)
      plan.side_a.push_back(*e);
    else if (group[*e] == gb)
      plan.side_b.push_back(*e);
  return plan;
}

// The tension that the material across the facets a crack opened between the two sides of a
// plan (as joint_direction pairs them) could carry at the plan's node: f_t times each facet's
// area per facet node, where neither element beside the facet has failed completely (none
// across failed material). The beam's hinge (docs/fracture.md) pulls with up to 0.55 of this
// and holds; the joints of a crack through failed material carry nothing.
double opened_facet_strength(const Body& body, const SplitPlan& plan)
{
  double strength = 0, n[3];
  const double per_node = body.material().ft / body.mesh().dim; // facet nodes: 2 in 2D, 3 in 3D
  for (const OpenedFacet& o : opened_facets(body, plan))
    if (body.element_failure(o.a, n) < 1.0 && body.element_failure(o.b, n) < 1.0)
      strength += per_node * facet_area(body, plan.node, o.f);
  return strength;
}

// The joints of a body: per pair of groups (lower first), the nodes whose stars hold both.
using Joints = std::map<std::pair<int, int>, std::vector<int>>;

Joints group_joints(const Body& body, const FacePieces& fp, const std::vector<int>& group)
{
  Joints joints;
  for (int w : fp.joint_nodes) { // a node inside one piece is inside one group
    const std::vector<int> groups = star_keys(body, w, group);
    for (size_t i = 0; i < groups.size(); ++i)
      for (size_t j = i + 1; j < groups.size(); ++j)
        joints[{groups[i], groups[j]}].push_back(w);
  }
  return joints;
}

// Whether the groups of pair touch nowhere but at its joints (directly or through other groups).
bool last_bond(const Joints& joints, std::pair<int, int> pair)
{
  std::vector<int> reached(1, pair.first);
  for (size_t h = 0; h < reached.size(); ++h)
    for (const auto& j : joints) {
      if (j.first == pair) continue;
      const int g = reached[h];
      const int other = j.first.first == g    ? j.first.second
                        : j.first.second == g ? j.first.first
                                              : -1;
      if (other == pair.second) return false;
      if (other < 0 || std::find(reached.begin(), reached.end(), other) != reached.end()) continue;
      reached.push_back(other);
    }
  return true;
}

// A joint has no material area: like a contact it carries compression, and of tension only
// what the material across the facets opened through it could carry (opened_facet_strength).
// The joints between two groups are one bond: they go together once the sum of their
// compressions (JointForces::compression) falls below minus the sum of their strengths.
bool joints_let_go(const Body& body, const std::vector<int>& group, std::pair<int, int> pair,
                   const std::vector<int>& nodes, JointForces& forces)
{
  double compression = 0, strength = 0;
  for (int w : nodes) {
    const SplitPlan plan = group_plan(body, w, group, pair.first, pair.second);
    compression += forces.compression(plan);
    strength += opened_facet_strength(body, plan);
  }
  return compression <= -strength;
}

// Whether the joints of a pair of groups are the last bond between them (last_bond) and neither
// group is a chip (debris that touches debris only): then they wait on their force alone
// (joints_let_go).
bool bond_may_part(const std::vector<char>& whole, const Joints& joints, std::pair<int, int> pair)
{
  return whole[pair.first] && whole[pair.second] && last_bond(joints, pair);
}

// The pairs of groups whose joints go at this check.
std::set<std::pair<int, int>> parting_pairs(const Body& body, const std::vector<int>& group,
                                            const std::vector<char>& whole, const Joints& joints)
{
  std::set<std::pair<int, int>> parting;
  std::optional<JointForces> forces; // copies the material state: only where a bond may part
  for (const auto& j : joints) {
    if (!bond_may_part(whole, joints, j.first)) continue;
    if (!forces) forces.emplace(body);
    if (joints_let_go(body, group, j.first, j.second, *forces)) parting.insert(j.first);
  }
  return parting;
}

// The classes a split node's star parts into, per star element: the pieces of the star that
// touch only at the node (joined through facets within the star, as plan_star_separation takes
// them: a crack through the node separates them even where they meet again beyond the crack's
// tip), each named by its lowest element, except that a class of debris only (pinch_groups)
// stays with a class of its owner's piece where the star holds one.
std::map<int, int> star_classes(const Body& body, int v, const std::vector<int>& piece,
                                const std::vector<int>& group, const std::vector<char>& whole)
{
  const std::vector<int> star(body.stars().begin(v), body.stars().end(v));
  std::map<int, int> cls;
  for (int e : star)
    cls[e] = e;
  const auto merge = [&cls](int from, int to) {
    for (auto& c : cls)
      if (c.second == from) c.second = to;
  };
  for (size_t i = 0; i < star.size(); ++i) // stars are small
    for (size_t j = i + 1; j < star.size(); ++j)
      if (cls[star[i]] != cls[star[j]] && shares_face(body.mesh(), star[i], star[j]))
        merge(std::max(cls[star[i]], cls[star[j]]), std::min(cls[star[i]], cls[star[j]]));
  for (int e : star) {
    if (whole[piece[e]]) continue;
    bool debris_only = true;
    for (int f : star)
      if (cls[f] == cls[e] && whole[piece[f]]) debris_only = false;
    if (!debris_only) continue;
    for (int f : star)
      if (whole[piece[f]] && piece[f] == group[e]) {
        merge(std::max(cls[e], cls[f]), std::min(cls[e], cls[f]));
        break;
      }
  }
  return cls;
}

// The classes of node w's star groups that stay joined (pairs not parting), each named by its
// lowest group.
std::map<int, int> joined_classes(const Body& body, int w, const std::vector<int>& group,
                                  const std::set<std::pair<int, int>>& parting)
{
  const std::vector<int> groups = star_keys(body, w, group);
  std::map<int, int> cls;
  for (int g : groups)
    cls[g] = g;
  for (size_t i = 0; i < groups.size(); ++i) // a handful of groups per star
    for (size_t j = i + 1; j < groups.size(); ++j)
      if (!parting.count({groups[i], groups[j]})) {
        const int from = cls[groups[j]], to = cls[groups[i]];
        for (auto& c : cls)
          if (c.second == from) c.second = to;
      }
  return cls;
}

// Parting nodes cuts no facet (the classes parted never share one), so the face-connected pieces
// stay those taken before; the copies made (from first_copy) join the joint nodes where their
// star holds two pieces (debris with its owner), and the key follows the new node count.
void keep_pieces_after_parting(const Body& body, int first_copy, FacePieces& fp)
{
  std::vector<int> joints;
  for (int w : fp.joint_nodes)
    if (joins_pieces(body, fp, w)) joints.push_back(w);
  for (int w = first_copy; w < body.num_nodes(); ++w)
    if (joins_pieces(body, fp, w)) joints.push_back(w);
  fp.joint_nodes.swap(joints);
  fp.key[0] = body.num_nodes();
}

// Whether a cut would split a quad4 that has failed completely: both pieces keep its crack
// strain, which their re-interpolated displacement (linear in the tri3 piece) does not fit, so
// the tri3 piece is pressed elastically (the free quad bar of test_fracture_quad_cut: -71 MPa,
// 0.107 J of strain energy out of nothing). Such a cut is not made; the split opens along the
// element boundaries.
bool cut_splits_failed_quad(const Body& body, const ElementCut& cut)
{
  const int* w_begin = body.stars().begin(cut.w);
  const int* w_end = body.stars().end(cut.w);
  double n[3];
  for (const int* e = body.stars().begin(cut.u); e != body.stars().end(cut.u); ++e)
    if (body.mesh().etype[*e] == ElemType::Quad4 && body.element_failure(*e, n) >= 1.0 &&
        std::find(w_begin, w_end, *e) != w_end)
      return true;
  return false;
}

} // namespace fracture_rules

std::vector<char> split_nodes(const Body& body)
{
  std::vector<char> split(body.num_nodes(), 0);
  for (int w = 0; w < body.num_nodes(); ++w)
    if (body.parents()[w] >= 0) split[w] = split[body.parents()[w]] = 1;
  return split;
}

std::vector<int> pinch_candidates(const Body& body)
{
  const std::vector<char> on_crack = split_nodes(body);
  std::vector<char> candidate(on_crack);
  for (int w = 0; w < body.num_nodes(); ++w) {
    if (!on_crack[w]) continue;
    for (const int* e = body.stars().begin(w); e != body.stars().end(w); ++e)
      for (int a = 0; a < nodes_per_elem(body.mesh().etype[*e]); ++a)
        candidate[body.mesh().conn[*e][a]] = 1;
  }
  std::vector<int> out;
  for (int w = 0; w < body.num_nodes(); ++w)
    if (candidate[w]) out.push_back(w);
  return out;
}

bool pinch_may_separate(const Body& body, FacePieces& pieces)
{
  const std::vector<int> candidates = pinch_candidates(body);
  if (candidates.empty()) return false;
  const FacePieces& fp = face_pieces(body, pieces);
  const std::vector<int>& piece = fp.piece;
  std::vector<char> whole;
  const std::vector<int> group = pinch_groups(body, fp, whole);
  for (int v : candidates) // a split node parts at once (plan_separation)
    if (body.parents()[v] >= 0) {
      std::set<int> classes;
      for (const auto& c : star_classes(body, v, piece, group, whole))
        classes.insert(c.second);
      if (classes.size() > 1) return true;
    }
  const Joints joints = group_joints(body, fp, group);
  for (const auto& j : joints) // waits on its joints' force only
    if (bond_may_part(whole, joints, j.first)) return true;
  return false;
}

const FacePieces& face_pieces(const Body& body, FacePieces& pieces)
{
  const Mesh& mesh = body.mesh();
  const long key[3] = {body.num_nodes(), mesh.num_elems(),
                       static_cast<long>(std::count(mesh.active.begin(), mesh.active.end(), 1))};
  if (!std::equal(key, key + 3, pieces.key)) {
    take_face_pieces(body, pieces);
    std::copy(key, key + 3, pieces.key);
  }
  return pieces;
}

bool pieces_touch_at_nodes(const Body& body, FacePieces& pieces)
{
  return !face_pieces(body, pieces).joint_nodes.empty();
}

std::vector<int> elements_on_crack(const Body& body, const std::vector<int>& failed)
{
  const std::vector<char> split = split_nodes(body);
  const Mesh& mesh = body.mesh();
  std::vector<int> reached;
  for (int e : failed)
    for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
      if (split[mesh.conn[e][a]]) {
        reached.push_back(e);
        break;
      }
  return reached;
}

std::vector<double> fragment_masses(const Body& body)
{
  const Mesh& mesh = body.mesh();
  std::vector<int> comp;
  const int count = element_components(mesh, comp);
  std::vector<int> node_comp(body.num_nodes(), -1);
  for (int e = 0; e < mesh.num_elems(); ++e)
    if (comp[e] >= 0)
      for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
        node_comp[mesh.conn[e][a]] = comp[e];
  std::vector<double> mass(count, 0.0);
  for (int n = 0; n < body.num_nodes(); ++n)
    if (node_comp[n] >= 0) mass[node_comp[n]] += body.masses()[n];
  std::sort(mass.rbegin(), mass.rend());
  return mass;
}

} // namespace fracdem
