// Zoltan's geometric partitioners (RCB, RIB, HSFC) on the particles where they are: each rank
// hands Zoltan its own positions and cost weights and gets the new owner of each.
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

#include "ptscotch_partition.h"

struct Zoltan_Struct;

namespace fracdem::balance
{

// One Zoltan object per balancing fix, kept between repartitions: RCB reuses its previous cuts
// as the first guesses of the next (RCB_REUSE), so a repartition after a small drift moves the
// cuts a little instead of cutting anew.
class ZoltanGeometric
{
public:
  // `method` is Zoltan's LB_METHOD (RCB, RIB or HSFC); `name` the partitioner's keyword, used in
  // failures.
  ZoltanGeometric(std::string method, std::string name, MPI_Comm comm);
  ~ZoltanGeometric();
  ZoltanGeometric(const ZoltanGeometric&) = delete;
  ZoltanGeometric& operator=(const ZoltanGeometric&) = delete;

  // Collective. nparts parts within `tolerance` (Zoltan's IMBALANCE_TOL) of this rank's vertices:
  // `coords` holds dim numbers per vertex, `weight` one per vertex. The parts are relabelled so
  // that most of the weight stays with its rank (distributed_labels); then the imbalance of the
  // weights (edge_cut is left 0: the caller measures it on its graph). Never throws: a failure
  // (Zoltan's, bad arguments, or a build without Zoltan) is agreed by all ranks and reported in
  // `failure` with the rank count and vertex count.
  DistributedResult partition(const std::vector<double>& coords, int dim,
                              const std::vector<double>& weight, int nparts, double tolerance);

private:
  DistributedResult run(const std::vector<double>& coords, int dim,
                        const std::vector<double>& weight, int nparts, double tolerance);

  std::string method_, name_;
  MPI_Comm comm_;
  Zoltan_Struct* zz_ = nullptr;
};

} // namespace fracdem::balance
