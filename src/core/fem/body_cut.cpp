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
} // namespace

int Body::bisect_edge(int u, int w, double t, std::vector<int>* new_elems)
{
  if (!edge_bisectable(mesh_, stars_, u, w) || !(t > 0 && t < 1))
    throw std::invalid_argument("Body::bisect_edge: edge not bisectable or t outside (0, 1)");
  // The shares u and w hold in the elements around the edge, before the cut.
  double loss[2] = {0, 0};
  for (int e : elements_on_edge(stars_, u, w)) {
    loss[0] += share_of(space_, mesh_, e, u);
    loss[1] += share_of(space_, mesh_, e, w);
  }
  const int ne = mesh_.num_elems();
  std::vector<int> parents;
  const int p = fracdem::bisect_edge(mesh_, stars_, u, w, t, parents);
  cut_elements(parents, ne, t);
  // ... less what they keep in the children: the slot children hold u, the new ones w.
  for (size_t i = 0; i < parents.size(); ++i) {
    loss[0] -= share_of(space_, mesh_, parents[i], u);
    loss[1] -= share_of(space_, mesh_, ne + static_cast<int>(i), w);
  }
  resize_nodes(p + 1);
  for (int d = 0; d < 3; ++d)
    x_[3 * p + d] = x_[3 * u + d] + t * (x_[3 * w + d] - x_[3 * u + d]);
  cut_masses(p, u, w, loss);
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

// The precomputed data of both children, the parent's material state copied to the new one,
// the viscous accounts (extensive: work and q W) shared by measure, t : 1 - t.
void Body::cut_elements(const std::vector<int>& parents, int first_child, double t)
{
  if (mesh_measure_.empty())
    for (int e = 0; e < mesh_elems_; ++e)
      mesh_measure_.push_back(space_.reference_measure(e));
  for (size_t i = 0; i < parents.size(); ++i) {
    const int e = parents[i], c = first_child + static_cast<int>(i);
    space_.set_element(mesh_, e);
    space_.set_element(mesh_, c);
    state_.resize(space_.state_size(), 0.0);
    std::copy(state_.begin() + space_.state_offset(e), state_.begin() + space_.state_offset(e + 1),
              state_.begin() + space_.state_offset(c));
    elem_parent_.push_back(e);
    if (std::binary_search(damaged_elems_.begin(), damaged_elems_.end(), e))
      damaged_elems_.push_back(c); // the largest index: the list stays sorted
    if (!viscosity_.on) continue;
    for (std::vector<double>* a : {&viscous_work_, &viscous_force_prev_, &viscous_force_}) {
      a->push_back((1 - t) * (*a)[e]);
      (*a)[e] *= t;
    }
    viscous_rate_.push_back(viscous_rate_[e]);
  }
}

// P takes the mass u and w lose, with its momentum (so P's velocity is their mass-weighted
// mean) and the same fraction of their forces (u and w keep their accelerations).
void Body::cut_masses(int p, int u, int w, const double* loss)
{
  double mp = 0, mom[3] = {0, 0, 0}, f[3] = {0, 0, 0};
  const int ends[2] = {u, w};
  for (int k = 0; k < 2; ++k) {
    const int n = ends[k];
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
  mass_[p] = mp;
  for (int d = 0; d < 3; ++d) {
    v_[3 * p + d] = mp > 0 ? mom[d] / mp : 0.0;
    f_[3 * p + d] = f[d];
  }
  for (int n : {u, w, p})
    inv_mass_[n] = mass_[n] > 0 ? 1.0 / mass_[n] : 0.0;
}

// P is held where both ends are held: prescribed (interpolated velocity, u's ramp and group)
// when both are, else in the components both hold; free when one end is prescribed and the
// other not. Its reaction groups are u's.
void Body::cut_conditions(int p, int u, int w, double t)
{
  const bool pu = bc_[u] == NodeBc::Prescribed, pw = bc_[w] == NodeBc::Prescribed;
  std::uint8_t mask = 0;
  if (pu && pw) {
    bc_[p] = NodeBc::Prescribed;
    mask = 7;
    ramp_[p] = ramp_[u];
    for (int d = 0; d < 3; ++d)
      v_prescribed_[3 * p + d] =
          v_prescribed_[3 * u + d] + t * (v_prescribed_[3 * w + d] - v_prescribed_[3 * u + d]);
  } else if (!pu && !pw) {
    mask = held_[u] & held_[w];
    bc_[p] = mask == 7 ? NodeBc::Fixed : mask ? NodeBc::Partial : NodeBc::Free;
  }
  held_[p] = mask;
  bc_group_[p] = mask ? bc_group_[u] : -1;
  for (int d = 0; d < 3; ++d) {
    component_group_[3 * p + d] = (mask >> d & 1) ? component_group_[3 * u + d] : -1;
    if (bc_[p] == NodeBc::Prescribed)
      v_[3 * p + d] = v_prescribed_[3 * p + d] * ramp_factor(p, time_);
    else if (mask >> d & 1)
      v_[3 * p + d] = 0;
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
    mesh_.etype.push_back(mesh_.etype[e]);
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
}

} // namespace fracdem
