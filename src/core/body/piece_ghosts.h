// The contact of a distributed body's own pieces by neighbour messages: which parts' surfaces can
// touch (boxes exchanged when the host re-neighbours), the surface nodes' state sent to those
// parts and their forces returned each step, and the owner rules that evaluate each contact on
// one rank (docs/distributed_bodies.md, "Contact of the pieces").
#pragma once

#include <vector>

#include "body/body_partition.h"
#include "body/facet_ghosts.h"
#include "contact/contact_search.h"
#include "contact/edge_contact.h"
#include "contact/surface_contact.h"

namespace fracdem
{

// One rank's side. The driver calls, on every rank at the same steps:
//   after a topology change: init(...)
//   when the host re-neighbours, and after init: all = allgather(local_box(...)); set_boxes(all)
//   each step: outgoing -> exchange with partners() -> take -> evaluate -> forces_back ->
//              exchange back -> add_returned (then the shared-node sum).
// The part's surface nodes (S: the whole surface's nodes that the part holds, owned or shared)
// go to every partner each step (6 doubles each, their global numbers only in the first message
// after a box exchange). Owner rules: a node against a facet is evaluated by the part that owns
// the node (MeshPart::owns); a pair of edges (e < f, ContactSurface::edges order) by the part of
// the element of e's first facet. Both hold what they need: the node and edge e are in S of
// their part, and anything within reach of them belongs to a partner (set_boxes), whose S holds
// every node of its facets.
// Per sender, the forces (3 each, from f by node number) of the nodes it sent, zeros where
// route says another sender gets the node: the replies that return forces computed on a replica
// to the parts that sent the nodes (PieceGhosts, and a distributed body's pairs on rank 0).
std::vector<std::vector<double>> routed_forces(const std::vector<std::vector<int>>& sent,
                                               const std::vector<std::vector<char>>& route,
                                               const double* f);

class PieceGhosts
{
public:
  static constexpr int kBoxDoubles = 6;

  // surface: the whole body's contact surface in global node numbers (ContactSurface::build from
  // the parts); facet_part: per facet of it, the part of its element; part: this rank's part.
  void init(const ContactSurface& surface, const std::vector<int>& facet_part,
            const MeshPart& part);

  // ---- box exchange ----
  // The box of the part's surface nodes at x (the part's positions) grown by `grow` (the travel
  // allowed until the next exchange and the contact's reach); 6 doubles, lo then hi.
  std::vector<double> local_box(const double* x, double grow);
  // Every rank's local_box, in rank order: partners are the parts whose boxes meet this one's.
  void set_boxes(const std::vector<double>& all);
  // Whether a surface node of the part is now further than `travel` along an axis outside the
  // box of the part's surface nodes at the exchange: a part that was not a partner then may now
  // be within reach, and its contacts with this part are not seen until the next exchange.
  bool moved_beyond(const double* x, double travel) const;

  // ---- each step ----
  // To partners()[k]: a flag (1: global numbers follow, count first), then x and v of S.
  void outgoing(const double* x, const double* v, std::vector<std::vector<double>>& out);
  // The replica by global node (rx, rv, rf: 3 per node of the body): S from x and v, the
  // partners' from in[k]; rf zeroed at every node known this step.
  void take(const std::vector<std::vector<double>>& in, const double* x, const double* v,
            double* rx, double* rv, double* rf);
  // This rank's contacts (node to facet; edge to edge when edges is given) on the replica:
  // forces added to st.f. Returns the number of contacts.
  int evaluate(const ContactSurface& s, SurfaceContact& nodes, EdgeContact* edges,
               const ContactBodyState& st, double dt);
  // Forces of the replica rf: S's added to f_part (the part's nodes), every other known node's
  // into back[k] for one partner that sent it (the lowest), 3 doubles per node it sent.
  void forces_back(const double* rf, double* f_part, std::vector<std::vector<double>>& back) const;
  // Forces returned by partners()[k] (3 doubles per node of S) added to f_part.
  void add_returned(const std::vector<std::vector<double>>& returned, double* f_part) const;

  const std::vector<int>& partners() const { return partners_; }
  int surface_nodes() const { return static_cast<int>(mine_.size()); } // |S|
  int known_nodes() const { return static_cast<int>(known_list_.size()); }
  int box_exchanges() const { return box_exchanges_; }

private:
  void learn_known(const ContactSurface& s);
  void search(const ContactSurface& s, const double* x);
  bool edge_pair_mine(const ContactSurface& s, int e, int f) const;

  int part_ = 0;
  std::vector<int> facet_part_;
  std::vector<int> mine_, mine_local_; // S: global numbers (ascending), index in the part
  std::vector<int> slaves_;            // surface indices of the nodes the part owns
  Box raw_ = empty_box();              // S's box at the last exchange (not grown)
  std::vector<int> partners_;
  bool send_ids_ = true;
  std::vector<std::vector<int>> recv_nodes_; // per partner: its S (global, ascending)
  std::vector<std::vector<char>> route_;     // per partner, per node of its S: forces go there
  std::vector<char> known_, facet_known_;    // per global node / facet: positions this step
  std::vector<int> known_list_, facets_;     // known nodes; facets with every node known
  std::vector<int> edges_mine_, edges_known_; // the edge search's sides (learn_known)
  bool edges_due_ = true;                     // they changed: restrict the edge search anew
  bool learn_ = true, stale_ = true;
  BufferedSearch search_{0.0};
  std::vector<double> kx_;
  std::vector<std::pair<int, int>> cand_; // (surface node index, facet), sorted
  int box_exchanges_ = 0;
  const ContactSurface* surface_ = nullptr;
};

} // namespace fracdem
