// The MPI half of a host's BodyHost (see mpi_body_host.h).
#include "mpi_body_host.h"

#include <functional>
#include <memory>
#include <vector>

#include "ghost_exchange.h"
#include "node_exchange.h"

namespace fracdem
{

void add_mpi_services(BodyHost& host, MPI_Comm comm)
{
  MPI_Comm_rank(comm, &host.rank);
  MPI_Comm_size(comm, &host.nprocs);
  auto reduce = [comm](MPI_Op op) {
    return
        [comm, op](double* a, int n) { MPI_Allreduce(MPI_IN_PLACE, a, n, MPI_DOUBLE, op, comm); };
  };
  host.sum = reduce(MPI_SUM);
  host.max = reduce(MPI_MAX);
  host.min = reduce(MPI_MIN);
  host.max_int = [comm](int* a, int n) {
    MPI_Allreduce(MPI_IN_PLACE, a, n, MPI_INT, MPI_MAX, comm);
  };
  host.gather = [comm](const std::vector<double>& mine) {
    int rank = 0, size = 1;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    int count = static_cast<int>(mine.size());
    std::vector<int> counts(rank == 0 ? size : 0), starts(rank == 0 ? size : 0);
    MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
    std::vector<double> all;
    if (rank == 0) {
      for (int r = 1; r < size; ++r)
        starts[r] = starts[r - 1] + counts[r - 1];
      all.resize(static_cast<size_t>(starts[size - 1]) + counts[size - 1]);
    }
    MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), starts.data(),
                MPI_DOUBLE, 0, comm);
    return all;
  };
  host.scatter = [comm](const std::function<std::vector<double>(int)>& make) {
    constexpr int kPartTag = 7320; // fracdem body parts at set-up (node exchange: 7301)
    int rank = 0, size = 1;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    if (rank == 0) {
      for (int r = 1; r < size; ++r) {
        const std::vector<double> message = make(r);
        MPI_Send(message.data(), static_cast<int>(message.size()), MPI_DOUBLE, r, kPartTag, comm);
      }
      return make(0);
    }
    MPI_Status status;
    MPI_Probe(0, kPartTag, comm, &status);
    int count = 0;
    MPI_Get_count(&status, MPI_DOUBLE, &count);
    std::vector<double> message(count);
    MPI_Recv(message.data(), count, MPI_DOUBLE, 0, kPartTag, comm, MPI_STATUS_IGNORE);
    return message;
  };
  host.all_gather = [comm](const std::vector<double>& mine) { return all_gather(comm, mine); };
  host.exchange = [comm](int round, const std::vector<int>& to,
                         const std::vector<std::vector<double>>& out, const std::vector<int>& from,
                         std::vector<std::vector<double>>& in) {
    constexpr int kGhostTag = 7310; // fracdem facet ghosts (node exchange: 7301)
    sparse_exchange(comm, kGhostTag + round, to, out, from, in);
  };
  host.shared_sum_for = [comm](const MeshPart& part) {
    auto exchange = std::make_shared<NodeExchange>(comm, part);
    return std::function<void(double*, int)>(
        [exchange](double* field, int width) { exchange->sum(field, width); });
  };
}

} // namespace fracdem
