// Graph-ownership forward/reverse communication: one aggregated message per partner rank.
//
// Every swap of a block goes to the same rank (one swap per periodic image), and every send list
// holds owned atoms only, so the swaps of a block are independent: their data travel in one
// buffer, segment after segment in swap order. Receives are posted first, then the sends, then
// one wait; the unpack callbacks run after it in a fixed order (reverse: the stock descending
// swap order), so results do not depend on the order in which messages arrive.
#include "comm_graph.h"

#include <algorithm>

#include "atom.h"
#include "atom_vec.h"
#include "compute.h"
#include "dump.h"
#include "fix.h"
#include "pair.h"

using namespace LAMMPS_NS;

namespace
{
constexpr int kTagForward = 1;
constexpr int kTagReverse = 2;
constexpr int kTagVariable = 6;
} // namespace

// Atoms sent (send side: owned atoms in the send lists) or received (ghosts) by block b.
int CommGraph::block_count(int b, bool send_side) const
{
  int n = 0;
  for (int s = 0; s < nshift_; ++s)
    n += send_side ? sendnum[b * nshift_ + s] : recvnum[b * nshift_ + s];
  return n;
}

// Forward: block b packs its send lists for me + k and unpacks the ghosts from me - k, per_atom
// doubles per atom (a fixed size). Block 0 (images of my own atoms) is copied locally.
void CommGraph::forward_blocks(int per_atom, const PackFn& pack, const UnpackFn& unpack, int tag)
{
  const int nblock = static_cast<int>(ring_.size());
  std::vector<size_t> recv_at(nblock + 1, 0), send_at(nblock + 1, 0);
  for (int b = 0; b < nblock; ++b) {
    recv_at[b + 1] = recv_at[b] + (b ? size_t(block_count(b, false)) * per_atom : 0);
    send_at[b + 1] = send_at[b] + (b ? size_t(block_count(b, true)) * per_atom : 0);
  }
  agg_recv_.resize(std::max<size_t>(recv_at[nblock], 1));
  agg_send_.resize(std::max<size_t>(send_at[nblock], 1));
  requests_.clear();
  for (int b = 1; b < nblock; ++b)
    if (recv_at[b + 1] > recv_at[b]) {
      requests_.emplace_back();
      MPI_Irecv(&agg_recv_[recv_at[b]], static_cast<int>(recv_at[b + 1] - recv_at[b]), MPI_DOUBLE,
                recvproc[b * nshift_], tag, gcomm_, &requests_.back());
    }
  for (int b = 1; b < nblock; ++b) {
    if (send_at[b + 1] == send_at[b]) continue;
    size_t at = send_at[b];
    for (int s = 0; s < nshift_; ++s) { // fixed segments: sizes known on both sides
      const int iswap = b * nshift_ + s;
      if (sendnum[iswap]) pack(iswap, &agg_send_[at]);
      at += size_t(sendnum[iswap]) * per_atom;
    }
    requests_.emplace_back();
    MPI_Isend(&agg_send_[send_at[b]], static_cast<int>(send_at[b + 1] - send_at[b]), MPI_DOUBLE,
              sendproc[b * nshift_], tag, gcomm_, &requests_.back());
  }
  for (int s = 0; s < nshift_ && nblock; ++s) // my own periodic images, while messages fly
    if (sendnum[s]) {
      self_buf_.resize(size_t(sendnum[s]) * per_atom + 1);
      pack(s, self_buf_.data());
      unpack(s, self_buf_.data());
    }
  MPI_Waitall(static_cast<int>(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE);
  for (int b = 1; b < nblock; ++b) {
    size_t at = recv_at[b];
    for (int s = 0; s < nshift_; ++s) {
      const int iswap = b * nshift_ + s;
      if (recvnum[iswap]) unpack(iswap, &agg_recv_[at]);
      at += size_t(recvnum[iswap]) * per_atom;
    }
  }
}

// Reverse: block b packs its ghosts for me - k and unpacks into its send lists what me + k
// returns. Unpacked in the stock order (descending swaps, my own images last), since unpacking
// adds into owned atoms and the order of a floating-point sum matters.
void CommGraph::reverse_blocks(int per_atom, const PackFn& pack, const UnpackFn& unpack, int tag)
{
  const int nblock = static_cast<int>(ring_.size());
  std::vector<size_t> recv_at(nblock + 1, 0), send_at(nblock + 1, 0);
  for (int b = 0; b < nblock; ++b) {
    recv_at[b + 1] = recv_at[b] + (b ? size_t(block_count(b, true)) * per_atom : 0);
    send_at[b + 1] = send_at[b] + (b ? size_t(block_count(b, false)) * per_atom : 0);
  }
  agg_recv_.resize(std::max<size_t>(recv_at[nblock], 1));
  agg_send_.resize(std::max<size_t>(send_at[nblock], 1));
  requests_.clear();
  for (int b = 1; b < nblock; ++b)
    if (recv_at[b + 1] > recv_at[b]) {
      requests_.emplace_back();
      MPI_Irecv(&agg_recv_[recv_at[b]], static_cast<int>(recv_at[b + 1] - recv_at[b]), MPI_DOUBLE,
                sendproc[b * nshift_], tag, gcomm_, &requests_.back());
    }
  for (int b = 1; b < nblock; ++b) {
    if (send_at[b + 1] == send_at[b]) continue;
    size_t at = send_at[b];
    for (int s = 0; s < nshift_; ++s) {
      const int iswap = b * nshift_ + s;
      if (recvnum[iswap]) pack(iswap, &agg_send_[at]);
      at += size_t(recvnum[iswap]) * per_atom;
    }
    requests_.emplace_back();
    MPI_Isend(&agg_send_[send_at[b]], static_cast<int>(send_at[b + 1] - send_at[b]), MPI_DOUBLE,
              recvproc[b * nshift_], tag, gcomm_, &requests_.back());
  }
  MPI_Waitall(static_cast<int>(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE);
  for (int b = nblock - 1; b >= 0; --b) {
    size_t at = recv_at[b + 1];
    for (int s = nshift_ - 1; s >= 0; --s) {
      const int iswap = b * nshift_ + s;
      if (!sendnum[iswap]) continue;
      if (b == 0) {
        self_buf_.resize(size_t(recvnum[iswap]) * per_atom + 1);
        pack(iswap, self_buf_.data());
        unpack(iswap, self_buf_.data());
        continue;
      }
      at -= size_t(sendnum[iswap]) * per_atom;
      unpack(iswap, &agg_recv_[at]);
    }
  }
}

// Variable sizes (a fix's own count per call): each block's message starts with its segment
// lengths; the receiver learns the total from the message itself (probe), one message per
// partner still. Forward: send lists -> ghosts; reverse: ghosts -> send lists.
void CommGraph::forward_blocks_variable(int max_per_atom, const PackFn& pack,
                                        const UnpackFn& unpack, bool reverse)
{
  const int nblock = static_cast<int>(ring_.size());
  std::vector<std::vector<double>> out(nblock), in(nblock);
  requests_.clear();
  for (int b = 1; b < nblock; ++b) {
    const int count = block_count(b, !reverse);
    if (!count) continue;
    std::vector<double>& msg = out[b];
    msg.assign(nshift_, 0.0);
    for (int s = 0; s < nshift_; ++s) {
      const int iswap = b * nshift_ + s, n = reverse ? recvnum[iswap] : sendnum[iswap];
      const size_t at = msg.size();
      msg.resize(at + size_t(n) * max_per_atom + bufextra + 1);
      const int used = n ? pack(iswap, &msg[at]) : 0;
      msg.resize(at + used);
      msg[s] = used;
    }
    requests_.emplace_back();
    MPI_Isend(msg.data(), static_cast<int>(msg.size()), MPI_DOUBLE,
              reverse ? recvproc[b * nshift_] : sendproc[b * nshift_], kTagVariable, gcomm_,
              &requests_.back());
  }
  for (int b = 1; b < nblock; ++b) {
    if (!block_count(b, reverse)) continue;
    const int from = reverse ? sendproc[b * nshift_] : recvproc[b * nshift_];
    MPI_Status st;
    int n = 0;
    MPI_Probe(from, kTagVariable, gcomm_, &st);
    MPI_Get_count(&st, MPI_DOUBLE, &n);
    in[b].resize(std::max(n, 1));
    MPI_Recv(in[b].data(), n, MPI_DOUBLE, from, kTagVariable, gcomm_, MPI_STATUS_IGNORE);
  }
  MPI_Waitall(static_cast<int>(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE);
  for (int bb = 0; bb < nblock; ++bb) {
    const int b = reverse ? nblock - 1 - bb : bb;
    std::vector<size_t> at(nshift_ + 1, nshift_); // segment starts after the header
    for (int s = 0; s < nshift_ && b; ++s)
      at[s + 1] = at[s] + (in[b].size() > size_t(s) ? static_cast<size_t>(in[b][s]) : 0);
    for (int ss = 0; ss < nshift_; ++ss) {
      const int s = reverse ? nshift_ - 1 - ss : ss, iswap = b * nshift_ + s;
      if (!(reverse ? sendnum[iswap] : recvnum[iswap])) continue;
      if (b == 0) {
        self_buf_.resize(size_t(reverse ? recvnum[iswap] : sendnum[iswap]) * max_per_atom +
                         bufextra + 1);
        pack(iswap, self_buf_.data());
        unpack(iswap, self_buf_.data());
      } else {
        unpack(iswap, &in[b][at[s]]);
      }
    }
  }
}

// ---- the host's entry points -------------------------------------------------------------------

void CommGraph::forward_comm(int dummy)
{
  if (!graph_mode_) {
    Comm::forward_comm(dummy);
    return;
  }
  AtomVec* avec = atom->avec;
  const bool vel = ghost_velocity != 0;
  forward_blocks(
      size_forward,
      [&](int i, double* buf) {
        return vel ? avec->pack_comm_vel(sendnum[i], sendlist[i], buf, pbc_flag[i], pbc[i])
                   : avec->pack_comm(sendnum[i], sendlist[i], buf, pbc_flag[i], pbc[i]);
      },
      [&](int i, double* buf) {
        if (vel)
          avec->unpack_comm_vel(recvnum[i], firstrecv[i], buf);
        else
          avec->unpack_comm(recvnum[i], firstrecv[i], buf);
      },
      kTagForward);
}

void CommGraph::reverse_comm()
{
  if (!graph_mode_) {
    Comm::reverse_comm();
    return;
  }
  AtomVec* avec = atom->avec;
  reverse_blocks(
      size_reverse,
      [&](int i, double* buf) { return avec->pack_reverse(recvnum[i], firstrecv[i], buf); },
      [&](int i, double* buf) { avec->unpack_reverse(sendnum[i], sendlist[i], buf); }, kTagReverse);
}

// Pairs, fixes, computes and dumps return their per-atom size from pack (the stock loop sizes its
// receives by it); asking with no atoms tells it before any receive is posted.
template <class Obj> void CommGraph::forward_object(Obj* obj)
{
  if (nswap == 0) return;
  self_buf_.resize(std::max<size_t>(self_buf_.size(), 1));
  const int per_atom = obj->pack_comm(0, sendlist[0], self_buf_.data(), pbc_flag[0], pbc[0]);
  forward_blocks(
      per_atom,
      [&](int i, double* buf) {
        obj->pack_comm(sendnum[i], sendlist[i], buf, pbc_flag[i], pbc[i]);
        return sendnum[i] * per_atom;
      },
      [&](int i, double* buf) { obj->unpack_comm(recvnum[i], firstrecv[i], buf); }, kTagForward);
}

template <class Obj> void CommGraph::reverse_object(Obj* obj)
{
  if (nswap == 0) return;
  self_buf_.resize(std::max<size_t>(self_buf_.size(), 1));
  const int per_atom = obj->pack_reverse_comm(0, firstrecv[0], self_buf_.data());
  reverse_blocks(
      per_atom,
      [&](int i, double* buf) {
        obj->pack_reverse_comm(recvnum[i], firstrecv[i], buf);
        return recvnum[i] * per_atom;
      },
      [&](int i, double* buf) { obj->unpack_reverse_comm(sendnum[i], sendlist[i], buf); },
      kTagReverse);
}

void CommGraph::forward_comm_pair(Pair* pair)
{
  if (!graph_mode_) return Comm::forward_comm_pair(pair);
  forward_object(pair);
}

void CommGraph::reverse_comm_pair(Pair* pair)
{
  if (!graph_mode_) return Comm::reverse_comm_pair(pair);
  reverse_object(pair);
}

void CommGraph::forward_comm_fix(Fix* fix)
{
  if (!graph_mode_) return Comm::forward_comm_fix(fix);
  forward_object(fix);
}

void CommGraph::reverse_comm_fix(Fix* fix)
{
  if (!graph_mode_) return Comm::reverse_comm_fix(fix);
  reverse_object(fix);
}

void CommGraph::forward_comm_compute(Compute* compute)
{
  if (!graph_mode_) return Comm::forward_comm_compute(compute);
  forward_object(compute);
}

void CommGraph::reverse_comm_compute(Compute* compute)
{
  if (!graph_mode_) return Comm::reverse_comm_compute(compute);
  reverse_object(compute);
}

void CommGraph::forward_comm_dump(Dump* dump)
{
  if (!graph_mode_) return Comm::forward_comm_dump(dump);
  forward_object(dump);
}

void CommGraph::reverse_comm_dump(Dump* dump)
{
  if (!graph_mode_) return Comm::reverse_comm_dump(dump);
  reverse_object(dump);
}

void CommGraph::forward_comm_variable_fix(Fix* fix)
{
  if (!graph_mode_) return Comm::forward_comm_variable_fix(fix);
  forward_blocks_variable(
      std::max(maxforward, fix->comm_forward),
      [&](int i, double* buf) {
        return fix->pack_comm(sendnum[i], sendlist[i], buf, pbc_flag[i], pbc[i]);
      },
      [&](int i, double* buf) { fix->unpack_comm(recvnum[i], firstrecv[i], buf); }, false);
}

void CommGraph::reverse_comm_variable_fix(Fix* fix)
{
  if (!graph_mode_) return Comm::reverse_comm_variable_fix(fix);
  forward_blocks_variable(
      std::max(maxreverse, fix->comm_reverse),
      [&](int i, double* buf) { return fix->pack_reverse_comm(recvnum[i], firstrecv[i], buf); },
      [&](int i, double* buf) { fix->unpack_reverse_comm(sendnum[i], sendlist[i], buf); }, true);
}
