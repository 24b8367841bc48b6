// MPI exchange of a distributed body's shared-node values (see node_exchange.h).
#include "node_exchange.h"

namespace fracdem
{

namespace
{
constexpr int kTag = 7301; // fracdem node exchange
}

NodeExchange::NodeExchange(MPI_Comm comm, const MeshPart& part) : comm_(comm), sum_(part)
{
  for (const PartNeighbour& nb : part.neighbours)
    ranks_.push_back(nb.part);
  send_.resize(ranks_.size());
  recv_.resize(ranks_.size());
  requests_.resize(2 * ranks_.size());
}

void NodeExchange::sum(double* field, int width)
{
  const int nk = static_cast<int>(ranks_.size());
  for (int k = 0; k < nk; ++k) {
    recv_[k].resize(sum_.message_size(k, width));
    MPI_Irecv(recv_[k].data(), static_cast<int>(recv_[k].size()), MPI_DOUBLE, ranks_[k], kTag,
              comm_, &requests_[k]);
  }
  for (int k = 0; k < nk; ++k) {
    sum_.pack(k, field, width, send_[k]);
    MPI_Isend(send_[k].data(), static_cast<int>(send_[k].size()), MPI_DOUBLE, ranks_[k], kTag,
              comm_, &requests_[nk + k]);
  }
  MPI_Waitall(2 * nk, requests_.data(), MPI_STATUSES_IGNORE);
  sum_.combine(field, width, recv_);
}

} // namespace fracdem
