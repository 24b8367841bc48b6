// fix balance/graph: imbalance-triggered graph repartitioning driven by recorded per-particle
// costs; the policy lives in src/core/balance, this adapter measures and applies.
#ifndef FRACDEM_FIX_BALANCE_GRAPH_H
#define FRACDEM_FIX_BALANCE_GRAPH_H

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "balance/balance_check.h"
#include "balance/balance_report.h"
#include "balance/balance_spec.h"
#include "balance/cell_grid.h"
#include "balance/cost_pricing.h"
#include "balance/partition_strategy.h"
#include "balance_exchange.h"
#include "distributed_graph.h"
#include "zoltan_geometric.h"
#include "fix.h"

namespace LAMMPS_NS
{

class FixBalanceGraph : public Fix
{
public:
  FixBalanceGraph(class LAMMPS*, int, char**);
  ~FixBalanceGraph() override;

  int setmask() override;
  void init() override;
  void setup_pre_exchange() override;
  void pre_exchange() override;
  void setup(int) override;
  void initial_integrate(int) override;
  void final_integrate() override;
  void end_of_step() override;
  void pre_neighbor() override;
  void pre_force(int) override;
  int pack_comm(int, int*, double*, int, int*) override;
  void unpack_comm(int, int, double*) override;
  void post_force(int) override;
  double compute_scalar() override;
  double compute_vector(int) override;
  void write_restart(FILE*) override;
  void restart(char*) override;
  int pack_restart(int, double*) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;

private:
  // What one check read from the host on this rank.
  struct Measured {
    fracdem::balance::WorkCounts counts;
    std::vector<std::int64_t> edges; // (tag_i, tag_j, weight) or (cell_i, cell_j, weight)
    std::vector<std::int64_t> cell;  // cell of each particle (cell graph only)
    std::vector<int> ends;           // (i, j) host indices of each edge (distributed graph only)
  };

  fracdem::balance::BalanceSpec spec_;
  fracdem::balance::CheckSchedule schedule_;
  fracdem::balance::ImbalanceTrigger trigger_;
  fracdem::balance::CostPricing pricing_;
  fracdem::balance::PartitionStrategy strategy_;
  fracdem::balance::BalanceOutputs outputs_;
  fracdem::balance::CellGrid grid_;
  std::string layout_kind_; // partitioner layers: the layout last reported (rank 0)
  FILE* out_ = nullptr;
  class CommGraph* comm_graph_ = nullptr;
  std::vector<class FixWallGran*> primitive_walls_;
  std::vector<class FixFemBody*> fem_bodies_;
  // pair_style fracdem/gran with 'counts pair': contacts and bridges as the pair counted them.
  class PairFracdemGran* pair_counts_ = nullptr;
  // Thread CPU time of this rank's particle work (neighbour build, pair, and the post-force fixes
  // defined before this one: walls, FE contact) since the last check; the measured work.
  double cpu_work_ = 0, cpu_start_ = 0;
  // Integration: CPU clock at this fix's end_of_step (until the next initial_integrate) and at the
  // end of its post_force (until its final_integrate); negative when that bracket is not open.
  double cpu_step_end_ = -1, cpu_after_force_ = -1;
  bool cpu_from_neighbor_ = false;
  std::vector<double> owner_rank_; // per-atom output: the rank that owns the particle
  // Distributed graph: the global vertex number of each local and ghost particle (ghosts' from
  // their owners by forward communication).
  std::vector<double> vertex_number_;
  // partitioner zoltan-rcb|rib|hsfc: Zoltan's object, kept between repartitions (created at the
  // first).
  std::unique_ptr<fracdem::balance::ZoltanGeometric> geometric_;
  // From a restart file, until the set-up of the first run applies it: the ranks that owned the
  // particles (0: ownership was the host's), the cell owners, and each local particle's owner.
  int restored_ranks_ = 0;
  fracdem::balance::CellGrid restored_grid_;
  std::vector<int> restored_cells_, restored_owner_;

  void fail(const std::string& msg) const; // "fix balance/graph: MSG" on all ranks
  void log(const std::string& line) const; // screen and log file (rank 0 calls it)
  bool restore_ownership();
  fracdem::balance::BalanceSpec read_spec(int narg, char** arg) const;
  fracdem::balance::InteractionCosts start_costs() const;
  void find_work_fixes();
  std::vector<double> insert_limits() const;

  Measured measure();
  void bin_cells(Measured& m);
  void count_pairs(Measured& m) const;
  bool take_pair_counts(Measured& m) const;
  void count_walls_and_facets(Measured& m) const;
  void refit_costs(const Measured& m, double interval_steps);
  fracdem::balance::CheckRow check_row(const fracdem::balance::RankWork& work);
  void write_row(fracdem::balance::CheckRow row) const;

  void repartition(const Measured& m, const fracdem::balance::RankWork& work, double work_sum);
  void repartition_particles(const Measured& m, const std::vector<std::int64_t>& weight);
  void repartition_cells(const Measured& m, const std::vector<std::int64_t>& weight);
  void repartition_distributed(const Measured& m, const std::vector<std::int64_t>& weight);
  fracdem::balance::DistributedResult
  partition_geometric(const fracdem::balance::DistributedGraph& g);
  fracdem::balance::DistributedShare
  distributed_share(const Measured& m, const std::vector<std::int64_t>& weight, std::int64_t first);
  void apply_destinations(std::vector<int> dest, const fracdem::balance::PartitionResult& r);
  void note_layout(const std::string& layout);
  void record_repartition(const fracdem::balance::PartitionResult& r, double migrated);
  bool kept_owners(bool failed, const std::string& failure) const;
  double sum_over_ranks(double mine) const;
  // partitioner layers: the axis of the gravity of fix gravity, never cut by a layout (-1: none).
  int gravity_axis() const;
};

} // namespace LAMMPS_NS

#endif
