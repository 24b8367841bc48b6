// MPI transport of a distributed body's facet ghosts: a sparse exchange between known partners
// and the gather of every rank's boxes.
#pragma once

#include <mpi.h>

#include <vector>

namespace fracdem
{

// Sends out[k] to rank to[k] and receives in[k] from rank from[k] (lengths unknown to the
// receiver: probed). Every send is posted first, then each receive, then one wait: one message
// per partner, no collective. tag: one per round, so rounds of a step never mix.
void sparse_exchange(MPI_Comm comm, int tag, const std::vector<int>& to,
                     const std::vector<std::vector<double>>& out, const std::vector<int>& from,
                     std::vector<std::vector<double>>& in);

// Every rank's `mine` (the same length on each), in rank order, on every rank.
std::vector<double> all_gather(MPI_Comm comm, const std::vector<double>& mine);

} // namespace fracdem
