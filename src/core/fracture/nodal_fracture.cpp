// Nodal fracture: failure map, crack points, cuts through elements (min_size) and node splits.
#include "fracture/nodal_fracture.h"

#include "fracture/element_cut.h"
#include "materials/material_table.h"
#include "materials/rankine.h"

#include <algorithm>

namespace fracdem
{

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

namespace
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
                          const double n[3], double line_tolerance = 1.0 / 3.0)
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

// A node whose element star fell into pieces that touch only at the node (cracks on several
// sides of it) is split into one node per piece (logged with a zero normal): fragments are
// never held together by a single node.
void separate_pinched_nodes(Body& body, std::vector<SplitEvent>& events)
{
  // Only nodes on a crack can have been pinched (their stars changed); copies are appended to
  // the list, so a star of three pieces is taken apart in two passes.
  std::vector<int> todo;
  for (int w = 0; w < body.num_nodes(); ++w)
    if (body.parents()[w] >= 0) todo.push_back(w);
  for (const SplitEvent& ev : events)
    todo.push_back(ev.node);
  std::sort(todo.begin(), todo.end());
  todo.erase(std::unique(todo.begin(), todo.end()), todo.end());
  for (size_t k = 0; k < todo.size(); ++k) {
    const int v = todo[k];
    const SplitPlan plan = body.plan_separation(v);
    if (!plan.splittable()) continue;
    SplitEvent ev{v, -1, {0, 0, 0}, static_cast<int>(plan.side_b.size())};
    ev.copy = body.split_node(plan);
    todo.push_back(ev.copy);
    events.push_back(ev);
  }
}

// Cuts through the elements of v's star that the failure plane crosses (each cut adds a node,
// which is on no crack yet). A cut puts a face in the plane and so competes with every later
// one: a handful per point at most; the bound only guards the loop.
void cut_star(Body& body, int v, const double n[3], double min_size, std::vector<char>& on_crack,
              std::vector<CutEvent>* cuts)
{
  constexpr int kMaxCutsPerPoint = 8;
  for (int k = 0; k < kMaxCutsPerPoint; ++k) {
    const ElementCut cut =
        find_element_cut(body.mesh(), body.stars(), body.positions().data(), v, n, min_size,
                         [&body](int e) { return body.piece_fraction(e); });
    if (!cut.found()) return;
    CutEvent ev{v, cut.elem, cut.u, cut.w, cut.t, -1, {}};
    std::vector<int> added;
    ev.new_node = body.bisect_edge(cut.u, cut.w, cut.t, &added, cut.joins);
    on_crack.push_back(1); // on the crack's line: where it goes on
    // elem's child first, then the neighbours'.
    for (int c : added)
      if (body.element_parent(c) == cut.elem) ev.new_elems.push_back(c);
    for (int c : added)
      if (body.element_parent(c) != cut.elem) ev.new_elems.push_back(c);
    if (cuts) cuts->push_back(ev);
  }
}

} // namespace

std::vector<SplitEvent> insert_cracks(Body& body, const std::vector<int>& points, double min_size,
                                      std::vector<CutEvent>* cuts)
{
  // Nodes on a physical crack: split nodes and their copies (and, with cuts, the nodes made on
  // a crack's line by a cut, where the crack goes on).
  std::vector<char> on_crack(body.num_nodes(), 0);
  for (int w = 0; w < body.num_nodes(); ++w)
    if (body.parents()[w] >= 0) on_crack[w] = on_crack[body.parents()[w]] = 1;
  const bool cutting = min_size > 0;
  if (cutting)
    for (size_t k = 0; k < body.cut_nodes().size(); k += 3)
      on_crack[body.cut_nodes()[k]] = 1;
  // A cut crack runs exactly along its plane, so only nodes much nearer to it than a third of
  // an element (those the min_size guard kept the cut from passing beside) continue it.
  const double line_tolerance = cutting ? std::min(1.0 / 3.0, 0.5 * min_size) : 1.0 / 3.0;
  std::vector<SplitEvent> events;
  for (int v : points) {
    // Re-checked here: a split earlier in this pass may have opened this band already.
    double n[3] = {0, 0, 0};
    const int e = driving_element(body, v, n);
    if (e < 0 || band_already_cracked(body, on_crack, e, v, n, line_tolerance)) continue;
    // With cuts the check comes before them (they change the star), on the plan of the star
    // as it is; the split then opens along the cut.
    if (cutting) {
      if (opening_carries_tension(body, body.plan_split(v, n), n)) continue;
      cut_star(body, v, n, min_size, on_crack, cuts);
    }
    const SplitPlan plan = body.plan_split(v, n);
    if (!plan.splittable() || (!cutting && opening_carries_tension(body, plan, n))) continue;
    SplitEvent ev{v, -1, {n[0], n[1], n[2]}, static_cast<int>(plan.side_b.size())};
    ev.copy = body.split_node(plan);
    on_crack[v] = 1;
    on_crack.push_back(1);
    events.push_back(ev);
  }
  separate_pinched_nodes(body, events);
  return events;
}

std::vector<int> elements_on_crack(const Body& body, const std::vector<int>& failed)
{
  std::vector<char> split(body.num_nodes(), 0);
  for (int w = 0; w < body.num_nodes(); ++w)
    if (body.parents()[w] >= 0) split[w] = split[body.parents()[w]] = 1;
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

// Mirrors one pass of insert_cracks' loop at v on an unchanged body: with cuts, the tension check
// on the star's plan comes first, then a cut or a splittable plan changes the body; without, a
// splittable plan whose opening carries no tension. The line tolerance is insert_cracks'.
bool crack_point_may_split(const Body& body, int v, const std::vector<char>& on_crack,
                           double min_size, const std::function<double(int)>& fraction)
{
  const bool cutting = min_size > 0;
  const double line_tolerance = cutting ? std::min(1.0 / 3.0, 0.5 * min_size) : 1.0 / 3.0;
  double n[3] = {0, 0, 0};
  const int e = driving_element(body, v, n);
  if (e < 0 || band_already_cracked(body, on_crack, e, v, n, line_tolerance)) return false;
  const SplitPlan plan = body.plan_split(v, n);
  if (opening_carries_tension(body, plan, n)) return false;
  if (plan.splittable()) return true;
  return cutting && find_element_cut(body.mesh(), body.stars(), body.positions().data(), v, n,
                                     min_size, fraction)
                        .found();
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
