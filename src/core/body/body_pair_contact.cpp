// BodyDriver's contact between a distributed body and replicated bodies (contact_bodies yes on
// both): each part sends rank 0 its facets near the replicated body, rank 0 evaluates the pair as
// the contact scene would and sends each part the forces of its nodes back
// (docs/distributed_bodies.md, "Contact with other bodies").
#include "body/body_driver.h"

#include <algorithm>

namespace fracdem
{

namespace
{
// Message tags of the pair's two rounds (BodyHost::exchange; 0-3: facet ghosts and pieces).
constexpr int kPairRoundOut = 4, kPairRoundBack = 5;

Box grown_box(const std::vector<int>& nodes, const double* x, double grow)
{
  Box b = empty_box();
  for (int n : nodes)
    for (int d = 0; d < 3; ++d) {
      b.lo[d] = std::min(b.lo[d], x[3 * n + d]);
      b.hi[d] = std::max(b.hi[d], x[3 * n + d]);
    }
  for (int d = 0; d < 3; ++d) {
    b.lo[d] -= grow;
    b.hi[d] += grow;
  }
  return b;
}
// Candidates (sphere, box) of a search over spheres (x, y, z, radius 0 each) and boxes, sorted by
// sphere then box.
std::vector<std::pair<int, int>> candidates(const std::vector<Aabb>& boxes,
                                            const std::vector<double>& spheres, double buffer)
{
  BufferedSearch search(buffer);
  search.build(boxes, spheres.data(), static_cast<int>(spheres.size() / 4));
  return search.candidates();
}

} // namespace

// Every body with contact_bodies yes, in the host's order, where one of them is distributed (and
// there is more than one); empty otherwise. Two distributed bodies are refused.
std::vector<BodyDriver*> BodyDriver::pair_group(const std::vector<BodyDriver*>& all) const
{
  std::vector<const BodyDriver*> dist;
  for (const BodyDriver* m : all)
    if (m->distributed_) dist.push_back(m);
  if (dist.size() > 1)
    fail(dist[0]->prefix() +
         "'parallel distributed' with 'contact_bodies yes': fix fem/body " + dist[1]->id_ +
         " is 'parallel distributed' with 'contact_bodies yes' too, and the contact between two "
         "distributed bodies is not done; give one of them 'parallel replicated' (or "
         "'contact_bodies no')");
  if (dist.empty() || all.size() < 2) return {};
  return all;
}

// The distributed body lists its replicated partners (the earlier body's call evaluates a pair,
// as the scene does); a replicated body notes its distributed partner. The pairs of the same
// bodies go on with their contacts in the next run (carry_pair_state), and the group continues
// (its held contact forces are replayed at the set-up: replays_body_contacts, the distributed
// body's flag for all) where its bodies are the last run's, as the scene's rule; a second call
// without a step between (write_restart's) changes neither.
void BodyDriver::take_pair_group(const std::vector<BodyDriver*>& group)
{
  const bool same = !group.empty() && group == pair_group_;
  // A second call before a step (write_restart's init) keeps the first call's answer.
  pair_continues_ = same && (pairs_pending_ ? pair_continues_ : !pairs_.empty());
  std::vector<BodyPair> last;
  if (group == pair_group_) last.swap(pairs_); // the same bodies: their contacts go on
  pair_group_ = group;
  pairs_.clear();
  pair_body_ = nullptr;
  pair_first_ = false;
  if (group.empty()) return;
  const auto at = [&](const BodyDriver* b) {
    return std::find(group.begin(), group.end(), b) - group.begin();
  };
  BodyDriver* d = *std::find_if(group.begin(), group.end(),
                                [](const BodyDriver* b) { return b->distributed_; });
  if (d != this) {
    pair_body_ = d;
    pair_first_ = at(this) < at(d);
    return;
  }
  for (BodyDriver* m : group)
    if (m != this) {
      pairs_.emplace_back();
      pairs_.back().other = m;
      pairs_.back().other_first = at(m) < at(this);
      for (const BodyPair& p : last)
        if (p.other == m) carry_pair_state(p, pairs_.back());
    }
  if (last.empty()) take_restored_body_pairs(); // after a restart: the file's contacts
  pairs_pending_ = pair_maps_due_ = true;
}

// A pair of the last run goes on in the new one with its contacts (held on rank 0, which
// evaluates it): a split run continues them as the scene's pairs do (ContactScene::pair_state).
void BodyDriver::carry_pair_state(const BodyPair& from, BodyPair& to)
{
  unpack_pair_state(pack_pair_state(from.mine_on_other, from.other_on_mine, from.edges),
                    to.mine_on_other, to.other_on_mine, to.edges);
}

// At the first evaluation of a run (every body's friction known): the pair (a, b), a the earlier
// body, takes a's settings and friction, as the scene's pair does.
void BodyDriver::configure_pairs()
{
  pairs_pending_ = false;
  drop_restored_pairs(pair_group_);
  for (BodyPair& p : pairs_) {
    const BodyDriver& a = p.other_first ? *p.other : *this;
    const BodyDriver& b = p.other_first ? *this : *p.other;
    const int ta = a.spec_->surface_type, tb = b.spec_->surface_type;
    const SurfaceContactOptions o = a.surface_options(tb, b.spec_->material.E, a.friction_(ta, tb));
    p.mine_on_other.configure(o);
    p.other_on_mine.configure(o);
    p.edges.configure(o);
  }
}

// The pairs this body's call evaluates (every rank enters): a distributed body's with the later
// replicated bodies, a replicated body's with a later distributed one.
void BodyDriver::pair_contacts(double dt)
{
  if (distributed_) {
    for (size_t k = 0; k < pairs_.size(); ++k)
      if (!pairs_[k].other_first) evaluate_pair(k, dt);
    return;
  }
  if (!pair_body_ || !pair_first_) return;
  for (size_t k = 0; k < pair_body_->pairs_.size(); ++k)
    if (pair_body_->pairs_[k].other == this) pair_body_->evaluate_pair(k, dt);
}

// After the surface changed: global node -> part node, the part's own facets (those of its
// elements) and, on rank 0, the replica of the surface nodes near the partners (unknown ones at
// their last known positions: the edge contact's search spans the whole surface).
void BodyDriver::build_pair_maps()
{
  pair_maps_due_ = false;
  pair_local_ = local_of_global(part_.global_node, global_nodes_);
  const GlobalSurface& whole = ghosts_.surface();
  pair_own_facets_.clear();
  for (size_t k = 0; k < surface_.facets.size(); ++k)
    if (whole.part[k] == part_.part) pair_own_facets_.push_back(static_cast<int>(k));
  // The free nodes this part owns (surface nodes of no facet: every element around them eroded).
  std::vector<char> on_facet(surf_m_.size(), 0);
  for (const Facet& fc : surface_.facets)
    for (int j = 0; j < fc.nn; ++j)
      on_facet[fc.n[j]] = 1;
  pair_own_free_.clear();
  for (int g : surface_.nodes)
    if (!on_facet[g] && pair_local_[g] >= 0 && part_.owns(pair_local_[g]))
      pair_own_free_.push_back(g);
  pair_known_nodes_.clear();
  pair_known_facets_.clear();
  if (host_.rank != 0) return;
  pair_x_ = surf_x_;
  pair_v_.assign(surf_x_.size(), 0.0);
  pair_f_.assign(surf_x_.size(), 0.0);
  pair_seen_.assign(surf_m_.size(), 0);
  pair_facet_known_.assign(surface_.facets.size(), 0);
}

// This part's facets whose box meets the partner's surface box grown by `grow`, and their nodes'
// positions and velocities (with the part's free nodes in that box): [facet count, facets, then
// per node (global number, x, v)].
std::vector<double> BodyDriver::pair_message(const BodyDriver& other, double grow)
{
  const Box near = grown_box(other.surface_.nodes, other.body_.positions().data(), grow);
  const double* x = body_.positions().data();
  const double* v = body_.velocities().data();
  std::vector<double> out(1, 0.0);
  pair_sent_mine_.clear();
  for (int k : pair_own_facets_) {
    const Facet& fc = surface_.facets[k];
    Box b = empty_box();
    for (int j = 0; j < fc.nn; ++j)
      for (int d = 0; d < 3; ++d) {
        const double q = x[3 * pair_local_[fc.n[j]] + d];
        b.lo[d] = std::min(b.lo[d], q);
        b.hi[d] = std::max(b.hi[d], q);
      }
    if (!boxes_overlap(b, near)) continue;
    out.push_back(k);
    pair_sent_mine_.insert(pair_sent_mine_.end(), fc.n.begin(), fc.n.begin() + fc.nn);
  }
  out[0] = static_cast<double>(out.size() - 1);
  for (int g : pair_own_free_) {
    const double* q = &x[3 * pair_local_[g]];
    bool in = true;
    for (int d = 0; d < 3; ++d)
      in = in && q[d] >= near.lo[d] && q[d] <= near.hi[d];
    if (in) pair_sent_mine_.push_back(g);
  }
  std::sort(pair_sent_mine_.begin(), pair_sent_mine_.end());
  pair_sent_mine_.erase(std::unique(pair_sent_mine_.begin(), pair_sent_mine_.end()),
                        pair_sent_mine_.end());
  for (int g : pair_sent_mine_) {
    const int n = pair_local_[g];
    out.push_back(g);
    out.insert(out.end(), &x[3 * n], &x[3 * n] + 3);
    out.insert(out.end(), &v[3 * n], &v[3 * n] + 3);
  }
  return out;
}

// Rank 0: the parts' messages (in rank order) into the replica; each node's force goes back to
// the lowest rank that sent it (sharers hold the same bits of a shared node).
void BodyDriver::gather_pair_nodes(const std::vector<std::vector<double>>& in)
{
  for (int g : pair_known_nodes_)
    pair_seen_[g] = 0;
  for (int k : pair_known_facets_)
    pair_facet_known_[k] = 0;
  pair_known_nodes_.clear();
  pair_known_facets_.clear();
  pair_sent_.assign(in.size(), {});
  pair_route_.assign(in.size(), {});
  for (size_t r = 0; r < in.size(); ++r) {
    const std::vector<double>& m = in[r];
    const size_t nf = static_cast<size_t>(m[0]);
    for (size_t i = 0; i < nf; ++i)
      pair_known_facets_.push_back(static_cast<int>(m[1 + i]));
    for (size_t at = 1 + nf; at + 6 < m.size(); at += 7) {
      const int g = static_cast<int>(m[at]);
      pair_sent_[r].push_back(g);
      pair_route_[r].push_back(pair_seen_[g] ? 0 : 1);
      if (pair_seen_[g]) continue;
      pair_seen_[g] = 1;
      pair_known_nodes_.push_back(g);
      std::copy(&m[at + 1], &m[at + 4], &pair_x_[3 * static_cast<size_t>(g)]);
      std::copy(&m[at + 4], &m[at + 7], &pair_v_[3 * static_cast<size_t>(g)]);
    }
  }
  std::sort(pair_known_nodes_.begin(), pair_known_nodes_.end());
  std::sort(pair_known_facets_.begin(), pair_known_facets_.end());
  for (int k : pair_known_facets_)
    pair_facet_known_[k] = 1;
  for (int g : pair_known_nodes_)
    std::fill(&pair_f_[3 * static_cast<size_t>(g)], &pair_f_[3 * static_cast<size_t>(g)] + 3, 0.0);
}

// Rank 0: the pair (this body, pairs_[k].other) on the replica: the known nodes on the partner's
// facets and the partner's surface nodes on the known facets (a search of each, rebuilt every
// step, buffer twice the deeper surface's reach as the scene's), the earlier body's nodes first,
// then edge to edge where both bodies take it (the earlier body's edges as the scene's A side).
// The partner's forces go to other_f; per rank, the forces of the nodes it sent.
std::vector<std::vector<double>> BodyDriver::resolve_pair(size_t k, double dt, double* other_f)
{
  BodyPair& p = pairs_[k];
  const BodyDriver& o = *p.other;
  const ContactSurface& os = o.surface_;
  const double* ox = o.body_.positions().data();
  const ContactBodyState me{pair_x_.data(), pair_v_.data(), surf_m_.data(), pair_f_.data()};
  const ContactBodyState them{ox, o.body_.velocities().data(), o.body_.masses().data(), other_f};
  const double buffer = 2 * std::max(surface_.max_reach, os.max_reach);
  // Known nodes on the partner's facets; surface indices ascending with the global numbers.
  std::vector<Aabb> boxes(os.facets.size());
  for (size_t f = 0; f < os.facets.size(); ++f)
    boxes[f] = node_box(os.facets[f].n.data(), os.facets[f].nn, ox);
  std::vector<double> spheres(4 * pair_known_nodes_.size(), 0.0);
  for (size_t i = 0; i < pair_known_nodes_.size(); ++i)
    std::copy(&pair_x_[3 * static_cast<size_t>(pair_known_nodes_[i])],
              &pair_x_[3 * static_cast<size_t>(pair_known_nodes_[i])] + 3, &spheres[4 * i]);
  std::vector<std::pair<int, int>> mine_cand = candidates(boxes, spheres, buffer);
  for (auto& c : mine_cand)
    c.first = static_cast<int>(std::lower_bound(surface_.nodes.begin(), surface_.nodes.end(),
                                                pair_known_nodes_[c.first]) -
                               surface_.nodes.begin());
  // The partner's surface nodes on the known facets.
  boxes.resize(pair_known_facets_.size());
  for (size_t j = 0; j < pair_known_facets_.size(); ++j) {
    const Facet& fc = surface_.facets[pair_known_facets_[j]];
    boxes[j] = node_box(fc.n.data(), fc.nn, pair_x_.data());
  }
  spheres.assign(4 * os.nodes.size(), 0.0);
  for (size_t s = 0; s < os.nodes.size(); ++s)
    std::copy(&ox[3 * os.nodes[s]], &ox[3 * os.nodes[s]] + 3, &spheres[4 * s]);
  std::vector<std::pair<int, int>> their_cand = candidates(boxes, spheres, buffer);
  for (auto& c : their_cand)
    c.second = pair_known_facets_[c.second];
  const auto mine_on_other = [&] {
    p.mine_on_other.resolve(surface_, me, os, them, false, dt, mine_cand.data(), mine_cand.size());
  };
  const auto other_on_mine = [&] {
    p.other_on_mine.resolve(os, them, surface_, me, false, dt, their_cand.data(),
                            their_cand.size());
  };
  if (p.other_first) {
    other_on_mine();
    mine_on_other();
  } else {
    mine_on_other();
    other_on_mine();
  }
  if (spec_->contact_edges && o.spec_->contact_edges) {
    // A pair of edges is evaluated where both facets of this body's edge are known.
    const auto known = [&](int e) {
      return pair_facet_known_[surface_.edges[e].facet[0]] &&
             pair_facet_known_[surface_.edges[e].facet[1]];
    };
    if (p.other_first)
      p.edges.evaluate(os, them, surface_, me, false, dt, [&](int, int f) { return known(f); });
    else
      p.edges.evaluate(surface_, me, os, them, false, dt, [&](int e, int) { return known(e); });
  }
  return routed_forces(pair_sent_, pair_route_, pair_f_.data());
}

// The forces of the nodes this part sent (3 per node, pair_message order) into f (part nodes).
void BodyDriver::add_pair_forces(const std::vector<double>& back, double* f) const
{
  for (size_t i = 0; i < pair_sent_mine_.size() && 3 * i + 2 < back.size(); ++i) {
    const int n = pair_local_[pair_sent_mine_[i]];
    for (int d = 0; d < 3; ++d)
      f[3 * n + d] += back[3 * i + d];
  }
}

// One pair, every rank alike: the parts' facets near the partner to rank 0 (one message per rank,
// no collective), evaluated there, the forces back (one message per rank). This body's forces go
// to its part's contact forces, or, where the partner's call evaluates (it comes first), to its
// pending ones; the partner's likewise (rank 0's share: the partner sums its contact forces over
// the ranks as it does the scene's).
void BodyDriver::evaluate_pair(size_t k, double dt)
{
  if (part_surface_due_) build_part_surface();
  if (pair_maps_due_) build_pair_maps();
  if (pairs_pending_) configure_pairs();
  BodyPair& p = pairs_[k];
  Body& ob = p.other->body_;
  double* other_f = p.other_first ? ob.contact_forces() : ob.pending_contact_forces();
  double* f = p.other_first ? body_.pending_contact_forces() : body_.contact_forces();
  const double grow = 2 * std::max(surface_.max_reach, p.other->surface_.max_reach);
  std::vector<std::vector<double>> mine(1, pair_message(*p.other, grow));
  std::vector<int> ranks;
  for (int r = 1; r < host_.nprocs; ++r)
    ranks.push_back(r);
  const std::vector<int> root(1, 0), none;
  if (host_.rank == 0) {
    if (!ranks.empty()) host_.exchange(kPairRoundOut, none, {}, ranks, pair_in_);
    pair_in_.insert(pair_in_.begin(), mine[0]);
    gather_pair_nodes(pair_in_);
    pair_out_ = resolve_pair(k, dt, other_f);
    add_pair_forces(pair_out_[0], f);
    pair_out_.erase(pair_out_.begin());
    if (!ranks.empty()) host_.exchange(kPairRoundBack, ranks, pair_out_, none, pair_in_);
  } else {
    host_.exchange(kPairRoundOut, root, mine, none, pair_in_);
    host_.exchange(kPairRoundBack, none, {}, root, pair_in_);
    add_pair_forces(pair_in_[0], f);
  }
}

} // namespace fracdem
