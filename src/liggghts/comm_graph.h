// Host communicator that lets atom ownership follow a graph partition instead of the spatial brick.
#ifndef FRACDEM_COMM_GRAPH_H
#define FRACDEM_COMM_GRAPH_H

#include <array>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include <mpi.h>

#include "balance/cell_grid.h"
#include "comm.h"

namespace LAMMPS_NS
{

// Drop-in replacement for the stock Comm, installed by the fracdem executable before the input is
// read. Until graph ownership is switched on it is the stock Comm (every call forwards to the
// base), so stock scripts run unchanged.
//
// In graph mode ownership is either per cell (set_cell_owners: every exchange sends each atom to
// the owner of its cell, so ownership follows the particles' motion and inserted particles find
// their owner) or per atom (set_destinations: an atom stays on its rank between repartitions, the
// paper's particle graph). Atoms that left the box through non-periodic boundaries are dropped, as
// the stock exchange drops them.
//
// Ghosts refine the paper's box exchange: the box is cut into cover cells at least one ghost
// cutoff wide; a rank's cover is the set of cells holding its atoms, with the bounding box of those
// atoms in each octant of the cell (plus its stock brick while an insertion fix must see every
// particle near the brick it inserts into), and a rank receives every atom image within the cutoff
// of its cover. Only the atoms of cells next to another rank's cover (or a periodic boundary) are
// tested (27-cell stencil).
//
// Communication talks to partner ranks only (the ranks whose atoms can come within the cutoff):
// one message per partner and communication, all fields of all periodic images in it, receives
// posted before sends, one wait (see docs/fix_balance_graph.md, "Communication pattern").
// Swaps stay the data layout, so the pack/unpack callbacks of atoms, pairs, fixes, computes and
// dumps work unchanged: swaps come in blocks of one swap per periodic image shift; block b sends
// to me + ring_[b] and receives from me - ring_[b] (ring offsets ascending, 0 = images of myself),
// which also keeps the base class's swap loop (forward_comm_array) deadlock-free.
class CommGraph : public Comm
{
public:
  explicit CommGraph(class LAMMPS*);
  ~CommGraph() override;

  void setup() override;
  void exchange() override;
  void borders() override;
  void forward_comm(int dummy = 0) override;
  void reverse_comm() override;
  void forward_comm_pair(class Pair*) override;
  void reverse_comm_pair(class Pair*) override;
  void forward_comm_fix(class Fix*) override;
  void reverse_comm_fix(class Fix*) override;
  void forward_comm_variable_fix(class Fix*) override;
  void reverse_comm_variable_fix(class Fix*) override;
  void forward_comm_compute(class Compute*) override;
  void reverse_comm_compute(class Compute*) override;
  void forward_comm_dump(class Dump*) override;
  void reverse_comm_dump(class Dump*) override;

  // Switches graph ownership on (idempotent, collective). Errors if the scene cannot support it.
  void enable_graph_ownership(const char* caller);
  bool graph_ownership() const { return graph_mode_; }
  // Whether ghosts must also cover the stock brick (insertion fixes check overlaps there).
  void set_cover_brick(bool on) { cover_brick_ = on; }
  // Restricts that brick cover to these boxes (6 doubles each: lo xyz, hi xyz), e.g. the bounding
  // boxes of the insertion regions; empty = the whole brick.
  void set_cover_limits(std::vector<double> boxes)
  {
    cover_limits_ = std::move(boxes);
    ++owners_version_;
  }
  // Ownership by cells: from now on every exchange sends each atom to the owner of its cell
  // (owners: one rank per cell of grid). Replaces per-atom destinations.
  void set_cell_owners(const fracdem::balance::CellGrid& grid, std::vector<int> owners)
  {
    cell_grid_ = grid;
    cell_owners_ = std::move(owners);
    time_next_migration_ = true;
    ++owners_version_;
  }
  bool has_cell_owners() const { return !cell_owners_.empty(); }
  const fracdem::balance::CellGrid& cell_grid() const { return cell_grid_; }
  const std::vector<int>& cell_owners() const { return cell_owners_; }
  // Destination rank of each local atom for the next exchange (size nlocal); consumed by it.
  void set_destinations(std::vector<int> dest)
  {
    pending_dest_ = std::move(dest);
    time_next_migration_ = true;
  }

  // Statistics of the last exchange/borders in graph mode.
  int last_migrated() const { return last_migrated_; }
  int partner_count() const { return static_cast<int>(partners_.size()); }
  double migration_seconds() const
  {
    return migration_seconds_;
  } // cumulative, repartition exchanges

private:
  // Opt-in (environment FRACDEM_BORDERS_STATS) cumulative cost of graph-mode borders, printed per
  // rank at the end: calls, owned atoms summed over calls, thread CPU, of which inside MPI.
  struct BordersStats {
    long calls = 0;
    double owned = 0, cpu = 0, mpi_cpu = 0;
  };
  static bool borders_stats_wanted();
  void borders_stats_begin();
  void borders_stats_end(int nlocal);
  void report_borders_stats() const;
  const bool stats_on_ = borders_stats_wanted();
  BordersStats stats_;
  double stats_cpu0_ = 0, stats_mpi0_ = 0;

  // Callbacks of one communication: pack swap iswap's data into buf (returns doubles written),
  // unpack swap iswap's data from buf.
  using PackFn = std::function<int(int iswap, double* buf)>;
  using UnpackFn = std::function<void(int iswap, double* buf)>;
  // A cover cell of a rank with the bounding box of that rank's atoms in it.
  struct CellOwner {
    std::int64_t cell = 0;
    int rank = -1;
    double box[6] = {0, 0, 0, 0, 0, 0};
    std::int64_t next = -1; // next entry of the same window cell
  };
  // Something near one of my cells that may need images of its atoms: a rank, the image shift
  // and the box its atoms (or its brick) occupy there.
  struct Candidate {
    int rank, shift;
    const double* box;
  };

  bool graph_mode_ = false;
  MPI_Comm gcomm_ = MPI_COMM_NULL; // private duplicate of world: our tags never meet the host's
  std::vector<int> pending_dest_;
  fracdem::balance::CellGrid cell_grid_;
  std::vector<int> cell_owners_;
  std::vector<std::array<int, 3>> shifts_; // periodic image shifts, zero shift first
  int nshift_ = 1;
  int shift_of_[27]; // index in shifts_ of (sx, sy, sz), (s + 1) base 3
  bool cover_brick_ = false;
  std::vector<double> cover_limits_;

  // Swap blocks and partners (set by borders).
  std::vector<int> ring_;     // ring offset k of each block, ascending, ring_[0] == 0
  std::vector<int> partners_; // ranks whose atoms can come within the cutoff of mine, ascending
  std::vector<int> block_to_; // per rank: block that sends to it (-1 if none)

  // Static partners of cell ownership, cached until the owners, the box or the cutoff change.
  std::int64_t owners_version_ = 0, partners_version_ = -1;
  double partners_key_[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::vector<int> static_partners_;
  std::vector<char> owner_interior_; // per owner cell: mine, and every cell within reach mine

  // Ghost search state of the last borders.
  fracdem::balance::CellGrid cover_;
  std::vector<std::int64_t> my_cells_;  // occupied cover cells, ascending
  std::vector<std::int64_t> my_coords_; // their grid coordinates (3 per cell)
  std::vector<double> my_boxes_;        // bounding box of my atoms per occupied cell
  std::vector<int> cell_first_, order_; // atoms of my_cells_[m]: order_[cell_first_[m] ...]
  std::vector<double> sub_boxes_;       // boxes of my atoms per octant of each cell
  std::vector<int> sub_first_;          // octant boxes of my_cells_[m]: sub_first_[m] ...
  std::int64_t span_lo_[3] = {0, 0, 0}, span_n_[3] = {1, 1, 1}; // cells my atoms span
  double my_box_[6] = {0, 0, 0, 0, 0, 0}; // my atoms' box, unwrapped to that span
  std::vector<double> rank_boxes_;        // per-atom ownership: every rank's box
  std::vector<double> bricks_;            // stock bricks (within the cover limits), nbox_ per rank
  int nbox_ = 0;
  std::vector<CellOwner> cell_owner_;    // cover boxes of my partners and me
  std::vector<std::int64_t> owner_slot_; // first cell_owner_ entry per cell of a local window
  std::vector<char> foreign_;            // per window cell: another rank's cover is there
  std::vector<char> near_;               // ... there or in one of the 26 cells around
  std::int64_t win_lo_[3] = {0, 0, 0}, win_n_[3] = {1, 1, 1};

  // Buffers: exchange per destination, aggregated messages per block.
  std::vector<std::vector<double>> out_buf_;
  std::vector<double> in_buf_, agg_send_, agg_recv_, self_buf_;
  std::vector<MPI_Request> requests_;
  int last_migrated_ = 0;
  double migration_seconds_ = 0;
  bool time_next_migration_ = false; // the next exchange carries out a repartition

  // comm_graph.cpp: swap layout and the exchange of atoms.
  void build_shifts();
  void build_blocks();
  int pack_leavers(std::vector<int>& dest);
  void migrate_sparse(int kept_and_sent);
  // comm_graph_forward.cpp: one aggregated message per partner block.
  // One aggregated forward (reverse) communication of a pair, fix, compute or dump.
  template <class Obj> void forward_object(Obj* obj);
  template <class Obj> void reverse_object(Obj* obj);
  void forward_blocks(int per_atom, const PackFn& pack, const UnpackFn& unpack, int tag);
  void reverse_blocks(int per_atom, const PackFn& pack, const UnpackFn& unpack, int tag);
  void forward_blocks_variable(int max_per_atom, const PackFn& pack, const UnpackFn& unpack,
                               bool reverse);
  int block_count(int b, bool send_side) const;
  // comm_graph_borders.cpp: ghost search.
  void bin_atoms();
  void build_sub_boxes();
  void compute_span();
  void compute_bricks();
  void find_partners();
  void find_static_partners();
  void add_brick_partners(std::vector<char>& is_partner);
  void exchange_cover();
  void cover_targets(std::size_t m, std::vector<std::vector<double>>& out) const;
  void build_owner_window();
  std::int64_t window_slot(const std::int64_t c[3]) const;
  void brick_candidates(std::size_t m, std::vector<Candidate>& cands) const;
  bool at_periodic_edge(const std::int64_t c[3]) const;
  void cell_candidates(std::size_t m, std::vector<Candidate>& cands) const;
  void search_ghosts();
  void send_borders();
  void unpack_borders(std::vector<std::vector<double>>& in);
};

} // namespace LAMMPS_NS

#endif
