// ContactScene: surface contact between many bodies (and each body's own pieces) from one
// buffer-zone search over all their surfaces, its work split among parts by graph partitioning.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "contact/edge_contact.h"
#include "contact/surface_contact.h"

namespace fracdem
{

// How the contact work is shared among the parts (contact_balance, docs/fix_fem_body.md).
// a_priori: vertices weighted by their candidate (potential-pair) counts, partitioned after
// every search; a_posteriori: weighted by the work recorded since the last check (facet tests +
// contacts evaluated, counted), partitioned when the imbalance B = max / mean of the parts'
// recorded work exceeds thresh (checked every `every` steps; after a topology change, by the
// candidate counts). parts: 0 = one per rank; K > 0 at one rank = K model parts, every node still
// evaluated on the rank but its work counted for its part (the work model of K ranks).
struct ContactBalance {
  enum Model { APriori, APosteriori };
  Model model = APosteriori;
  double thresh = 1.1;
  int every = 10;
  int parts = 0;
  std::string file; // CSV of the checks (rank 0); empty: none
};

// One body of the scene: its surface, and the contact of its own pieces (held by the body: its
// state is in the body's restart record); self null: no self contact. edges: the edge-to-edge
// contact of its pieces (3D, contact_edges yes; also held by the body); null: the body takes no
// edge contact, with its pieces or with others.
struct SceneMember {
  const ContactSurface* surface = nullptr;
  SurfaceContact* self = nullptr;
  EdgeContact* edges = nullptr;
};

// The parallel context: this rank, the rank count, an in-place sum over the ranks entered by all
// at the same point (nothing at one rank), and a line printer (called on rank 0 only).
struct SceneComm {
  int rank = 0, nprocs = 1;
  std::function<void(double*, int)> sum;
  std::function<void(const std::string&)> print;
};

// Candidates: every surface node of every body against every facet of every body whose box,
// inflated by half the buffer, holds it (the node inflated by the other half); the buffer is
// twice the deepest accepted contact of all surfaces (reach), and the search is redone when the
// largest displacement of a surface node along an axis since the last one exceeds half the
// reach (a node and a facet then approached by at most the reach, so every contact up to reach
// deep is among the candidates; paper eqs. 1-2), or after a topology change (invalidate()).
// Evaluation: body i's call (evaluate_body, in body order, every rank alike) resolves its own
// pieces and its pairs with every later body j, nodes of i on facets of j then nodes of j on
// facets of i, as the pairwise SurfaceContact objects did, each node on the part that owns it.
// Edge-to-edge contact (3D) of a pair, or of a body's pieces, is not split by node: every rank
// evaluates it (edge contacts are a few per cent of the contact work), so its per-pair state
// stays the same everywhere (restart records come from rank 0), and the forces are added on the
// part pair_part(a, b) only.
// A pair's contact state in ContactScene::pair_state's layout (nodes of a on facets of b, nodes of
// b on facets of a: each a record count and (node, penetration, offset) records; then the edge
// pairs' count and records of 6) from its three objects, and back into them (throws on a
// corrupt state).
std::vector<double> pack_pair_state(const SurfaceContact& a_on_b, const SurfaceContact& b_on_a,
                                    const EdgeContact& edges);
void unpack_pair_state(const std::vector<double>& state, SurfaceContact& a_on_b,
                       SurfaceContact& b_on_a, EdgeContact& edges);

class ContactScene
{
public:
  // pair_options[idx(a, b)], a < b: the options of the pair's two directions.
  void configure(std::vector<SceneMember> members, std::vector<SurfaceContactOptions> pair_options,
                 const ContactBalance& balance, SceneComm comm);
  ~ContactScene();
  int size() const { return static_cast<int>(members_.size()); }
  static int pair_index(int a, int b) { return b * (b - 1) / 2 + a; } // a < b
  // After a topology change of any member: numbering, search and (where nodes came or went)
  // the partition are made again at the next evaluation.
  void invalidate() { stale_ = true; }
  // states: one per member; x, v and m of all, f of member i and the later ones (the earlier
  // ones are not touched). Search when due (once per step), then the contacts of body i; the
  // last member's call also checks the balance every `every` steps. Returns the contacts
  // evaluated on this rank.
  int evaluate_body(int i, const std::vector<ContactBodyState>& states, std::int64_t step,
                    double dt);
  // Every rank gets the whole contact state of member i's own pieces (restart records are
  // written from rank 0). Entered by every rank.
  void gather_self_state(int i);
  // The contact state of the pair of bodies (a, b), a < b: nodes of a on facets of b, nodes of b
  // on facets of a (each a record count and (node, penetration, offset) records), then edge to
  // edge (EdgeContact::pack_state records of 6), whole on every rank. A new scene of the same
  // bodies takes it (restore_pair_state), so that a run split in two goes on with the contacts
  // of the first (they would start afresh, as new contacts, and push with another force).
  // Entered by every rank, pair by pair in the same order.
  std::vector<double> pair_state(int a, int b) const;
  void restore_pair_state(int a, int b, const std::vector<double>& state);
  // The part that evaluates work of the pair (a, b) not split by node (e.g. edge contact).
  int pair_part(int a, int b) const;

  // ---- inspection (tests, logs) ----
  int parts() const { return nparts_; }
  // (surface node of a, facet of b) candidates of the ordered pair, sorted.
  std::vector<std::pair<int, int>> candidates(int a, int b) const;
  const std::vector<int>& owners() const { return owner_; } // per scene node (members in order)
  long searches() const { return searches_; }
  long repartitions() const { return repartitions_; }
  double buffer() const { return buffer_; }
  // Totals of this rank since configure (all parts' in model mode).
  long tests() const { return total_tests_; }
  long contacts() const { return total_contacts_; }
  double last_imbalance() const { return last_b_; }
  // Per part: the work (tests + contacts) booked by the balance checks so far, all ranks'.
  const std::vector<double>& booked() const { return booked_; }
  // B of the last partition's own vertex weights (what it promised).
  double predicted_imbalance() const { return predicted_b_; }

private:
  void renumber();
  void fold_window();
  void carry_weights(const std::vector<int>& old_off);
  void search(const std::vector<ContactBodyState>& states);
  bool search_due() const;
  void gather_positions(const std::vector<ContactBodyState>& states);
  std::vector<double> apriori_weights() const;
  void repartition(const std::vector<double>& weights, std::int64_t step, const char* why,
                   double measured);
  void move_contact_state(const std::vector<int>& old_owner);
  void check_balance(std::int64_t step);
  int resolve(int a, int b, const std::vector<ContactBodyState>& states, double dt);
  int resolve_edges(int a, int b, const std::vector<ContactBodyState>& states, double dt);
  bool evaluates_all() const { return nparts_ == 1 || model_parts_; }

  std::vector<SceneMember> members_;
  std::vector<SurfaceContactOptions> pair_options_;
  // Pair objects of the two directions of every pair a < b: [2 idx] nodes of a on facets of b,
  // [2 idx + 1] nodes of b on facets of a.
  std::vector<SurfaceContact> pairs_;
  std::vector<EdgeContact> edge_pairs_; // [idx]: edges of a against edges of b (3D), a < b
  ContactBalance balance_;
  SceneComm comm_;
  int nparts_ = 1, part_ = 0;
  bool model_parts_ = false; // parts at one rank: counted, all evaluated here
  // Scene numbering: member m's surface nodes are node_off_[m] .. node_off_[m + 1) (its
  // surface's nodes in order), its facets facet_off_[m] ...
  std::vector<int> node_off_, facet_off_;
  std::vector<double> sx_;
  BufferedSearch search_{0.0};
  double reach_ = 0, buffer_ = 0; // deepest accepted contact of all surfaces; 2 reach
  bool stale_ = true;
  std::int64_t searched_step_ = INT64_MIN;
  // Candidates grouped by ordered pair (a, b) -> cand_off_[a * n + b] ..; local indices.
  std::vector<std::size_t> cand_off_;
  std::vector<std::pair<int, int>> cand_;
  std::vector<int> owner_;
  // Node owners by (member, mesh node), carried over a renumbering.
  std::vector<std::vector<int>> mesh_owner_;
  std::vector<double> win_tests_, win_contacts_; // per scene node, since the last check
  // Per part (work, tests, contacts) of the window done under an earlier numbering.
  std::vector<double> carried_, booked_;
  // Per scene node: work recorded under earlier numberings since the last check (a posteriori
  // weights), and the members' node lists of the current numbering.
  std::vector<double> weights_window_;
  std::vector<std::vector<int>> numbered_;
  std::int64_t last_check_ = INT64_MIN;
  long searches_ = 0, repartitions_ = 0, total_tests_ = 0, total_contacts_ = 0;
  double last_b_ = 1.0, predicted_b_ = 0.0;
  bool repartitioned_ = false;
  std::FILE* csv_ = nullptr;
};

} // namespace fracdem
