// Graph-ownership communicator: exchange to balancer-chosen ranks, ghosts by cover-box overlap.
#include "comm_graph.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "atom.h"
#include "atom_vec.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"

using namespace LAMMPS_NS;

namespace
{
constexpr int kExchangeSlack = 1000; // doubles beyond the per-atom maximum, as the stock comm
constexpr std::int64_t kMaxCells = std::int64_t(1) << 24; // cover grid size limit
constexpr int kStencil = 2;                               // cover cells per ghost cutoff
} // namespace

CommGraph::CommGraph(LAMMPS* lmp) : Comm(lmp) {}

void CommGraph::enable_graph_ownership(const char* caller)
{
  if (graph_mode_) return;
  char msg[512];
  if (domain->triclinic) {
    snprintf(msg, sizeof msg, "%s: graph ownership needs an orthogonal box (triclinic given)",
             caller);
    error->all(FLERR, msg);
  }
  if (style != 0) { // 0 == SINGLE in the host's comm.cpp
    snprintf(msg, sizeof msg, "%s: graph ownership supports 'communicate single' only", caller);
    error->all(FLERR, msg);
  }
  if (exchangeEvents) {
    snprintf(msg, sizeof msg, "%s: graph ownership cannot record exchange events (CFD coupling)",
             caller);
    error->all(FLERR, msg);
  }
  graph_mode_ = true;
  // New swap pattern and neighbour bins that span the whole box; exchange() restores the brick.
  setup();
  if (neighbor->style) neighbor->setup_bins();
  domain->set_local_box();
}

void CommGraph::build_swaps()
{
  shifts_.clear();
  const int* periodic = domain->periodicity;
  const int zmax = domain->dimension == 3 ? 1 : 0;
  shifts_.push_back({0, 0, 0});
  for (int sz = -zmax; sz <= zmax; ++sz)
    for (int sy = -1; sy <= 1; ++sy)
      for (int sx = -1; sx <= 1; ++sx) {
        if (sx == 0 && sy == 0 && sz == 0) continue;
        if ((sx && !periodic[0]) || (sy && !periodic[1]) || (sz && !periodic[2])) continue;
        shifts_.push_back({sx, sy, sz});
      }
  const int nshift = static_cast<int>(shifts_.size());
  nswap = nprocs * nshift;
  if (nswap > maxswap) grow_swap(nswap);
  for (int k = 0; k < nprocs; ++k)
    for (int s = 0; s < nshift; ++s) {
      const int iswap = k * nshift + s;
      sendproc[iswap] = (me + k) % nprocs;
      recvproc[iswap] = (me - k + nprocs) % nprocs;
      pbc_flag[iswap] = s != 0;
      for (int d = 0; d < 6; ++d)
        pbc[iswap][d] = d < 3 ? shifts_[s][d] : 0;
      sendnum[iswap] = recvnum[iswap] = 0;
      size_forward_recv[iswap] = size_reverse_send[iswap] = size_reverse_recv[iswap] = 0;
      firstrecv[iswap] = atom->nlocal;
    }
}

void CommGraph::setup()
{
  if (!graph_mode_) {
    Comm::setup();
    return;
  }
  // Ghost cutoff exactly as the stock comm computes it.
  double cut = std::max(neighbor->cutneighmax, cutghostuser);
  for (int i = 0; i < modify->nfix; ++i)
    if (modify->fix[i]->use_rad_for_cut_neigh_and_ghost())
      cut = std::max(cut, modify->fix[i]->extend_cut_ghost() + neighbor->skin);
  cutghost[0] = cutghost[1] = cutghost[2] = cut;
  build_swaps();
  // Neighbour bins are laid out over domain->sublo/subhi by the setup_bins() call that follows;
  // owned atoms may lie anywhere in the box, so the bins must span all of it.
  for (int d = 0; d < 3; ++d) {
    domain->sublo[d] = domain->boxlo[d];
    domain->subhi[d] = domain->boxhi[d];
  }
}

void CommGraph::exchange()
{
  if (!graph_mode_) {
    Comm::exchange();
    return;
  }
  const double t_start = MPI_Wtime();
  domain->set_local_box(); // the brick again, for insertion and is_in_subdomain users

  if (map_style) atom->map_clear();
  atom->nghost = 0;
  atom->avec->clear_bonus();

  AtomVec* avec = atom->avec;
  int nlocal = atom->nlocal;
  std::vector<int> dest;
  if (!cell_owners_.empty()) {
    dest.resize(nlocal);
    for (int i = 0; i < nlocal; ++i)
      dest[i] = cell_owners_[cell_grid_.cell_of(atom->x[i])];
  } else if (static_cast<int>(pending_dest_.size()) == nlocal) {
    dest.swap(pending_dest_);
  } else {
    dest.assign(nlocal, me);
  }
  pending_dest_.clear();

  const int* periodic = domain->periodicity;
  const double *lo = domain->boxlo, *hi = domain->boxhi;
  const int per_atom_max = maxexchange_atom + maxexchange_fix + kExchangeSlack;
  out_buf_.resize(nprocs);
  for (auto& b : out_buf_)
    b.clear();

  int migrated = 0;
  int i = 0;
  while (i < nlocal) {
    double* xi = atom->x[i];
    bool outside = false;
    for (int d = 0; d < domain->dimension; ++d)
      if (!periodic[d] && (xi[d] < lo[d] || xi[d] >= hi[d])) outside = true;
    if (outside || dest[i] != me) {
      if (!outside) {
        std::vector<double>& b = out_buf_[dest[i]];
        const size_t at = b.size();
        b.resize(at + per_atom_max);
        const int n = avec->pack_exchange(i, &b[at]);
        b.resize(at + n);
        ++migrated;
      }
      avec->copy(nlocal - 1, i, 1);
      dest[i] = dest[nlocal - 1];
      --nlocal;
    } else {
      ++i;
    }
  }
  atom->nlocal = nlocal;

  int any = migrated;
  MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_SUM, world);
  if (any) {
    std::vector<int> send_count(nprocs), recv_count(nprocs), send_disp(nprocs), recv_disp(nprocs);
    std::vector<double> send_all;
    for (int p = 0; p < nprocs; ++p) {
      send_disp[p] = static_cast<int>(send_all.size());
      send_count[p] = static_cast<int>(out_buf_[p].size());
      send_all.insert(send_all.end(), out_buf_[p].begin(), out_buf_[p].end());
    }
    MPI_Alltoall(send_count.data(), 1, MPI_INT, recv_count.data(), 1, MPI_INT, world);
    int total = 0;
    for (int p = 0; p < nprocs; ++p) {
      recv_disp[p] = total;
      total += recv_count[p];
    }
    in_buf_.resize(std::max(total, 1));
    MPI_Alltoallv(send_all.data(), send_count.data(), send_disp.data(), MPI_DOUBLE, in_buf_.data(),
                  recv_count.data(), recv_disp.data(), MPI_DOUBLE, world);
    int m = 0;
    while (m < total)
      m += avec->unpack_exchange(&in_buf_[m]);
    if (time_next_migration_) migration_seconds_ += MPI_Wtime() - t_start;
  }
  time_next_migration_ = false;
  last_migrated_ = migrated;

  bigint nlocal_big = atom->nlocal;
  MPI_Allreduce(&nlocal_big, &atom->natoms, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (atom->firstgroupname) atom->first_reorder();
}

void CommGraph::borders()
{
  if (!graph_mode_) {
    Comm::borders();
    return;
  }
  AtomVec* avec = atom->avec;
  const int nlocal = atom->nlocal;
  double** x = atom->x;

  // Cover of each rank: the cells (edge >= half the ghost cutoff) that hold its owned atoms, plus
  // the cells of its brick when an insertion fix needs to see every particle near the brick. An
  // atom image within the cutoff of an owned atom of rank q is within the cutoff of the cell that
  // holds that atom, at most kStencil cells away; sending each atom to the ranks of the cells it is
  // that close to is complete, and over-covers by at most one cell diagonal.
  const double *prd = domain->prd, *boxlo = domain->boxlo;
  const int* periodic = domain->periodicity;
  const int dim = domain->dimension;
  std::int64_t ncell[3] = {1, 1, 1};
  double cell_size[3] = {prd[0], prd[1], prd[2]};
  {
    // Coarsen uniformly if the grid would be huge (a coarser cover is still complete).
    double coarsen = 1.0;
    for (;;) {
      std::int64_t total = 1;
      for (int d = 0; d < dim; ++d) {
        ncell[d] = std::max<std::int64_t>(
            1, static_cast<std::int64_t>(prd[d] * kStencil / (cutghost[d] * coarsen)));
        total *= ncell[d];
      }
      if (total <= kMaxCells) break;
      coarsen *= 1.26;
    }
    for (int d = 0; d < dim; ++d)
      cell_size[d] = prd[d] / ncell[d];
  }
  auto cell_coord = [&](double x, int d) {
    std::int64_t c = static_cast<std::int64_t>(std::floor((x - boxlo[d]) / cell_size[d]));
    return std::min(std::max<std::int64_t>(c, 0), ncell[d] - 1);
  };
  auto cell_id = [&](std::int64_t cx, std::int64_t cy, std::int64_t cz) {
    return (cz * ncell[1] + cy) * ncell[0] + cx;
  };
  auto cell_coords = [&](std::int64_t id, std::int64_t c[3]) {
    c[0] = id % ncell[0], c[1] = (id / ncell[0]) % ncell[1], c[2] = id / (ncell[0] * ncell[1]);
  };

  // My occupied cells with the bounding box of my atoms in each: the cover is tested against
  // those boxes, which is exact where a cell holds one atom (cells are half a cutoff wide).
  std::vector<std::pair<std::int64_t, int>> atom_cell(nlocal);
  for (int i = 0; i < nlocal; ++i) {
    std::int64_t c[3] = {0, 0, 0};
    for (int d = 0; d < dim; ++d)
      c[d] = cell_coord(x[i][d], d);
    atom_cell[i] = {cell_id(c[0], c[1], c[2]), i};
  }
  std::sort(atom_cell.begin(), atom_cell.end());
  std::vector<std::int64_t> my_cells;
  std::vector<double> my_boxes;
  std::vector<int> my_cell_of(nlocal); // index in my_cells of each atom's cell
  for (const auto& ac : atom_cell) {
    const double* xi = x[ac.second];
    if (my_cells.empty() || my_cells.back() != ac.first) {
      my_cells.push_back(ac.first);
      my_boxes.insert(my_boxes.end(), {xi[0], xi[1], xi[2], xi[0], xi[1], xi[2]});
    } else {
      double* b = &my_boxes[my_boxes.size() - 6];
      for (int d = 0; d < 3; ++d)
        b[d] = std::min(b[d], xi[d]), b[3 + d] = std::max(b[3 + d], xi[d]);
    }
    my_cell_of[ac.second] = static_cast<int>(my_cells.size() - 1);
  }
  // Bricks of all ranks, when insertion fixes need every particle near the brick they insert
  // into: tested per atom as boxes (cheap), not as cells (a brick can hold very many cells).
  std::vector<double> bricks;
  int nbox = 0; // boxes per rank: the brick, or its intersections with the cover limits
  if (cover_brick_) {
    std::vector<double> mine_boxes;
    const double brick[6] = {domain->sublo[0], domain->sublo[1], domain->sublo[2],
                             domain->subhi[0], domain->subhi[1], domain->subhi[2]};
    if (cover_limits_.empty()) {
      mine_boxes.assign(brick, brick + 6);
    } else {
      for (size_t k = 0; k + 5 < cover_limits_.size(); k += 6)
        for (int d = 0; d < 6; ++d)
          mine_boxes.push_back(d < 3 ? std::max(brick[d], cover_limits_[k + d])
                                     : std::min(brick[d], cover_limits_[k + d])); // may be empty
    }
    nbox = static_cast<int>(mine_boxes.size() / 6);
    bricks.resize(mine_boxes.size() * nprocs);
    MPI_Allgather(mine_boxes.data(), 6 * nbox, MPI_DOUBLE, bricks.data(), 6 * nbox, MPI_DOUBLE,
                  world);
  }
  const double cut2 = cutghost[0] * cutghost[0];
  // Box tests that decide what is exchanged get a little slack: a superset is harmless.
  const double reach2 = cut2 * (1.0 + 1e-9);
  const int nshift = static_cast<int>(shifts_.size());
  // Squared gap between box a shifted by periodic image s and box b (6 doubles: lo, hi).
  auto box_gap2 = [&](const double* a, int s, const double* b) {
    double g2 = 0;
    for (int d = 0; d < dim; ++d) {
      const double off = shifts_[s][d] * prd[d];
      const double gap = std::max({b[d] - (a[3 + d] + off), 0.0, (a[d] + off) - b[3 + d]});
      g2 += gap * gap;
    }
    return g2;
  };

  // The cell range my atoms occupy per dimension, taken circularly across periodic boundaries
  // (a part that straddles one is still compact): start cell and length.
  std::int64_t span_lo[3] = {0, 0, 0}, span_n[3] = {1, 1, 1};
  {
    std::vector<char> occupied_along[3];
    for (int d = 0; d < dim; ++d)
      occupied_along[d].assign(ncell[d], 0);
    for (std::int64_t id : my_cells) {
      std::int64_t c[3];
      cell_coords(id, c);
      for (int d = 0; d < dim; ++d)
        occupied_along[d][c[d]] = 1;
    }
    for (int d = 0; d < dim; ++d) {
      const std::vector<char>& occupied = occupied_along[d];
      span_lo[d] = 0, span_n[d] = ncell[d];
      if (my_cells.empty()) continue;
      if (!periodic[d]) {
        std::int64_t lo = 0, hi = ncell[d] - 1;
        while (!occupied[lo])
          ++lo;
        while (!occupied[hi])
          --hi;
        span_lo[d] = lo, span_n[d] = hi - lo + 1;
        continue;
      }
      // Largest circular run of empty cells; the span is its complement.
      std::int64_t best = 0, best_end = 0, run = 0;
      for (std::int64_t k = 0; k < 2 * ncell[d]; ++k) {
        run = occupied[k % ncell[d]] ? 0 : run + 1;
        if (run > best && run <= ncell[d]) best = run, best_end = k;
      }
      if (best > 0) span_lo[d] = (best_end + 1) % ncell[d], span_n[d] = ncell[d] - best;
    }
  }
  // My atoms' bounding box in coordinates unwrapped to that span (its upper bound may pass the
  // box's): the test for which ranks exchange cover cells with me.
  double my_box[6] = {HUGE_VAL, HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (int i = 0; i < nlocal; ++i)
    for (int d = 0; d < 3; ++d) {
      double xd = x[i][d];
      if (d < dim && periodic[d] && cell_coord(xd, d) < span_lo[d]) xd += prd[d];
      my_box[d] = std::min(my_box[d], xd), my_box[3 + d] = std::max(my_box[3 + d], xd);
    }

  // Cover cells are exchanged with nearby ranks only, so that the work per rank scales with its
  // own atoms, not with the whole system: the ranks whose atom boxes come within the cutoff of
  // mine (some periodic image). Every atom that can need a ghost of mine, and every cover box my
  // atoms can be tested against, belongs to such a rank.
  std::vector<double> rank_boxes(6 * nprocs);
  MPI_Allgather(my_box, 6, MPI_DOUBLE, rank_boxes.data(), 6, MPI_DOUBLE, world);
  std::vector<int> partners;
  for (int q = 0; q < nprocs; ++q) {
    if (q == me) continue;
    // Evaluated on the ordered pair so that both ranks reach the same verdict bit for bit.
    const double* a = &rank_boxes[6 * std::min(me, q)];
    const double* b = &rank_boxes[6 * std::max(me, q)];
    for (int sh = 0; sh < nshift; ++sh)
      if (box_gap2(a, sh, b) <= reach2) {
        partners.push_back(q);
        break;
      }
  }
  // To each partner: my cover cells that some image of its atoms' box can reach, as
  // (cell, box) records of 7 doubles (cell ids stay far below 2^53).
  const int npart = static_cast<int>(partners.size());
  std::vector<std::vector<double>> send_cells(npart), recv_cells(npart);
  std::vector<int> send_n(npart), recv_n(npart);
  for (int k = 0; k < npart; ++k) {
    const double* pbox = &rank_boxes[6 * partners[k]];
    for (size_t m = 0; m < my_cells.size(); ++m) {
      const double* cb = &my_boxes[6 * m];
      bool near = false;
      for (int sh = 0; sh < nshift && !near; ++sh)
        near = box_gap2(cb, sh, pbox) <= reach2;
      if (!near) continue;
      send_cells[k].push_back(static_cast<double>(my_cells[m]));
      send_cells[k].insert(send_cells[k].end(), cb, cb + 6);
    }
    send_n[k] = static_cast<int>(send_cells[k].size());
  }
  {
    std::vector<MPI_Request> req(2 * npart);
    for (int k = 0; k < npart; ++k) {
      MPI_Irecv(&recv_n[k], 1, MPI_INT, partners[k], 1, world, &req[2 * k]);
      MPI_Isend(&send_n[k], 1, MPI_INT, partners[k], 1, world, &req[2 * k + 1]);
    }
    MPI_Waitall(2 * npart, req.data(), MPI_STATUSES_IGNORE);
    for (int k = 0; k < npart; ++k) {
      recv_cells[k].resize(recv_n[k]);
      MPI_Irecv(recv_cells[k].data(), recv_n[k], MPI_DOUBLE, partners[k], 2, world, &req[2 * k]);
      MPI_Isend(send_cells[k].data(), send_n[k], MPI_DOUBLE, partners[k], 2, world,
                &req[2 * k + 1]);
    }
    MPI_Waitall(2 * npart, req.data(), MPI_STATUSES_IGNORE);
  }
  // Cover cells of my partners and me, as (cell, rank, atom box) sorted by cell and rank.
  cell_owner_.clear();
  auto add_owner = [&](std::int64_t cell, int rank, const double* box) {
    CellOwner co;
    co.cell = cell;
    co.rank = rank;
    std::copy(box, box + 6, co.box);
    cell_owner_.push_back(co);
  };
  for (size_t m = 0; m < my_cells.size(); ++m)
    add_owner(my_cells[m], me, &my_boxes[6 * m]);
  for (int k = 0; k < npart; ++k)
    for (int r = 0; r + 6 < recv_n[k]; r += 7)
      add_owner(static_cast<std::int64_t>(recv_cells[k][r]), partners[k], &recv_cells[k][r + 1]);
  std::sort(cell_owner_.begin(), cell_owner_.end(), [](const CellOwner& a, const CellOwner& b) {
    return a.cell != b.cell ? a.cell < b.cell : a.rank < b.rank;
  });

  // Constant-time lookup of a cell's owners over a window: my span widened by the stencil (a
  // cell outside it is beyond the reach of every cell of mine).
  std::int64_t win_lo[3] = {0, 0, 0}, win_n[3] = {1, 1, 1};
  for (int d = 0; d < dim; ++d) {
    win_lo[d] = span_lo[d] - kStencil, win_n[d] = span_n[d] + 2 * kStencil;
    if (periodic[d]) {
      if (win_n[d] >= ncell[d]) win_lo[d] = 0, win_n[d] = ncell[d];
      win_lo[d] = (win_lo[d] + ncell[d]) % ncell[d];
    } else {
      const std::int64_t hi = std::min(ncell[d], win_lo[d] + win_n[d]);
      win_lo[d] = std::max<std::int64_t>(0, win_lo[d]), win_n[d] = hi - win_lo[d];
    }
  }
  auto window_slot = [&](const std::int64_t c[3]) -> std::int64_t {
    std::int64_t slot = 0;
    for (int d = 2; d >= 0; --d) {
      std::int64_t t = c[d] - win_lo[d];
      if (periodic[d] && t < 0) t += ncell[d];
      if (t < 0 || t >= win_n[d]) return -1;
      slot = slot * win_n[d] + t;
    }
    return slot;
  };
  owner_slot_.assign(win_n[0] * win_n[1] * win_n[2], -1);
  for (size_t k = 0; k < cell_owner_.size(); ++k)
    if (k == 0 || cell_owner_[k].cell != cell_owner_[k - 1].cell) {
      std::int64_t c[3];
      cell_coords(cell_owner_[k].cell, c);
      const std::int64_t slot = window_slot(c);
      if (slot >= 0) owner_slot_[slot] = static_cast<std::int64_t>(k);
    }
  auto owners = [&](const std::int64_t c[3]) {
    const std::int64_t slot = window_slot(c);
    const std::int64_t id = cell_id(c[0], c[1], c[2]);
    if (slot < 0 || owner_slot_[slot] < 0) return std::make_pair(std::int64_t(0), std::int64_t(0));
    std::int64_t last = owner_slot_[slot];
    while (last < static_cast<std::int64_t>(cell_owner_.size()) && cell_owner_[last].cell == id)
      ++last;
    return std::make_pair(owner_slot_[slot], last);
  };

  const int zr = dim == 3 ? kStencil : 0;

  for (int iswap = 0; iswap < nswap; ++iswap)
    sendnum[iswap] = 0;
  auto shift_index = [&](const int sh[3]) {
    for (int s = 0; s < nshift; ++s)
      if (shifts_[s][0] == sh[0] && shifts_[s][1] == sh[1] && shifts_[s][2] == sh[2]) return s;
    return -1;
  };

  // Per cell of mine, once: the nearby cells (within the cutoff of the cell) whose owners need
  // images from it. Interior cells get none, so their atoms cost nothing below.
  cand_start_.assign(my_cells.size() + 1, 0);
  cands_.clear();
  for (size_t m = 0; m < my_cells.size(); ++m) {
    std::int64_t c[3];
    cell_coords(my_cells[m], c);
    for (int dz = -zr; dz <= zr; ++dz)
      for (int dy = -kStencil; dy <= kStencil; ++dy)
        for (int dx = -kStencil; dx <= kStencil; ++dx) {
          const int off[3] = {dx, dy, dz};
          Candidate cand;
          std::int64_t n[3];
          int sh[3] = {0, 0, 0};
          bool valid = true;
          double gap2 = 0;
          for (int d = 0; d < 3 && valid; ++d) {
            n[d] = c[d] + off[d];
            if (d < dim) {
              const double gap = std::max(0.0, (std::abs(off[d]) - 1) * cell_size[d]);
              gap2 += gap * gap;
            }
            if (n[d] < 0 || n[d] >= ncell[d]) {
              if (!periodic[d] || d >= dim || std::abs(off[d]) > ncell[d]) {
                valid = false;
                break;
              }
              // Across the boundary: the owners there need the image of the atom shifted into
              // their side of the box.
              sh[d] = n[d] < 0 ? 1 : -1;
              n[d] = n[d] < 0 ? n[d] + ncell[d] : n[d] - ncell[d];
            }
          }
          if (!valid || gap2 > cut2) continue;
          const auto range = owners(n);
          const bool unshifted = sh[0] == 0 && sh[1] == 0 && sh[2] == 0;
          bool useful = false;
          for (std::int64_t o = range.first; o < range.second && !useful; ++o)
            useful = !(cell_owner_[o].rank == me && unshifted);
          if (!useful) continue;
          for (int d = 0; d < 3; ++d) { // the cell's bounds in my frame (unwrapped)
            cand.lo[d] = boxlo[d] + (c[d] + off[d]) * cell_size[d];
            cand.hi[d] = cand.lo[d] + cell_size[d];
          }
          cand.shift = shift_index(sh);
          cand.first = range.first;
          cand.last = range.second;
          cands_.push_back(cand);
        }
    cand_start_[m + 1] = static_cast<std::int64_t>(cands_.size());
  }

  std::vector<int> targets; // swap indices this atom goes to, deduplicated
  for (int i = 0; i < nlocal; ++i) {
    const size_t m = my_cell_of[i];
    targets.clear();
    if (cover_brick_) {
      for (int s = 0; s < nshift; ++s) {
        double y[3];
        for (int d = 0; d < 3; ++d)
          y[d] = x[i][d] + shifts_[s][d] * prd[d];
        for (int qb = 0; qb < nprocs * nbox; ++qb) {
          const int q = qb / nbox;
          if (q == me && s == 0) continue;
          const double* b = &bricks[6 * qb];
          bool empty = false;
          double dist2 = 0;
          for (int d = 0; d < dim; ++d) {
            if (b[d] > b[3 + d]) empty = true;
            const double gap = std::max({b[d] - y[d], 0.0, y[d] - b[3 + d]});
            dist2 += gap * gap;
          }
          if (empty || dist2 > cut2) continue;
          const int iswap = ((q - me + nprocs) % nprocs) * nshift + s;
          if (std::find(targets.begin(), targets.end(), iswap) == targets.end())
            targets.push_back(iswap);
        }
      }
    }
    if (cand_start_[m] == cand_start_[m + 1] && targets.empty()) continue; // interior
    for (std::int64_t k = cand_start_[m]; k < cand_start_[m + 1]; ++k) {
      const Candidate& cd = cands_[k];
      double dist2 = 0;
      for (int d = 0; d < dim; ++d) {
        const double gap = std::max({cd.lo[d] - x[i][d], 0.0, x[i][d] - cd.hi[d]});
        dist2 += gap * gap;
      }
      if (dist2 > cut2) continue;
      double y[3]; // the image of atom i that the candidate's owners would see
      for (int d = 0; d < 3; ++d)
        y[d] = x[i][d] + shifts_[cd.shift][d] * prd[d];
      for (std::int64_t o = cd.first; o < cd.last; ++o) {
        const int q = cell_owner_[o].rank;
        if (q == me && cd.shift == 0) continue; // an owned atom is no ghost of itself
        const double* b = cell_owner_[o].box;
        double gap2 = 0;
        for (int d = 0; d < dim; ++d) {
          const double gap = std::max({b[d] - y[d], 0.0, y[d] - b[3 + d]});
          gap2 += gap * gap;
        }
        if (gap2 > cut2) continue; // no atom of q in that cell is within reach
        const int iswap = ((q - me + nprocs) % nprocs) * nshift + cd.shift;
        if (std::find(targets.begin(), targets.end(), iswap) == targets.end())
          targets.push_back(iswap);
      }
    }
    for (int iswap : targets) {
      if (sendnum[iswap] == maxsendlist[iswap]) grow_list(iswap, sendnum[iswap]);
      sendlist[iswap][sendnum[iswap]++] = i;
    }
  }

  int smax = 0, rmax = 0;
  for (int iswap = 0; iswap < nswap; ++iswap) {
    const int nsend = sendnum[iswap];
    if (nsend * size_border > maxsend) grow_send(nsend * size_border, 0);
    const int n =
        ghost_velocity
            ? avec->pack_border_vel(nsend, sendlist[iswap], buf_send, pbc_flag[iswap], pbc[iswap])
            : avec->pack_border(nsend, sendlist[iswap], buf_send, pbc_flag[iswap], pbc[iswap]);
    int nrecv = 0;
    double* buf = buf_send;
    if (sendproc[iswap] != me) {
      MPI_Sendrecv(&nsend, 1, MPI_INT, sendproc[iswap], 0, &nrecv, 1, MPI_INT, recvproc[iswap], 0,
                   world, MPI_STATUS_IGNORE);
      if (nrecv * size_border > maxrecv) grow_recv(nrecv * size_border);
      MPI_Request request;
      if (nrecv)
        MPI_Irecv(buf_recv, nrecv * size_border, MPI_DOUBLE, recvproc[iswap], 0, world, &request);
      if (n) MPI_Send(buf_send, n, MPI_DOUBLE, sendproc[iswap], 0, world);
      if (nrecv) MPI_Wait(&request, MPI_STATUS_IGNORE);
      buf = buf_recv;
    } else {
      nrecv = nsend;
    }
    const int first = atom->nlocal + atom->nghost;
    if (ghost_velocity)
      avec->unpack_border_vel(nrecv, first, buf);
    else
      avec->unpack_border(nrecv, first, buf);

    smax = std::max(smax, nsend);
    rmax = std::max(rmax, nrecv);
    recvnum[iswap] = nrecv;
    size_forward_recv[iswap] = nrecv * size_forward;
    size_reverse_send[iswap] = nrecv * size_reverse;
    size_reverse_recv[iswap] = nsend * size_reverse;
    firstrecv[iswap] = first;
    atom->nghost += nrecv;
  }

  int max = std::max(maxforward * smax, maxreverse * rmax);
  if (max > maxsend) grow_send(max, 0);
  max = std::max(maxforward * rmax, maxreverse * smax);
  if (max > maxrecv) grow_recv(max);

  if (map_style) atom->map_set();
}
