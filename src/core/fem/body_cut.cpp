// Body: cracks through elements (conforming edge bisection, its mass, momentum and state
// bookkeeping) and their part of the restart record.
#include "fem/body.h"

#include "fem/edge_bisect.h"

#include <algorithm>
#include <stdexcept>

namespace fracdem
{

namespace
{
// Lumped share of node n in element e (0 when e does not hold n).
double share_of(const FeSpace& space, const Mesh& mesh, int e, int n)
{
  double me[4];
  space.element_nodal_masses(mesh, e, me);
  double m = 0;
  for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
    if (mesh.conn[e][a] == n) m += me[a];
  return m;
}

// The nodes whose lumped shares a cut changes: u and w (a tri3 / tet4 split at t keeps every
// other node's share, t + (1 - t) of it), with a quad4 around the edge every node of the
// elements around it (its split into a tri3 and a quad4 moves shares between all its nodes).
std::vector<int> changed_nodes(const Mesh& mesh, const std::vector<int>& around, int u, int w)
{
  std::vector<int> nodes{u, w};
  for (int e : around)
    if (mesh.etype[e] == ElemType::Quad4)
      for (int e2 : around)
        for (int a = 0; a < nodes_per_elem(mesh.etype[e2]); ++a)
          if (std::find(nodes.begin(), nodes.end(), mesh.conn[e2][a]) == nodes.end())
            nodes.push_back(mesh.conn[e2][a]);
  return nodes;
}
} // namespace

int Body::bisect_edge(int u, int w, double t, std::vector<int>* new_elems,
                      const std::vector<QuadJoin>& joins)
{
  if (!edge_bisectable(mesh_, stars_, u, w) || !(t > 0 && t < 1))
    throw std::invalid_argument("Body::bisect_edge: edge not bisectable or t outside (0, 1)");
  // The shares the changed nodes hold in the elements around the edge, before the cut ...
  const std::vector<int> around = elements_on_edge(stars_, u, w);
  const std::vector<int> nodes = changed_nodes(mesh_, around, u, w);
  const bool gains = nodes.size() > 2;
  std::vector<double> loss(nodes.size(), 0.0);
  std::vector<std::array<int, 4>> parent_conn;
  for (int e : around) {
    parent_conn.push_back(mesh_.conn[e]);
    for (size_t k = 0; k < nodes.size(); ++k)
      loss[k] += share_of(space_, mesh_, e, nodes[k]);
  }
  const int ne = mesh_.num_elems();
  std::vector<int> parents;
  const int p = fracdem::bisect_edge(mesh_, stars_, u, w, t, parents, joins);
  cut_elements(parents, ne, t, parent_conn);
  // ... less what they keep in the children.
  for (size_t i = 0; i < parents.size(); ++i)
    for (size_t k = 0; k < nodes.size(); ++k) {
      loss[k] -= share_of(space_, mesh_, parents[i], nodes[k]);
      loss[k] -= share_of(space_, mesh_, ne + static_cast<int>(i), nodes[k]);
    }
  resize_nodes(p + 1);
  for (int d = 0; d < 3; ++d)
    x_[3 * p + d] = x_[3 * u + d] + t * (x_[3 * w + d] - x_[3 * u + d]);
  cut_masses(p, nodes, loss, gains);
  cut_conditions(p, u, w, t);
  cut_nodes_.insert(cut_nodes_.end(), {p, u, w});
  join_cut_node_sets(p);
  stars_.build(mesh_); // O(nodes + elements) per cut: cuts are rare events
  if (elem_begin_ <= 0 && elem_end_ >= ne) elem_end_ = mesh_.num_elems();
  if (new_elems) {
    new_elems->clear();
    for (int e = ne; e < mesh_.num_elems(); ++e)
      new_elems->push_back(e);
  }
  grow_track_marks();
  return p;
}

double Body::piece_fraction(int e) const
{
  if (mesh_measure_.empty()) return 1.0;
  int root = e;
  while (root >= mesh_elems_)
    root = elem_parent_[root - mesh_elems_];
  return space_.reference_measure(e) / mesh_measure_[root];
}

// The precomputed data of both children, the parent's material state copied to the new one (a
// quad4 parent's mapped to both, map_quad_states), the viscous accounts (extensive: work and
// q W) shared by measure: t : 1 - t for a tri3 / tet4 parent.
void Body::cut_elements(const std::vector<int>& parents, int first_child, double t,
                        const std::vector<std::array<int, 4>>& parent_conn)
{
  if (mesh_measure_.empty())
    for (int e = 0; e < mesh_elems_; ++e)
      mesh_measure_.push_back(space_.reference_measure(e));
  for (size_t i = 0; i < parents.size(); ++i) {
    const int e = parents[i], c = first_child + static_cast<int>(i);
    space_.set_element(mesh_, e);
    space_.set_element(mesh_, c);
    state_.resize(space_.state_size(), 0.0);
    const bool quad = mesh_.etype[e] == ElemType::Quad4;
    if (quad)
      map_quad_states(e, c, parent_conn[i]);
    else
      std::copy(state_.begin() + space_.state_offset(e),
                state_.begin() + space_.state_offset(e + 1),
                state_.begin() + space_.state_offset(c));
    elem_parent_.push_back(e);
    if (std::binary_search(damaged_elems_.begin(), damaged_elems_.end(), e))
      damaged_elems_.push_back(c); // the largest index: the list stays sorted
    if (!viscosity_.on) continue;
    const double keep = quad ? space_.reference_measure(e) /
                                   (space_.reference_measure(e) + space_.reference_measure(c))
                             : t;
    for (std::vector<double>* a : {&viscous_work_, &viscous_force_prev_, &viscous_force_}) {
      a->push_back((1 - keep) * (*a)[e]);
      (*a)[e] *= keep;
    }
    viscous_rate_.push_back(viscous_rate_[e]);
  }
}

// A quad4 parent's children (the quad4 in slot e, the tri3 c) take each of their integration
// points' material state (damage, crack normal, band width, dissipation density) from the
// parent's point nearest to it (the tri3's one point at its centroid). Why nearest: the states
// are point values of a field the parent sampled at its four Gauss points; the nearest sample is
// the parent's own estimate there, keeps every value a state the law produced (no averaged
// damage or crack normals), and a uniform state is copied exactly, so the dissipated energy
// (density times weight) stays the parent's where its points agree.
void Body::map_quad_states(int e, int c, const std::array<int, 4>& parent_conn)
{
  const int per = (space_.state_offset(e + 1) - space_.state_offset(e)) / 4;
  if (per == 0) return;
  const double* X = mesh_.X.data();
  double from[4][2], to[4][2];
  quad_point_positions(X, parent_conn, from);
  quad_point_positions(X, mesh_.conn[e], to);
  auto nearest = [&](const double* y) {
    int best = 0;
    double d2 = 1e300;
    for (int q = 0; q < 4; ++q) {
      const double dx = from[q][0] - y[0], dy = from[q][1] - y[1], r = dx * dx + dy * dy;
      if (r < d2) d2 = r, best = q;
    }
    return best;
  };
  const std::vector<double> parent(state_.begin() + space_.state_offset(e),
                                   state_.begin() + space_.state_offset(e + 1));
  for (int q = 0; q < 4; ++q)
    std::copy_n(parent.begin() + per * nearest(to[q]), per,
                state_.begin() + space_.state_offset(e) + per * q);
  double centroid[2] = {0, 0};
  for (int a = 0; a < 3; ++a)
    for (int d = 0; d < 2; ++d)
      centroid[d] += X[3 * mesh_.conn[c][a] + d] / 3;
  std::copy_n(parent.begin() + per * nearest(centroid), per,
              state_.begin() + space_.state_offset(c));
}

// P takes the mass the changed nodes lose, with its momentum and the same fraction of their
// forces (they keep their accelerations). With `gains` (a quad4 split) a node whose share grew
// takes its gain out of that pool at the pool's mean velocity (its velocity becomes the
// mass-weighted mean: momentum kept, kinetic energy not increased) with the same fraction of the
// pool's force; P keeps the rest. Without, losses below zero (round-off) are ignored.
void Body::cut_masses(int p, const std::vector<int>& nodes, const std::vector<double>& loss,
                      bool gains)
{
  double mp = 0, mom[3] = {0, 0, 0}, f[3] = {0, 0, 0};
  for (size_t k = 0; k < nodes.size(); ++k) {
    const int n = nodes[k];
    const double dm = std::min(std::max(loss[k], 0.0), mass_[n]);
    const double share = mass_[n] > 0 ? dm / mass_[n] : 0.0;
    for (int d = 0; d < 3; ++d) {
      mom[d] += dm * v_[3 * n + d];
      const double fs = share * f_[3 * n + d];
      f[d] += fs;
      f_[3 * n + d] -= fs;
    }
    mass_[n] -= dm;
    mp += dm;
  }
  double taken = 0;
  for (size_t k = 0; gains && mp > 0 && k < nodes.size(); ++k) {
    const int n = nodes[k];
    const double gain = std::min(std::max(-loss[k], 0.0), mp - taken);
    if (!(gain > 0)) continue;
    const double part = gain / mp; // of the pool as it was: its velocity is mom / mp
    for (int d = 0; d < 3; ++d) {
      v_[3 * n + d] = (mass_[n] * v_[3 * n + d] + part * mom[d]) / (mass_[n] + gain);
      f_[3 * n + d] += part * f[d];
    }
    mass_[n] += gain;
    inv_mass_[n] = 1.0 / mass_[n];
    taken += gain;
  }
  const double keep = mp > 0 ? (mp - taken) / mp : 0.0;
  mass_[p] = mp - taken;
  for (int d = 0; d < 3; ++d) {
    v_[3 * p + d] = mp > 0 ? mom[d] / mp : 0.0;
    f_[3 * p + d] = taken > 0 ? keep * f[d] : f[d];
  }
  for (int n : nodes)
    inv_mass_[n] = mass_[n] > 0 ? 1.0 / mass_[n] : 0.0;
  inv_mass_[p] = mass_[p] > 0 ? 1.0 / mass_[p] : 0.0;
}

// P is held where both ends are held: prescribed (interpolated velocity, u's ramp and group)
// when both are, else in the components both hold (moving at the interpolated prescribed
// velocity of a partly prescribed end, 0 where `fixed` holds both); free when one end is
// prescribed and the other not. Its reaction groups are u's.
void Body::cut_conditions(int p, int u, int w, double t)
{
  const bool pu = bc_[u] == NodeBc::Prescribed, pw = bc_[w] == NodeBc::Prescribed;
  std::uint8_t mask = 0;
  bool moving = false;
  if (pu && pw) {
    bc_[p] = NodeBc::Prescribed;
    mask = 7;
  } else if (!pu && !pw) {
    mask = held_[u] & held_[w];
    for (int d = 0; d < 3; ++d)
      moving |= (mask >> d & 1) && (v_prescribed_[3 * u + d] != 0 || v_prescribed_[3 * w + d] != 0);
    bc_[p] = mask == 7 && !moving ? NodeBc::Fixed : mask ? NodeBc::Partial : NodeBc::Free;
  }
  const bool interpolate = (pu && pw) || moving;
  if (pu && pw) ramp_[p] = ramp_[u];
  if (moving) ramp_[p] = ramp_[u] > 0 ? ramp_[u] : ramp_[w];
  for (int d = 0; d < 3; ++d)
    v_prescribed_[3 * p + d] = interpolate && (mask >> d & 1)
                                   ? v_prescribed_[3 * u + d] +
                                         t * (v_prescribed_[3 * w + d] - v_prescribed_[3 * u + d])
                                   : 0.0;
  held_[p] = mask;
  bc_group_[p] = mask ? bc_group_[u] : -1;
  for (int d = 0; d < 3; ++d) {
    component_group_[3 * p + d] = (mask >> d & 1) ? component_group_[3 * u + d] : -1;
    if (mask >> d & 1) v_[3 * p + d] = v_prescribed_[3 * p + d] * ramp_factor(p, time_);
  }
}

// A node made by a cut joins the node sets that hold both ends of its edge (sets stay sorted).
void Body::join_cut_node_sets(int n)
{
  const long k = cut_index(n);
  if (k < 0) return;
  const int u = cut_nodes_[k + 1], w = cut_nodes_[k + 2];
  for (auto& entry : mesh_.node_sets) {
    std::vector<int>& s = entry.second;
    if (std::binary_search(s.begin(), s.end(), u) && std::binary_search(s.begin(), s.end(), w))
      s.insert(std::upper_bound(s.begin(), s.end(), n), n);
  }
}

// Where node n's triple starts in cut_nodes_, or -1 when no cut made n (cut nodes are appended,
// so the triples are in ascending order of their first entry).
long Body::cut_index(int n) const
{
  long lo = 0, hi = static_cast<long>(cut_nodes_.size() / 3);
  while (lo < hi) {
    const long mid = (lo + hi) / 2;
    if (cut_nodes_[3 * mid] < n)
      lo = mid + 1;
    else
      hi = mid;
  }
  return 3 * lo < static_cast<long>(cut_nodes_.size()) && cut_nodes_[3 * lo] == n ? 3 * lo : -1;
}

// The reaction groups of a cut node's held components: those of its edge's first end.
void Body::cut_node_groups(int n)
{
  const long k = cut_index(n);
  if (k < 0) return;
  for (int d = 0; d < 3; ++d)
    component_group_[3 * n + d] =
        (held_[n] >> d & 1) ? component_group_[3 * cut_nodes_[k + 1] + d] : -1;
}

/* ----------------------------------------------------------------------
   restart, version 5 (written once a cut was made): after the header,
   k = elements made by cuts, their parents (k), m = cuts, (P, u, w) per cut (3 m)
------------------------------------------------------------------------- */

void Body::pack_growth(std::vector<double>& buf) const
{
  buf.push_back(static_cast<double>(elem_parent_.size()));
  buf.insert(buf.end(), elem_parent_.begin(), elem_parent_.end());
  buf.push_back(static_cast<double>(cut_nodes_.size() / 3));
  buf.insert(buf.end(), cut_nodes_.begin(), cut_nodes_.end());
}

// Grows the mesh (as built) by the record's new elements: type, region and sets from their
// parents; the connectivity follows in the record, the element data is rebuilt after it.
const double* Body::unpack_growth(const double* p, int ne)
{
  const int k = static_cast<int>(*p++);
  if (k < 0 || ne != mesh_elems_ + k || mesh_.num_elems() != mesh_elems_)
    throw std::runtime_error("restart file holds a cut body of " + std::to_string(ne) +
                             " elements that does not grow from this mesh's " +
                             std::to_string(mesh_.num_elems()));
  elem_parent_.assign(p, p + k);
  p += k;
  for (int i = 0; i < k; ++i) {
    const int e = elem_parent_[i], c = mesh_elems_ + i;
    if (e < 0 || e >= c) throw std::runtime_error("restart file: corrupt cut-element record");
    // A quad4 parent's new element is its tri3 child (fem/edge_bisect.h); others keep the type.
    const ElemType pt = mesh_.etype[e];
    mesh_.etype.push_back(pt == ElemType::Quad4 ? ElemType::Tri3 : pt);
    mesh_.conn.push_back(mesh_.conn[e]);
    mesh_.active.push_back(1);
    if (static_cast<int>(mesh_.region.size()) == c) mesh_.region.push_back(mesh_.region[e]);
    for (auto& entry : mesh_.elem_sets)
      if (std::binary_search(entry.second.begin(), entry.second.end(), e))
        entry.second.push_back(c);
  }
  const int m = static_cast<int>(*p++);
  cut_nodes_.assign(p, p + 3 * m);
  return p + 3 * m;
}

// After the grown connectivity is read: the element data of the grown mesh (computed as the cuts
// computed it, from the reference coordinates), its material-state and viscous slots, and a
// whole-body element range.
void Body::restore_cut_elements()
{
  mesh_measure_.clear(); // the mesh's, as the body was built (the same bits as the first cut took)
  for (int e = 0; e < mesh_elems_; ++e)
    mesh_measure_.push_back(space_.reference_measure(e));
  space_.build(mesh_, material_);
  state_.assign(space_.state_size(), 0.0);
  set_bulk_viscosity(viscosity_);
  if (elem_begin_ <= 0 && elem_end_ >= mesh_elems_) elem_end_ = mesh_.num_elems();
  grow_track_marks();
}

} // namespace fracdem
