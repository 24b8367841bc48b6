// The MPI half of a host's BodyHost (see mpi_body_host.h).
#include "mpi_body_host.h"

#include <functional>
#include <memory>

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
  host.shared_sum_for = [comm](const MeshPart& part) {
    auto exchange = std::make_shared<NodeExchange>(comm, part);
    return std::function<void(double*, int)>(
        [exchange](double* field, int width) { exchange->sum(field, width); });
  };
}

} // namespace fracdem
