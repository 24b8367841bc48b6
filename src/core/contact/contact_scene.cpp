// One search over all bodies' surfaces; each surface node's contacts evaluated on its part.
#include "contact/contact_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "balance/graph_partition.h"

namespace fracdem
{

namespace
{
std::string fmt(const char* f, double a)
{
  char buf[64];
  std::snprintf(buf, sizeof buf, f, a);
  return buf;
}
} // namespace

ContactScene::~ContactScene()
{
  if (csv_) std::fclose(csv_);
}

void ContactScene::configure(std::vector<SceneMember> members,
                             std::vector<SurfaceContactOptions> pair_options,
                             const ContactBalance& balance, SceneComm comm)
{
  members_ = std::move(members);
  pair_options_ = std::move(pair_options);
  balance_ = balance;
  comm_ = std::move(comm);
  if (!comm_.sum) comm_.sum = [](double*, int) {};
  model_parts_ = comm_.nprocs == 1 && balance_.parts > 1;
  nparts_ = model_parts_ ? balance_.parts : std::max(comm_.nprocs, 1);
  part_ = model_parts_ ? 0 : comm_.rank;
  const int n = size();
  pairs_.assign(2 * static_cast<size_t>(n * (n - 1) / 2), SurfaceContact());
  edge_pairs_.assign(static_cast<size_t>(n * (n - 1) / 2), EdgeContact());
  for (int b = 1; b < n; ++b)
    for (int a = 0; a < b; ++a) {
      const int p = pair_index(a, b);
      pairs_[2 * p].configure(pair_options_.at(p));
      pairs_[2 * p + 1].configure(pair_options_.at(p));
      edge_pairs_[p].configure(pair_options_.at(p));
    }
  mesh_owner_.assign(n, {});
  owner_.clear();
  carried_.assign(3 * static_cast<size_t>(nparts_), 0.0);
  booked_.assign(nparts_, 0.0);
  weights_window_.clear();
  numbered_.clear();
  stale_ = true;
  searched_step_ = last_check_ = INT64_MIN;
  if (csv_) std::fclose(csv_);
  csv_ = nullptr;
  if (!balance_.file.empty() && comm_.rank == 0) {
    csv_ = std::fopen(balance_.file.c_str(), "w");
    if (!csv_)
      throw std::runtime_error("keyword 'contact_balance': cannot open '" + balance_.file +
                               "' for writing");
    std::fputs("step,imbalance,repartitions,predicted_imbalance,searches", csv_);
    for (const char* what : {"work", "tests", "contacts"})
      for (int p = 0; p < nparts_; ++p)
        std::fprintf(csv_, ",%s_%d", what, p);
    std::fputc('\n', csv_);
  }
}

int ContactScene::pair_part(int a, int b) const
{
  const int k = a == b ? a : pair_index(std::min(a, b), std::max(a, b));
  return k % nparts_;
}

// Scene numbering from the members' surfaces; owners carried over by mesh node (-1: new).
void ContactScene::renumber()
{
  const int n = size();
  const std::vector<int> old_off = node_off_;
  fold_window();
  node_off_.assign(n + 1, 0);
  facet_off_.assign(n + 1, 0);
  reach_ = 0;
  for (int m = 0; m < n; ++m) {
    const ContactSurface& s = *members_[m].surface;
    node_off_[m + 1] = node_off_[m] + static_cast<int>(s.nodes.size());
    facet_off_[m + 1] = facet_off_[m] + static_cast<int>(s.facets.size());
    reach_ = std::max(reach_, s.max_reach);
  }
  buffer_ = 2 * reach_;
  owner_.assign(node_off_[n], nparts_ == 1 ? 0 : -1);
  if (nparts_ > 1)
    for (int m = 0; m < n; ++m) {
      const std::vector<int>& nodes = members_[m].surface->nodes;
      const std::vector<int>& known = mesh_owner_[m];
      for (size_t s = 0; s < nodes.size(); ++s)
        if (static_cast<size_t>(nodes[s]) < known.size())
          owner_[node_off_[m] + s] = known[nodes[s]];
    }
  carry_weights(old_off);
  win_tests_.assign(node_off_[n], 0.0);
  win_contacts_.assign(node_off_[n], 0.0);
}

// A topology change of one member renumbers the scene in the middle of a step, after the earlier
// members' evaluation: their work since the last check stays booked to the parts that did it
// (carried_), and stays in the recorded work of its nodes for the a posteriori weights
// (weights_window_).
void ContactScene::fold_window()
{
  carried_.resize(3 * static_cast<size_t>(nparts_), 0.0);
  weights_window_.resize(win_tests_.size(), 0.0);
  for (size_t g = 0; g < owner_.size() && g < win_tests_.size(); ++g) {
    const int p = owner_[g] < 0 ? 0 : owner_[g];
    carried_[p] += win_tests_[g] + win_contacts_[g];
    carried_[nparts_ + p] += win_tests_[g];
    carried_[2 * nparts_ + p] += win_contacts_[g];
    weights_window_[g] += win_tests_[g] + win_contacts_[g];
  }
}

// weights_window_ from the numbering of old_off / numbered_ (the members' node lists then) to the
// current one, by mesh node (mesh nodes keep their index through splits and erosion).
void ContactScene::carry_weights(const std::vector<int>& old_off)
{
  const int n = size();
  std::vector<double> carried(node_off_[n], 0.0);
  if (numbered_.size() == static_cast<size_t>(n) && old_off.size() == static_cast<size_t>(n + 1))
    for (int m = 0; m < n; ++m) {
      const std::vector<int>& before = numbered_[m];
      std::vector<double> by_mesh(before.empty() ? 0 : before.back() + 1, 0.0);
      for (size_t s = 0; s < before.size(); ++s)
        if (old_off[m] + s < weights_window_.size())
          by_mesh[before[s]] = weights_window_[old_off[m] + s];
      const std::vector<int>& nodes = members_[m].surface->nodes;
      for (size_t s = 0; s < nodes.size(); ++s)
        if (static_cast<size_t>(nodes[s]) < by_mesh.size())
          carried[node_off_[m] + s] = by_mesh[nodes[s]];
    }
  weights_window_ = std::move(carried);
  numbered_.resize(n);
  for (int m = 0; m < n; ++m)
    numbered_[m] = members_[m].surface->nodes;
}

void ContactScene::gather_positions(const std::vector<ContactBodyState>& states)
{
  sx_.resize(3 * static_cast<size_t>(node_off_.back()));
  for (int m = 0; m < size(); ++m) {
    const std::vector<int>& nodes = members_[m].surface->nodes;
    double* out = &sx_[3 * static_cast<size_t>(node_off_[m])];
    for (size_t s = 0; s < nodes.size(); ++s)
      for (int d = 0; d < 3; ++d)
        out[3 * s + d] = states[m].x[3 * nodes[s] + d];
  }
}

// A contact up to reach deep is a node within reach of its facet's box (per axis). Boxes and
// nodes are inflated by reach each, so the search holds every such pair as long as the node and
// the facet's nodes approached by at most reach since: each moved by at most half of it (paper
// eqs. 1-2 with l_buff = reach / 2).
bool ContactScene::search_due() const
{
  return 2 * search_.node_travel(sx_.data(), node_off_.back()) > reach_;
}

void ContactScene::search(const std::vector<ContactBodyState>& states)
{
  const int n = size(), nn = node_off_[n];
  std::vector<Aabb> boxes(facet_off_[n]);
  for (int m = 0; m < n; ++m) {
    const ContactSurface& s = *members_[m].surface;
    for (size_t k = 0; k < s.facets.size(); ++k)
      boxes[facet_off_[m] + k] = node_box(s.facets[k].n.data(), s.facets[k].nn, states[m].x);
  }
  std::vector<double> spheres(4 * static_cast<size_t>(nn), 0.0);
  for (int g = 0; g < nn; ++g)
    std::copy(&sx_[3 * g], &sx_[3 * g] + 3, &spheres[4 * g]);
  search_ = BufferedSearch(buffer_);
  search_.build(boxes, spheres.data(), nn);
  search_.remember_positions(sx_.data(), nn, sx_.data(), nn);
  ++searches_;
  // Grouped by ordered pair (node's member, facet's member), order kept within each group.
  const auto& all = search_.candidates();
  std::vector<int> key(all.size());
  cand_off_.assign(static_cast<size_t>(n) * n + 1, 0);
  for (size_t c = 0; c < all.size(); ++c) {
    const int a = static_cast<int>(
        std::upper_bound(node_off_.begin(), node_off_.end(), all[c].first) - node_off_.begin() - 1);
    const int b =
        static_cast<int>(std::upper_bound(facet_off_.begin(), facet_off_.end(), all[c].second) -
                         facet_off_.begin() - 1);
    key[c] = a * n + b;
    ++cand_off_[key[c] + 1];
  }
  for (size_t k = 0; k + 1 < cand_off_.size(); ++k)
    cand_off_[k + 1] += cand_off_[k];
  cand_.resize(all.size());
  std::vector<size_t> fill(cand_off_.begin(), cand_off_.end() - 1);
  for (size_t c = 0; c < all.size(); ++c) {
    const int a = key[c] / n, b = key[c] % n;
    cand_[fill[key[c]]++] = {all[c].first - node_off_[a], all[c].second - facet_off_[b]};
  }
  if (nparts_ == 1) return;
  const bool unowned = std::find(owner_.begin(), owner_.end(), -1) != owner_.end();
  if (unowned)
    repartition(apriori_weights(), -1, "new surface nodes", 0);
  else if (balance_.model == ContactBalance::APriori)
    repartition(apriori_weights(), -1, "a priori, after the search", 0);
}

std::vector<std::pair<int, int>> ContactScene::candidates(int a, int b) const
{
  if (cand_off_.empty()) return {};
  const size_t k = static_cast<size_t>(a) * size() + b;
  return {cand_.begin() + cand_off_[k], cand_.begin() + cand_off_[k + 1]};
}

// The paper's a priori weights: each node's potential targets (its candidates), at least 1.
std::vector<double> ContactScene::apriori_weights() const
{
  std::vector<double> w(node_off_.back(), 1.0);
  for (const auto& c : search_.candidates()) // scene node numbers
    w[c.first] += 1.0;
  return w;
}

int ContactScene::evaluate_body(int i, const std::vector<ContactBodyState>& states,
                                std::int64_t step, double dt)
{
  if (stale_) {
    for (EdgeContact& ec : edge_pairs_)
      ec.invalidate();
    renumber();
    gather_positions(states);
    search(states);
    stale_ = false;
    searched_step_ = step;
  } else if (step != searched_step_) {
    gather_positions(states);
    if (search_due()) search(states);
    searched_step_ = step;
  }
  int contacts = 0;
  if (members_[i].self) contacts += resolve(i, i, states, dt);
  contacts += resolve_edges(i, i, states, dt);
  for (int j = i + 1; j < size(); ++j) {
    contacts += resolve(i, j, states, dt);
    contacts += resolve(j, i, states, dt);
    contacts += resolve_edges(i, j, states, dt);
  }
  if (i == size() - 1 && balance_.every > 0 && step % balance_.every == 0 && step != last_check_)
    check_balance(step);
  return contacts;
}

// Edge to edge between a and b (a <= b; a == b: a's own pieces) where both take it: evaluated
// on every rank (the same per-pair state everywhere), the forces added on pair_part(a, b) only.
int ContactScene::resolve_edges(int a, int b, const std::vector<ContactBodyState>& states,
                                double dt)
{
  if (!members_[a].edges || !members_[b].edges) return 0;
  const bool mine = evaluates_all() || pair_part(a, b) == part_;
  ContactBodyState sa = states[a], sb = states[b];
  if (!mine) sa.f = sb.f = nullptr;
  EdgeContact& ec = a == b ? *members_[a].edges : edge_pairs_[pair_index(a, b)];
  const int n = ec.evaluate(*members_[a].surface, sa, *members_[b].surface, sb, a == b, dt);
  return mine ? n : 0;
}

// The nodes of a on the facets of b (a == b: a's own pieces).
int ContactScene::resolve(int a, int b, const std::vector<ContactBodyState>& states, double dt)
{
  SurfaceContact& sc = a == b  ? *members_[a].self
                       : a < b ? pairs_[2 * pair_index(a, b)]
                               : pairs_[2 * pair_index(b, a) + 1];
  const size_t k = static_cast<size_t>(a) * size() + b;
  const size_t first = cand_off_[k], count = cand_off_[k + 1] - first;
  const int off = node_off_[a];
  const SurfaceContact::Counts c =
      sc.resolve(*members_[a].surface, states[a], *members_[b].surface, states[b], a == b, dt,
                 cand_.data() + first, count, evaluates_all() ? nullptr : owner_.data() + off,
                 part_, win_tests_.data() + off, win_contacts_.data() + off);
  total_tests_ += c.tests;
  total_contacts_ += c.contacts;
  return static_cast<int>(c.contacts);
}

// B = max / mean of the parts' work since the last check (tests + contacts, counted); above
// thresh the a posteriori model partitions again by the recorded work of each node.
void ContactScene::check_balance(std::int64_t step)
{
  last_check_ = step;
  const int nn = node_off_.back();
  std::vector<double> per(3 * static_cast<size_t>(nparts_), 0.0);
  for (int g = 0; g < nn; ++g) {
    const int p = owner_[g] < 0 ? 0 : owner_[g];
    per[p] += win_tests_[g] + win_contacts_[g];
    per[nparts_ + p] += win_tests_[g];
    per[2 * nparts_ + p] += win_contacts_[g];
  }
  carried_.resize(per.size(), 0.0);
  for (size_t k = 0; k < per.size(); ++k)
    per[k] += carried_[k];
  std::fill(carried_.begin(), carried_.end(), 0.0);
  comm_.sum(per.data(), static_cast<int>(per.size()));
  const std::vector<double> work(per.begin(), per.begin() + nparts_);
  booked_.resize(nparts_, 0.0);
  for (int p = 0; p < nparts_; ++p)
    booked_[p] += work[p];
  last_b_ = balance::imbalance(work);
  if (csv_) {
    std::fprintf(csv_, "%lld,%.6f,%ld,%.6f,%ld", static_cast<long long>(step), last_b_,
                 repartitions_, predicted_b_, searches_);
    for (double v : per)
      std::fprintf(csv_, ",%.0f", v);
    std::fputc('\n', csv_);
    std::fflush(csv_);
  }
  if (nparts_ > 1 && balance_.model == ContactBalance::APosteriori && last_b_ > balance_.thresh) {
    std::vector<double> w(nn);
    for (int g = 0; g < nn; ++g)
      w[g] = win_tests_[g] + win_contacts_[g] + weights_window_[g];
    if (!evaluates_all()) comm_.sum(w.data(), nn);
    for (double& x : w)
      x = std::max(x, 1.0);
    repartition(w, step, "a posteriori", last_b_);
  }
  std::fill(win_tests_.begin(), win_tests_.end(), 0.0);
  std::fill(win_contacts_.begin(), win_contacts_.end(), 0.0);
  std::fill(weights_window_.begin(), weights_window_.end(), 0.0);
}

// METIS parts of the graph of surface nodes (edges: a candidate node to its facet's nodes),
// relabelled to move as few nodes as possible; the moved nodes' contact state goes with them.
void ContactScene::repartition(const std::vector<double>& weights, std::int64_t step,
                               const char* why, double measured)
{
  const int n = size(), nn = node_off_[n];
  std::vector<balance::WeightedPair> pairs;
  pairs.reserve(3 * cand_.size());
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const size_t k = static_cast<size_t>(a) * n + b;
      const ContactSurface& sb = *members_[b].surface;
      for (size_t c = cand_off_[k]; c < cand_off_[k + 1]; ++c) {
        const Facet& fc = sb.facets[cand_[c].second];
        for (int j = 0; j < fc.nn; ++j) {
          const int s = static_cast<int>(
              std::lower_bound(sb.nodes.begin(), sb.nodes.end(), fc.n[j]) - sb.nodes.begin());
          pairs.push_back({node_off_[a] + cand_[c].first, node_off_[b] + s, 1});
        }
      }
    }
  std::vector<int64_t> vw(nn);
  for (int g = 0; g < nn; ++g)
    vw[g] = std::max<int64_t>(1, std::llround(weights[g]));
  // Parts within half the trigger's margin (1 % at most), so that the next check finds the new
  // parts below the trigger: METIS k-way, then diffusion where it left a part above that.
  const double ub = std::clamp(1 + 0.5 * (balance_.thresh - 1), 1.001, 1.01);
  std::vector<int> part;
  try {
    const balance::Graph graph = balance::build_graph(nn, vw, pairs);
    part = balance::partition_kway(graph, nparts_, ub);
    if (balance::imbalance(balance::part_loads(weights, part, nparts_)) > ub)
      balance::refine_partition(graph, part, nparts_, ub);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("contact scene: graph partitioning failed: ") + e.what());
  }
  part = balance::relabel_max_overlap(part, owner_, std::vector<double>(nn, 1.0), nparts_);
  const std::vector<int> old = owner_;
  owner_ = part;
  int moved = 0;
  for (int g = 0; g < nn; ++g)
    moved += old[g] >= 0 && old[g] != part[g] ? 1 : 0;
  for (int m = 0; m < n; ++m) {
    const std::vector<int>& nodes = members_[m].surface->nodes;
    std::vector<int>& known = mesh_owner_[m];
    known.assign(nodes.empty() ? 0 : nodes.back() + 1, -1);
    for (size_t s = 0; s < nodes.size(); ++s)
      known[nodes[s]] = owner_[node_off_[m] + s];
  }
  predicted_b_ = balance::imbalance(balance::part_loads(weights, part, nparts_));
  ++repartitions_;
  if (!evaluates_all()) move_contact_state(old);
  if (comm_.print && step >= 0)
    comm_.print("contact scene: step " + std::to_string(step) + ": repartitioned (" + why +
                fmt(", B = %.3f", measured) + fmt(" > %g", balance_.thresh) + ") into " +
                std::to_string(nparts_) + " parts of " + std::to_string(nn) + " surface nodes" +
                fmt(": predicted B %.3f, ", predicted_b_) + std::to_string(moved) +
                " nodes moved\n");
}

// Every contact object's state, each node's from its old owner (new nodes have none), summed
// into every rank: each part then continues the contacts of the nodes it now owns.
void ContactScene::move_contact_state(const std::vector<int>& old)
{
  const int n = size();
  std::vector<std::pair<SurfaceContact*, int>> objects; // (object, member of its nodes)
  for (int m = 0; m < n; ++m)
    if (members_[m].self) objects.push_back({members_[m].self, m});
  for (int b = 1; b < n; ++b)
    for (int a = 0; a < b; ++a) {
      objects.push_back({&pairs_[2 * pair_index(a, b)], a});
      objects.push_back({&pairs_[2 * pair_index(a, b) + 1], b});
    }
  std::vector<double> buf;
  for (const auto& [sc, m] : objects) {
    const std::vector<int>& nodes = members_[m].surface->nodes;
    const size_t at = buf.size();
    buf.resize(at + 3 * nodes.size());
    const int off = node_off_[m];
    // A node without an owner has the same state on every rank (restart, or none): rank 0's.
    sc->export_state(
        nodes, [&](size_t s) { return old[off + s] < 0 ? part_ == 0 : old[off + s] == part_; },
        &buf[at]);
  }
  comm_.sum(buf.data(), static_cast<int>(buf.size()));
  size_t at = 0;
  for (const auto& [sc, m] : objects) {
    sc->import_state(members_[m].surface->nodes, &buf[at]);
    at += 3 * members_[m].surface->nodes.size();
  }
}

void ContactScene::gather_self_state(int i)
{
  SurfaceContact* sc = members_[i].self;
  if (evaluates_all() || !sc) return;
  const std::vector<int>& nodes = members_[i].surface->nodes;
  const std::vector<int>& known = mesh_owner_[i];
  std::vector<double> buf(3 * nodes.size());
  // Before any partition (or for a node not yet owned) every rank holds the same state: rank 0's.
  sc->export_state(
      nodes,
      [&](size_t s) {
        const size_t node = static_cast<size_t>(nodes[s]);
        const int o = node < known.size() ? known[node] : -1;
        return o < 0 ? part_ == 0 : o == part_;
      },
      buf.data());
  comm_.sum(buf.data(), static_cast<int>(buf.size()));
  sc->import_state(nodes, buf.data());
}

namespace
{
template <class Contact>
void put_state(const Contact& c, std::size_t width, std::vector<double>& out)
{
  std::vector<double> state;
  c.pack_state(state);
  out.push_back(static_cast<double>(state.size() / width));
  out.insert(out.end(), state.begin(), state.end());
}

template <class Contact>
void take_state(Contact& c, std::size_t width, const std::vector<double>& in, std::size_t& at)
{
  if (at >= in.size()) throw std::runtime_error("contact scene: short pair state");
  const std::size_t len = width * static_cast<std::size_t>(in[at++]);
  if (at + len > in.size()) throw std::runtime_error("contact scene: short pair state");
  c.unpack_state(in.data() + at, len);
  at += len;
}
} // namespace

std::vector<double> ContactScene::pair_state(int a, int b) const
{
  std::vector<double> out;
  const int p = pair_index(a, b);
  for (int dir = 0; dir < 2; ++dir) {
    const int m = dir == 0 ? a : b; // whose nodes
    const std::vector<int>& nodes = members_[m].surface->nodes;
    const std::vector<int>& known = mesh_owner_[m];
    std::vector<double> buf(3 * nodes.size());
    // As gather_self_state: each node's state from its owner (rank 0's before a partition).
    pairs_[2 * p + dir].export_state(
        nodes,
        [&](size_t s) {
          if (evaluates_all()) return true;
          const size_t node = static_cast<size_t>(nodes[s]);
          const int o = node < known.size() ? known[node] : -1;
          return o < 0 ? part_ == 0 : o == part_;
        },
        buf.data());
    if (!evaluates_all()) comm_.sum(buf.data(), static_cast<int>(buf.size()));
    const std::size_t count_at = out.size();
    out.push_back(0);
    for (std::size_t s = 0; s < nodes.size(); ++s)
      if (buf[3 * s] > 0.5) {
        out.insert(out.end(), {static_cast<double>(nodes[s]), buf[3 * s + 1], buf[3 * s + 2]});
        out[count_at] += 1;
      }
  }
  put_state(edge_pairs_[p], 6, out); // evaluated on every rank alike: every rank holds it whole
  return out;
}

void ContactScene::restore_pair_state(int a, int b, const std::vector<double>& state)
{
  const int p = pair_index(a, b);
  unpack_pair_state(state, pairs_[2 * p], pairs_[2 * p + 1], edge_pairs_[p]);
}


std::vector<double> pack_pair_state(const SurfaceContact& a_on_b, const SurfaceContact& b_on_a,
                                    const EdgeContact& edges)
{
  std::vector<double> out;
  put_state(a_on_b, 3, out);
  put_state(b_on_a, 3, out);
  put_state(edges, 6, out);
  return out;
}

void unpack_pair_state(const std::vector<double>& state, SurfaceContact& a_on_b,
                       SurfaceContact& b_on_a, EdgeContact& edges)
{
  std::size_t at = 0;
  take_state(a_on_b, 3, state, at);
  take_state(b_on_a, 3, state, at);
  take_state(edges, 6, state, at);
  if (at != state.size()) throw std::runtime_error("contact scene: corrupt pair state");
}

} // namespace fracdem
