// The contact of a distributed body's pieces by neighbour messages (see piece_ghosts.h).
#include "body/piece_ghosts.h"

#include <algorithm>
#include <limits>

namespace fracdem
{

namespace
{
void grow_box(Box& b, const double* q)
{
  for (int d = 0; d < 3; ++d) {
    b.lo[d] = std::min(b.lo[d], q[d]);
    b.hi[d] = std::max(b.hi[d], q[d]);
  }
}
} // namespace

void PieceGhosts::init(const ContactSurface& surface, const std::vector<int>& facet_part,
                       const MeshPart& part)
{
  surface_ = &surface;
  part_ = part.part;
  facet_part_ = facet_part;
  mine_.clear();
  mine_local_.clear();
  slaves_.clear();
  // part.global_node is ascending: a merge of the two sorted lists.
  size_t i = 0;
  for (size_t s = 0; s < surface.nodes.size(); ++s) {
    const int g = surface.nodes[s];
    while (i < part.global_node.size() && part.global_node[i] < g)
      ++i;
    if (i == part.global_node.size() || part.global_node[i] != g) continue;
    mine_.push_back(g);
    mine_local_.push_back(static_cast<int>(i));
    if (part.owns(static_cast<int>(i))) slaves_.push_back(static_cast<int>(s));
  }
  const int ng = surface.nodes.empty() ? 0 : surface.nodes.back() + 1;
  known_.assign(ng, 0);
  partners_.clear();
  recv_nodes_.clear();
  route_.clear();
  learn_ = stale_ = true;
}

std::vector<double> PieceGhosts::local_box(const double* x, double grow)
{
  raw_ = empty_box();
  for (int n : mine_local_)
    grow_box(raw_, &x[3 * n]);
  Box b = raw_;
  if (!mine_local_.empty())
    for (int d = 0; d < 3; ++d) {
      b.lo[d] -= grow;
      b.hi[d] += grow;
    }
  std::vector<double> out(b.lo, b.lo + 3);
  out.insert(out.end(), b.hi, b.hi + 3);
  return out;
}

void PieceGhosts::set_boxes(const std::vector<double>& all)
{
  const int nranks = static_cast<int>(all.size()) / kBoxDoubles;
  std::vector<Box> boxes(nranks);
  for (int r = 0; r < nranks; ++r) {
    std::copy(&all[kBoxDoubles * r], &all[kBoxDoubles * r] + 3, boxes[r].lo);
    std::copy(&all[kBoxDoubles * r + 3], &all[kBoxDoubles * r + 3] + 3, boxes[r].hi);
  }
  // Symmetric: both sides compare the same two boxes.
  std::vector<int> partners;
  for (int q = 0; q < nranks; ++q)
    if (q != part_ && boxes_overlap(boxes[part_], boxes[q])) partners.push_back(q);
  if (partners != partners_) {
    partners_ = std::move(partners);
    recv_nodes_.assign(partners_.size(), {});
  }
  send_ids_ = learn_ = true; // S of the partners sent again; known nodes learnt again
  ++box_exchanges_;
}

bool PieceGhosts::moved_beyond(const double* x, double travel) const
{
  for (int n : mine_local_)
    for (int d = 0; d < 3; ++d)
      if (x[3 * n + d] < raw_.lo[d] - travel || x[3 * n + d] > raw_.hi[d] + travel) return true;
  return false;
}

void PieceGhosts::outgoing(const double* x, const double* v, std::vector<std::vector<double>>& out)
{
  out.resize(partners_.size());
  for (std::vector<double>& m : out) {
    m.clear();
    m.push_back(send_ids_ ? 1.0 : 0.0);
    if (send_ids_) {
      m.push_back(static_cast<double>(mine_.size()));
      m.insert(m.end(), mine_.begin(), mine_.end());
    }
    for (int n : mine_local_) {
      m.insert(m.end(), &x[3 * n], &x[3 * n] + 3);
      m.insert(m.end(), &v[3 * n], &v[3 * n] + 3);
    }
  }
  send_ids_ = false;
}

void PieceGhosts::take(const std::vector<std::vector<double>>& in, const double* x, const double* v,
                       double* rx, double* rv, double* rf)
{
  for (size_t i = 0; i < mine_.size(); ++i) {
    std::copy(&x[3 * mine_local_[i]], &x[3 * mine_local_[i]] + 3, &rx[3 * mine_[i]]);
    std::copy(&v[3 * mine_local_[i]], &v[3 * mine_local_[i]] + 3, &rv[3 * mine_[i]]);
  }
  for (size_t k = 0; k < partners_.size(); ++k) {
    const std::vector<double>& m = in[k];
    size_t at = 1;
    if (m[0] != 0.0) {
      const size_t n = static_cast<size_t>(m[1]);
      recv_nodes_[k].assign(m.begin() + 2, m.begin() + 2 + n);
      at = 2 + n;
      learn_ = true;
    }
    for (int g : recv_nodes_[k]) {
      std::copy(&m[at], &m[at] + 3, &rx[3 * g]);
      std::copy(&m[at + 3], &m[at + 3] + 3, &rv[3 * g]);
      at += 6;
    }
  }
  if (learn_) learn_known(*surface_);
  for (int g : known_list_)
    std::fill(&rf[3 * g], &rf[3 * g] + 3, 0.0);
}

// The nodes known from now until the next box exchange, the facets they complete, and where the
// forces of the nodes that are not the part's go (the lowest partner that sent each).
void PieceGhosts::learn_known(const ContactSurface& s)
{
  learn_ = false;
  stale_ = true;
  std::fill(known_.begin(), known_.end(), 0);
  for (int g : mine_)
    known_[g] = 1;
  route_.assign(partners_.size(), {});
  for (size_t k = 0; k < partners_.size(); ++k) {
    route_[k].assign(recv_nodes_[k].size(), 0);
    for (size_t i = 0; i < recv_nodes_[k].size(); ++i) {
      const int g = recv_nodes_[k][i];
      route_[k][i] = known_[g] ? 0 : 1; // partners in ascending order: the lowest first
      known_[g] = 1;
    }
  }
  known_list_.clear();
  for (int g : s.nodes)
    if (known_[g]) known_list_.push_back(g);
  facet_known_.assign(s.facets.size(), 0);
  facets_.clear();
  for (size_t k = 0; k < s.facets.size(); ++k) {
    bool all = true;
    for (int j = 0; j < s.facets[k].nn; ++j)
      all = all && known_[s.facets[k].n[j]];
    facet_known_[k] = all ? 1 : 0;
    if (all) facets_.push_back(static_cast<int>(k));
  }
  // The edge pairs this part evaluates (edge_pair_mine): a first edge of its own against any
  // edge whose facets it knows, both known; the edge search looks at these alone.
  edges_mine_.clear();
  edges_known_.clear();
  for (int e = 0; e < static_cast<int>(s.edges.size()); ++e) {
    const SurfaceEdge& edge = s.edges[e];
    if (!facet_known_[edge.facet[0]] || !facet_known_[edge.facet[1]]) continue;
    edges_known_.push_back(e);
    if (facet_part_[edge.facet[0]] == part_) edges_mine_.push_back(e);
  }
  edges_due_ = true;
}

// The part's nodes against the known facets: the scene's buffered search (reach of the deepest
// accepted contact, rebuilt when the known nodes moved by more than half of it).
void PieceGhosts::search(const ContactSurface& s, const double* x)
{
  const int nk = static_cast<int>(known_list_.size());
  kx_.resize(3 * static_cast<size_t>(nk));
  for (int i = 0; i < nk; ++i)
    std::copy(&x[3 * known_list_[i]], &x[3 * known_list_[i]] + 3, &kx_[3 * i]);
  const double reach = s.max_reach;
  if (!stale_ && !(2 * search_.node_travel(kx_.data(), nk) > reach)) return;
  stale_ = false;
  std::vector<Aabb> boxes(facets_.size());
  for (size_t j = 0; j < facets_.size(); ++j)
    boxes[j] = node_box(s.facets[facets_[j]].n.data(), s.facets[facets_[j]].nn, x);
  std::vector<double> spheres(4 * slaves_.size(), 0.0);
  for (size_t i = 0; i < slaves_.size(); ++i)
    std::copy(&x[3 * s.nodes[slaves_[i]]], &x[3 * s.nodes[slaves_[i]]] + 3, &spheres[4 * i]);
  search_ = BufferedSearch(2 * reach);
  search_.build(boxes, spheres.data(), static_cast<int>(slaves_.size()));
  search_.remember_positions(kx_.data(), nk, kx_.data(), nk);
  // Sorted by node, then facet: slaves_ and facets_ are ascending.
  cand_.clear();
  for (const auto& c : search_.candidates())
    cand_.emplace_back(slaves_[c.first], facets_[c.second]);
}

// Edge e's first facet's part evaluates (e, f); every node of both edges' facets must be known.
bool PieceGhosts::edge_pair_mine(const ContactSurface& s, int e, int f) const
{
  if (facet_part_[s.edges[e].facet[0]] != part_) return false;
  for (int g : {e, f})
    for (int k : s.edges[g].facet)
      if (!facet_known_[k]) return false;
  return true;
}

int PieceGhosts::evaluate(const ContactSurface& s, SurfaceContact& nodes, EdgeContact* edges,
                          const ContactBodyState& st, double dt)
{
  search(s, st.x);
  // One call per step on every rank, candidates or not (the contacts' continuity counts calls).
  int n =
      static_cast<int>(nodes.resolve(s, st, s, st, true, dt, cand_.data(), cand_.size()).contacts);
  if (edges && edges_due_) {
    edges->restrict_search(edges_mine_, edges_known_);
    edges_due_ = false;
  }
  if (edges)
    n += edges->evaluate(s, st, s, st, true, dt,
                         [&](int e, int f) { return edge_pair_mine(s, e, f); });
  return n;
}

std::vector<std::vector<double>> routed_forces(const std::vector<std::vector<int>>& sent,
                                               const std::vector<std::vector<char>>& route,
                                               const double* f)
{
  std::vector<std::vector<double>> back(sent.size());
  for (size_t r = 0; r < sent.size(); ++r) {
    back[r].assign(3 * sent[r].size(), 0.0);
    for (size_t i = 0; i < sent[r].size(); ++i)
      if (route[r][i])
        std::copy(&f[3 * static_cast<size_t>(sent[r][i])],
                  &f[3 * static_cast<size_t>(sent[r][i])] + 3, &back[r][3 * i]);
  }
  return back;
}

void PieceGhosts::forces_back(const double* rf, double* f_part,
                              std::vector<std::vector<double>>& back) const
{
  for (size_t i = 0; i < mine_.size(); ++i)
    for (int d = 0; d < 3; ++d)
      f_part[3 * mine_local_[i] + d] += rf[3 * mine_[i] + d];
  back = routed_forces(recv_nodes_, route_, rf);
}

void PieceGhosts::add_returned(const std::vector<std::vector<double>>& returned,
                               double* f_part) const
{
  for (size_t k = 0; k < partners_.size(); ++k)
    for (size_t i = 0; i < mine_.size(); ++i)
      for (int d = 0; d < 3; ++d)
        f_part[3 * mine_local_[i] + d] += returned[k][3 * i + d];
}

} // namespace fracdem
