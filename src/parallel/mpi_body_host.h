// The MPI half of a host's BodyHost: this rank, reductions over a communicator, and the
// neighbour exchange of distributed bodies (both hosts add their output and errors).
#pragma once

#include <mpi.h>

#include "body/body_driver.h"

namespace fracdem
{

// Sets host.rank, nprocs, sum, max, min, max_int, gather, scatter, all_gather, exchange and
// shared_sum_for over comm.
void add_mpi_services(BodyHost& host, MPI_Comm comm);

} // namespace fracdem
