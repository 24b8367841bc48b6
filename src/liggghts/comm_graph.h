// Host communicator that lets atom ownership follow a graph partition instead of the spatial brick.
#ifndef FRACDEM_COMM_GRAPH_H
#define FRACDEM_COMM_GRAPH_H

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

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
// the stock exchange drops them. Ghosts refine the paper's box exchange: the
// box is cut into cells of edge >= the ghost cutoff, each rank's cover is the set of cells holding
// its atoms (plus its stock brick's cells while an insertion fix must see every particle near the
// brick it inserts into), and a rank receives every atom image in a cell adjacent to its cover.
// Swaps are arranged as a ring (swap k sends to me+k, receives from me-k) times the periodic image
// shifts, so the stock
// forward/reverse communication of atoms, pairs, fixes, computes and dumps works unchanged.
class CommGraph : public Comm
{
public:
  explicit CommGraph(class LAMMPS*);

  void setup() override;
  void exchange() override;
  void borders() override;

  // Switches graph ownership on (idempotent). Errors if the scene cannot support it.
  void enable_graph_ownership(const char* caller);
  bool graph_ownership() const { return graph_mode_; }
  // Whether ghosts must also cover the stock brick (insertion fixes check overlaps there).
  void set_cover_brick(bool on) { cover_brick_ = on; }
  // Restricts that brick cover to these boxes (6 doubles each: lo xyz, hi xyz), e.g. the bounding
  // boxes of the insertion regions; empty = the whole brick.
  void set_cover_limits(std::vector<double> boxes) { cover_limits_ = std::move(boxes); }
  // Ownership by cells: from now on every exchange sends each atom to the owner of its cell
  // (owners: one rank per cell of grid). Replaces per-atom destinations.
  void set_cell_owners(const fracdem::balance::CellGrid& grid, std::vector<int> owners)
  {
    cell_grid_ = grid;
    cell_owners_ = std::move(owners);
    time_next_migration_ = true;
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
  double migration_seconds() const
  {
    return migration_seconds_;
  } // cumulative, repartition exchanges

private:
  bool graph_mode_ = false;
  std::vector<int> pending_dest_;
  fracdem::balance::CellGrid cell_grid_;
  std::vector<int> cell_owners_;
  std::vector<std::array<int, 3>> shifts_; // periodic image shifts, zero shift first
  // A cover cell of a rank with the bounding box of that rank's atoms in it.
  struct CellOwner {
    std::int64_t cell = 0;
    int rank = -1;
    double box[6] = {0, 0, 0, 0, 0, 0};
  };
  std::vector<CellOwner> cell_owner_;    // sorted by cell, then rank
  std::vector<std::int64_t> owner_slot_; // first cell_owner_ entry per cell of a local window
  // A cell near one of mine whose owners need images from my cell: its unwrapped bounds, the
  // image shift and its range in cell_owner_.
  struct Candidate {
    double lo[3], hi[3];
    int shift;
    std::int64_t first, last;
  };
  std::vector<Candidate> cands_;
  std::vector<std::int64_t> cand_start_; // per cell of mine (sorted my_cells order)
  bool cover_brick_ = false;
  std::vector<double> cover_limits_;
  std::vector<std::vector<double>> out_buf_; // exchange buffers per destination
  std::vector<double> in_buf_;
  int last_migrated_ = 0;
  double migration_seconds_ = 0;
  bool time_next_migration_ = false; // the next exchange carries out a repartition

  void build_swaps();
};

} // namespace LAMMPS_NS

#endif
