// MPI exchange of a distributed body's shared-node values: one message per neighbouring part.
#pragma once

#include <mpi.h>

#include <vector>

#include "body/body_partition.h"

namespace fracdem
{

// Sums per-node vectors over the parts that share each node (InterfaceSum), one part per rank of
// `comm` (part p on rank p). One communication posts every receive, then every send (one message
// per neighbouring part, width doubles per shared node, no node ids), then waits once: no chain
// of blocking swaps, no collective.
class NodeExchange
{
public:
  NodeExchange(MPI_Comm comm, const MeshPart& part);
  // field: width doubles per local node, this part's contributions; afterwards the shared
  // nodes hold the sum over their sharers (the same bits on every sharer).
  void sum(double* field, int width);
  const InterfaceSum& interface() const { return sum_; }

private:
  MPI_Comm comm_;
  std::vector<int> ranks_; // neighbour parts = ranks
  InterfaceSum sum_;
  std::vector<std::vector<double>> send_, recv_;
  std::vector<MPI_Request> requests_;
};

} // namespace fracdem
