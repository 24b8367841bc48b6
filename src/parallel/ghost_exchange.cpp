// MPI transport of a distributed body's facet ghosts (see ghost_exchange.h).
#include "ghost_exchange.h"

#include <cstddef>

namespace fracdem
{

void sparse_exchange(MPI_Comm comm, int tag, const std::vector<int>& to,
                     const std::vector<std::vector<double>>& out, const std::vector<int>& from,
                     std::vector<std::vector<double>>& in)
{
  std::vector<MPI_Request> requests(to.size());
  for (std::size_t k = 0; k < to.size(); ++k)
    MPI_Isend(out[k].data(), static_cast<int>(out[k].size()), MPI_DOUBLE, to[k], tag, comm,
              &requests[k]);
  in.resize(from.size());
  for (std::size_t k = 0; k < from.size(); ++k) {
    MPI_Status status;
    MPI_Probe(from[k], tag, comm, &status);
    int count = 0;
    MPI_Get_count(&status, MPI_DOUBLE, &count);
    in[k].resize(count);
    MPI_Recv(in[k].data(), count, MPI_DOUBLE, from[k], tag, comm, MPI_STATUS_IGNORE);
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
}

std::vector<double> all_gather(MPI_Comm comm, const std::vector<double>& mine)
{
  int size = 1;
  MPI_Comm_size(comm, &size);
  std::vector<double> all(mine.size() * size);
  MPI_Allgather(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, all.data(),
                static_cast<int>(mine.size()), MPI_DOUBLE, comm);
  return all;
}

} // namespace fracdem
