// Graph-ownership communicator: set-up, swap blocks, and the exchange of atoms to their owners.
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
#include "lmptype.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"

using namespace LAMMPS_NS;

namespace
{
constexpr int kExchangeSlack = 1000; // doubles beyond the per-atom maximum, as the stock comm
constexpr int kTagExchange = 5;
} // namespace

CommGraph::CommGraph(LAMMPS* lmp) : Comm(lmp) {}

CommGraph::~CommGraph()
{
  report_borders_stats();
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (gcomm_ != MPI_COMM_NULL && !finalized) MPI_Comm_free(&gcomm_);
}

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
  // Our own communicator: wildcard probes (exchange) and per-partner tags never see host traffic.
  if (gcomm_ == MPI_COMM_NULL) MPI_Comm_dup(world, &gcomm_);
  graph_mode_ = true;
  // New swap pattern and neighbour bins that span the whole box; exchange() restores the brick.
  setup();
  if (neighbor->style) neighbor->setup_bins();
  domain->set_local_box();
}

void CommGraph::build_shifts()
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
  nshift_ = static_cast<int>(shifts_.size());
  std::fill(shift_of_, shift_of_ + 27, 0);
  for (int s = 0; s < nshift_; ++s)
    shift_of_[(shifts_[s][0] + 1) + 3 * (shifts_[s][1] + 1) + 9 * (shifts_[s][2] + 1)] = s;
}

// Blocks of swaps for the ring offsets that reach a partner in either direction (the partner
// relation is symmetric, so both ends of every message agree on its block), offset 0 first.
void CommGraph::build_blocks()
{
  ring_.assign(1, 0);
  for (int p : partners_) {
    ring_.push_back((p - me + nprocs) % nprocs);
    ring_.push_back((me - p + nprocs) % nprocs);
  }
  std::sort(ring_.begin(), ring_.end());
  ring_.erase(std::unique(ring_.begin(), ring_.end()), ring_.end());
  block_to_.assign(nprocs, -1);
  nswap = static_cast<int>(ring_.size()) * nshift_;
  if (nswap > maxswap) grow_swap(nswap);
  for (size_t b = 0; b < ring_.size(); ++b) {
    const int k = ring_[b];
    block_to_[(me + k) % nprocs] = static_cast<int>(b);
    for (int s = 0; s < nshift_; ++s) {
      const int iswap = static_cast<int>(b) * nshift_ + s;
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
  // Images are shifted by one box length at most (the stock comm chains swaps instead).
  for (int d = 0; d < domain->dimension; ++d)
    if (domain->periodicity[d] && cut >= domain->prd[d]) {
      char msg[256];
      snprintf(msg, sizeof msg,
               "Graph ownership needs the ghost cutoff (%g) below the periodic box length (%g)",
               cut, domain->prd[d]);
      error->all(FLERR, msg);
    }
  build_shifts();
  // No ghosts until the next borders(), which builds the blocks for the partners it finds.
  nswap = 0;
  ring_.clear();
  // Neighbour bins are laid out over domain->sublo/subhi by the setup_bins() call that follows;
  // owned atoms may lie anywhere in the box, so the bins must span all of it.
  for (int d = 0; d < 3; ++d) {
    domain->sublo[d] = domain->boxlo[d];
    domain->subhi[d] = domain->boxhi[d];
  }
}

// Moves every atom that leaves to another rank (or through a non-periodic boundary) out of the
// local arrays, packed per destination into out_buf_. Returns the number packed for others.
int CommGraph::pack_leavers(std::vector<int>& dest)
{
  AtomVec* avec = atom->avec;
  const int* periodic = domain->periodicity;
  const double *lo = domain->boxlo, *hi = domain->boxhi;
  const int per_atom_max = maxexchange_atom + maxexchange_fix + kExchangeSlack;
  std::vector<double> scratch(per_atom_max);
  out_buf_.resize(nprocs);
  for (auto& b : out_buf_)
    b.clear();
  int nlocal = atom->nlocal, migrated = 0, i = 0;
  while (i < nlocal) {
    double* xi = atom->x[i];
    bool outside = false;
    for (int d = 0; d < domain->dimension; ++d)
      if (!periodic[d] && (xi[d] < lo[d] || xi[d] >= hi[d])) outside = true;
    if (outside || dest[i] != me) {
      if (!outside) { // through a scratch atom: growing the buffer would zero-fill the maximum
        const int n = avec->pack_exchange(i, scratch.data());
        out_buf_[dest[i]].insert(out_buf_[dest[i]].end(), scratch.begin(), scratch.begin() + n);
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
  return migrated;
}

// Sparse exchange with unknown senders (NBX, Hoefler et al. 2010): synchronous sends to the
// destinations only, receive whatever arrives, and once my sends are matched enter a non-blocking
// reduction; when it completes every message has been received. The reduction also sums the atom
// count (kept + sent per rank), which the stock exchange computes with its own Allreduce, so the
// exchange costs one collective, as the stock one does. Messages are unpacked in source order so
// that the local atom order does not depend on arrival order.
void CommGraph::migrate_sparse(int kept_and_sent)
{
  requests_.clear();
  for (int p = 0; p < nprocs; ++p)
    if (!out_buf_[p].empty()) {
      requests_.emplace_back();
      MPI_Issend(out_buf_[p].data(), static_cast<int>(out_buf_[p].size()), MPI_DOUBLE, p,
                 kTagExchange, gcomm_, &requests_.back());
    }
  std::vector<std::pair<int, std::vector<double>>> got;
  const bigint mine = kept_and_sent;
  bigint total = 0;
  MPI_Request reduction = MPI_REQUEST_NULL;
  bool reducing = false;
  for (;;) {
    int flag = 0;
    MPI_Status st;
    MPI_Iprobe(MPI_ANY_SOURCE, kTagExchange, gcomm_, &flag, &st);
    if (flag) {
      int n = 0;
      MPI_Get_count(&st, MPI_DOUBLE, &n);
      got.emplace_back(st.MPI_SOURCE, std::vector<double>(n));
      MPI_Recv(got.back().second.data(), n, MPI_DOUBLE, st.MPI_SOURCE, kTagExchange, gcomm_,
               MPI_STATUS_IGNORE);
    } else if (!reducing) {
      MPI_Testall(static_cast<int>(requests_.size()), requests_.data(), &flag, MPI_STATUSES_IGNORE);
      if (flag) {
        MPI_Iallreduce(&mine, &total, 1, MPI_LMP_BIGINT, MPI_SUM, gcomm_, &reduction);
        reducing = true;
      }
    } else {
      MPI_Test(&reduction, &flag, MPI_STATUS_IGNORE);
      if (flag) break;
    }
  }
  std::sort(got.begin(), got.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& msg : got) {
    size_t m = 0;
    while (m < msg.second.size())
      m += atom->avec->unpack_exchange(const_cast<double*>(&msg.second[m]));
  }
  atom->natoms = total;
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

  const int nlocal = atom->nlocal;
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

  const int migrated = pack_leavers(dest);
  migrate_sparse(atom->nlocal + migrated);
  if (time_next_migration_) migration_seconds_ += MPI_Wtime() - t_start;
  time_next_migration_ = false;
  last_migrated_ = migrated;
  if (atom->firstgroupname) atom->first_reorder();
}
