// BodyDriver's contact of a distributed body's own pieces: the whole surface's topology on every
// rank, the state of the partner parts' surface nodes by neighbour messages each host step
// (body/piece_ghosts.h; docs/distributed_bodies.md, "Contact of the pieces").
#include "body/body_driver.h"

#include <algorithm>
#include <cstdio>

namespace fracdem
{

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
// free nodes), after the contact state's gathering (gather_piece_state); the surface boxes are
// exchanged next.
void BodyDriver::build_part_surface()
{
  part_surface_due_ = false;
  gather_piece_state(); // the evaluating ranks may change with the parts
  const GlobalSurface& whole = ghosts_.surface();
  const int ng = global_nodes_;
  const std::vector<int> local_node = local_of_global(part_.global_node, ng);
  int ge = 0;
  for (int e : part_.global_elem)
    ge = std::max(ge, e + 1);
  const std::vector<int> local_elem = local_of_global(part_.global_elem, ge);
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
  surf_owned_.assign(nodes.size(), 0);
  std::vector<double> m(nodes.size(), 0.0);
  for (size_t s = 0; s < nodes.size(); ++s) {
    const int n = local_node[nodes[s]];
    surf_owned_[s] = n >= 0 && part_.owns(n) ? 1 : 0;
    if (surf_owned_[s]) m[s] = body_.masses()[n];
  }
  host_.sum(m.data(), static_cast<int>(m.size()));
  // Nodes not known this step sit at their last known position (at first: their reference one;
  // the pieces' searches take known nodes only, the D-R pairs' on rank 0 the whole surface).
  surf_x_ = std::move(X);
  surf_v_.assign(3 * static_cast<size_t>(ng), 0.0);
  surf_f_.assign(3 * static_cast<size_t>(ng), 0.0);
  surf_m_.assign(ng, 0.0);
  for (size_t s = 0; s < nodes.size(); ++s)
    surf_m_[nodes[s]] = m[s];
  pieces_.init(surface_, whole.part, part_);
  piece_boxes_due_ = true;
}

// Every rank gets the pieces' whole contact state, each contact's from the rank that evaluated
// it (node to facet: the node's owner; edge pairs: the ranks' records gathered on rank 0 and
// sent back): before the parts change (build_part_surface) and before a restart record is
// written. Entered by every rank; nothing to do while every rank holds the same state (set-up,
// a restart read, the last gathering).
void BodyDriver::gather_piece_state()
{
  if (!piece_state_spread_) return;
  piece_state_spread_ = false;
  const std::vector<int>& nodes = surface_.nodes;
  std::vector<double> buf(3 * nodes.size());
  self_contact_.export_state(
      nodes, [&](size_t s) { return surf_owned_[s] != 0; }, buf.data());
  host_.sum(buf.data(), static_cast<int>(buf.size()));
  self_contact_.import_state(nodes, buf.data());
  if (!spec_->contact_edges) return;
  std::vector<double> pairs;
  self_edges_.pack_state(pairs);
  pairs = host_.gather ? host_.gather(pairs) : pairs;
  pairs = host_.scatter ? host_.scatter([&](int) { return pairs; }) : pairs;
  try {
    self_edges_.unpack_state(pairs.data(), pairs.size());
  } catch (const std::exception& e) {
    fail(prefix() + e.what());
  }
}

// Each host step, no collective here: the part's surface nodes' positions and velocities to the
// partner parts (those whose surface boxes met this one's at the last exchange: set-up, a
// topology change, a host re-neighbouring, or a part's surface leaving its box), theirs received
// into the replica, this rank's contacts evaluated (piece_ghosts.h: node to facet on the node's
// owner, edge pairs on the part of the lower edge's first facet), the forces of other parts' nodes
// sent back to them; the shared-node sum of the contact forces follows (distributed_forces).
void BodyDriver::distributed_body_contacts(std::int64_t, double dt)
{
  if (part_surface_due_) build_part_surface();
  const double* x = body_.positions().data();
  const double* v = body_.velocities().data();
  if (piece_boxes_due_) {
    const std::vector<double> box = pieces_.local_box(x, piece_travel() + surface_.max_reach);
    pieces_.set_boxes(host_.all_gather ? host_.all_gather(box) : box);
    piece_boxes_due_ = false;
  }
  const std::vector<int>& partners = pieces_.partners();
  pieces_.outgoing(x, v, piece_out_);
  if (!partners.empty()) host_.exchange(2, partners, piece_out_, partners, piece_in_);
  pieces_.take(piece_in_, x, v, surf_x_.data(), surf_v_.data(), surf_f_.data());
  ContactBodyState me{surf_x_.data(), surf_v_.data(), surf_m_.data(), surf_f_.data()};
  pieces_.evaluate(surface_, self_contact_, spec_->contact_edges ? &self_edges_ : nullptr, me, dt);
  piece_state_spread_ = true;
  pieces_.forces_back(surf_f_.data(), body_.contact_forces(), piece_back_);
  if (!partners.empty()) host_.exchange(3, partners, piece_back_, partners, piece_returned_);
  pieces_.add_returned(piece_returned_, body_.contact_forces());
}

// The search buffer as the host resolved it (by default its neighbour skin): how far a part's
// surface may move between two exchanges of the parts' boxes.
double BodyDriver::piece_travel() const
{
  return std::max({contact_.options().buffer, spec_->buffer, 0.0});
}

// 1 when this part's surface has left its box (grown by the buffer) since the boxes were
// exchanged, so a part out of reach then may be in reach now. The caller max-reduces it and
// renews every part's box at this step's contact: no pair within reach is missed, whether the
// host re-neighbours or not (an FE-only run never does).
int BodyDriver::piece_moved() const
{
  if (piece_boxes_due_ || part_surface_due_) return 0; // renewed at this step's contact anyway
  return pieces_.moved_beyond(body_.positions().data(), piece_travel()) ? 1 : 0;
}

} // namespace fracdem
