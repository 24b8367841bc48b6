// BodyDriver's contact of a distributed body's own pieces: a replica of the whole surface's state
// on every rank, all-reduced each host step, and the contact scene run on it as for a replicated
// body (docs/distributed_bodies.md, "Contact of the pieces").
#include "body/body_driver.h"

#include <algorithm>

namespace fracdem
{

namespace
{

// Local index of each global number (-1: not in `global`).
std::vector<int> inverse(const std::vector<int>& global, int size)
{
  std::vector<int> local(std::max(size, 0), -1);
  for (size_t i = 0; i < global.size(); ++i)
    if (global[i] >= 0 && global[i] < size) local[global[i]] = static_cast<int>(i);
  return local;
}

} // namespace

// Nodes of the part whose elements, on every part that shares them, are all eroded: (global
// number, X) per owned one, gathered and sent to every rank (a body that cannot erode has none).
std::vector<double> BodyDriver::free_surface_nodes() const
{
  if (!can_erode()) return {};
  const Mesh& mesh = body_.mesh();
  std::vector<double> live(part_.num_nodes(), 0.0); // live elements around each node
  for (int e = 0; e < mesh.num_elems(); ++e)
    if (mesh.active[e])
      for (int n : mesh.conn[e])
        if (n >= 0) live[n] += 1.0;
  shared_sum_(live.data(), 1);
  std::vector<double> mine;
  for (int n = 0; n < part_.num_nodes(); ++n)
    if (part_.owns(n) && !(live[n] > 0)) {
      mine.push_back(part_.global_node[n]);
      mine.insert(mine.end(), &mesh.X[3 * n], &mesh.X[3 * n] + 3);
    }
  const std::vector<double> all = host_.gather ? host_.gather(mine) : mine;
  return host_.scatter ? host_.scatter([&](int) { return all; }) : all;
}

// The whole body's contact surface in global node numbers, as a replicated body builds it from
// its mesh: facets, their order and their nodes' reference positions from the whole surface
// every rank holds (GlobalSurface), each facet's reach from the part that holds its element, the
// free nodes (free_surface_nodes) and the surface nodes' masses from their owners. Entered by
// every rank at the first evaluation after a topology change: two all-reductions of one double
// per facet and per surface node (and, for a body that can erode, a gather and a scatter of the
// free nodes).
void BodyDriver::build_part_surface()
{
  part_surface_due_ = false;
  const GlobalSurface& whole = ghosts_.surface();
  const int ng = global_nodes_;
  const std::vector<int> local_node = inverse(part_.global_node, ng);
  int ge = 0;
  for (int e : part_.global_elem)
    ge = std::max(ge, e + 1);
  const std::vector<int> local_elem = inverse(part_.global_elem, ge);
  std::vector<double> reach(whole.facets.size(), 0.0);
  for (size_t k = 0; k < whole.facets.size(); ++k) {
    Facet fc = whole.facets[k];
    if (fc.elem >= ge || local_elem[fc.elem] < 0) continue;
    fc.elem = local_elem[fc.elem];
    for (int j = 0; j < fc.nn; ++j)
      fc.n[j] = local_node[fc.n[j]];
    reach[k] = facet_reach(body_.mesh(), fc);
  }
  host_.sum(reach.data(), static_cast<int>(reach.size()));
  std::vector<double> X(3 * static_cast<size_t>(ng), 0.0); // surface nodes' only
  for (size_t i = 0; i < whole.nodes.size(); ++i)
    std::copy(&whole.X[3 * i], &whole.X[3 * i] + 3, &X[3 * static_cast<size_t>(whole.nodes[i])]);
  const std::vector<double> free_list = free_surface_nodes();
  std::vector<int> free;
  for (size_t k = 0; k + 3 < free_list.size(); k += 4) {
    const int g = static_cast<int>(free_list[k]);
    free.push_back(g);
    std::copy(&free_list[k + 1], &free_list[k + 1] + 3, &X[3 * static_cast<size_t>(g)]);
  }
  std::sort(free.begin(), free.end());
  surface_.build(whole.facets, reach, X.data(), ng, free);
  const std::vector<int>& nodes = surface_.nodes;
  surf_local_.assign(nodes.size(), -1);
  surf_owned_.assign(nodes.size(), 0);
  std::vector<double> m(nodes.size(), 0.0);
  for (size_t s = 0; s < nodes.size(); ++s) {
    const int n = local_node[nodes[s]];
    surf_local_[s] = n;
    surf_owned_[s] = n >= 0 && part_.owns(n) ? 1 : 0;
    if (surf_owned_[s]) m[s] = body_.masses()[n];
  }
  host_.sum(m.data(), static_cast<int>(m.size()));
  surf_x_.assign(3 * static_cast<size_t>(ng), 0.0);
  surf_v_.assign(3 * static_cast<size_t>(ng), 0.0);
  surf_f_.assign(3 * static_cast<size_t>(ng), 0.0);
  surf_m_.assign(ng, 0.0);
  for (size_t s = 0; s < nodes.size(); ++s)
    surf_m_[nodes[s]] = m[s];
}

// Each host step: every part gives the positions and velocities of the surface nodes it owns, one
// all-reduction (6 doubles per surface node) gives every rank the whole surface, the scene
// (search, the contact work's partition over the ranks, node-to-facet / edge contact, their
// states) runs on it as on a replicated body, and a second all-reduction (3 doubles per surface
// node) brings every contact force to the node's owner, whose shared-node sum follows.
void BodyDriver::distributed_body_contacts(std::int64_t step, double dt)
{
  if (part_surface_due_) build_part_surface();
  const std::vector<int>& nodes = surface_.nodes;
  const size_t ns = nodes.size();
  const double* x = body_.positions().data();
  const double* v = body_.velocities().data();
  surf_buf_.assign(6 * ns, 0.0);
  for (size_t s = 0; s < ns; ++s)
    if (surf_owned_[s]) {
      const int n = surf_local_[s];
      std::copy(&x[3 * n], &x[3 * n] + 3, &surf_buf_[6 * s]);
      std::copy(&v[3 * n], &v[3 * n] + 3, &surf_buf_[6 * s + 3]);
    }
  host_.sum(surf_buf_.data(), static_cast<int>(6 * ns));
  for (size_t s = 0; s < ns; ++s) {
    const int g = nodes[s];
    std::copy(&surf_buf_[6 * s], &surf_buf_[6 * s] + 3, &surf_x_[3 * g]);
    std::copy(&surf_buf_[6 * s + 3], &surf_buf_[6 * s + 3] + 3, &surf_v_[3 * g]);
    std::fill(&surf_f_[3 * g], &surf_f_[3 * g] + 3, 0.0);
  }
  ContactBodyState me{surf_x_.data(), surf_v_.data(), surf_m_.data(), surf_f_.data()};
  if (scene_) {
    if (scene_owner_->scene_pending_) scene_owner_->configure_scene();
    try {
      scene_->evaluate_body(scene_index_, {me}, step, dt);
    } catch (const std::runtime_error& e) {
      fail(prefix() + e.what());
    }
  } else if (host_.rank == 0) { // no set_partners (unit tests): rank 0 takes every node
    self_contact_.evaluate(surface_, me, surface_, me, true, dt);
    if (spec_->contact_edges) self_edges_.evaluate(surface_, me, surface_, me, true, dt);
  }
  surf_buf_.resize(3 * ns);
  for (size_t s = 0; s < ns; ++s)
    std::copy(&surf_f_[3 * nodes[s]], &surf_f_[3 * nodes[s]] + 3, &surf_buf_[3 * s]);
  host_.sum(surf_buf_.data(), static_cast<int>(3 * ns));
  double* f = body_.contact_forces();
  for (size_t s = 0; s < ns; ++s)
    if (surf_owned_[s])
      for (int d = 0; d < 3; ++d)
        f[3 * surf_local_[s] + d] += surf_buf_[3 * s + d];
}

} // namespace fracdem
