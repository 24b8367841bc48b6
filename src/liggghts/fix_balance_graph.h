// fix balance/graph: imbalance-triggered graph repartitioning driven by recorded per-particle
// costs.
#ifndef FRACDEM_FIX_BALANCE_GRAPH_H
#define FRACDEM_FIX_BALANCE_GRAPH_H

#include <cstdio>
#include <cstdint>
#include <string>
#include <vector>

#include "balance/cell_grid.h"
#include "balance/cost_calibration.h"
#include "balance/cost_fit.h"
#include "balance/graph_partition.h"
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
  void post_force(int) override;
  double compute_scalar() override;
  double compute_vector(int) override;
  void write_restart(FILE*) override;
  void restart(char*) override;

  enum class GraphModel { APriori, APosteriori };
  enum class CostModel { Counts, Calibrated, Timed, Fitted };
  enum class Strategy { Auto, Refine, Scratch };
  enum class Partitioner { Metis, Scotch, Rcb, Layers };

private:
  // What one check measured on this rank, per local particle and in total.
  struct LocalCosts {
    std::vector<double> cost;            // work model per particle
    std::vector<std::int64_t> potential; // potential targets per particle
    // Further per-particle counts of the work model's terms (pair checks are `potential`).
    std::vector<int> contacts, wall_contacts, facet_checks, facet_contacts;
    fracdem::balance::TermCounts term_sums{}; // this rank's total of each term
    std::vector<std::int64_t> edges;          // (tag_i, tag_j, weight) or (cell_i, cell_j, weight)
    std::vector<std::int64_t> cell;           // cell of each particle (cell graph only)
    double total = 0;
    double sum_all = 0; // total over all ranks (set by the check)
  };

  int check_every_;
  double threshold_;
  GraphModel graph_model_ = GraphModel::APosteriori;
  CostModel cost_model_ = CostModel::Timed;
  Strategy strategy_ = Strategy::Auto;
  Partitioner partitioner_ = Partitioner::Metis;
  std::vector<std::string> insert_regions_; // limit the insertion ghost cover to these
  double cell_factor_ = 2.0; // cell edge in ghost cutoffs; 0 = one vertex per particle
  fracdem::balance::CellGrid grid_;
  std::string layout_kind_; // partitioner layers: the layout last reported (rank 0)
  fracdem::balance::InteractionCosts costs_;
  fracdem::balance::InteractionCosts calibrated_; // the start-up costs (prior of cost fitted)
  // cost fitted: the samples (one per rank and check) of the last few checks, oldest first.
  std::vector<fracdem::balance::CostSample> fit_samples_;
  FILE* out_ = nullptr;
  class CommGraph* comm_graph_ = nullptr;
  std::vector<class FixWallGran*> primitive_walls_;
  std::vector<class FixFemBody*> fem_bodies_;
  // Thread CPU time of this rank's particle work (neighbour build, pair, and the post-force fixes
  // defined before this one: walls, FE contact) since the last check; the measured work.
  double cpu_work_ = 0, cpu_start_ = 0;
  // Integration: CPU clock at this fix's end_of_step (until the next initial_integrate) and at the
  // end of its post_force (until its final_integrate); negative when that bracket is not open.
  double cpu_step_end_ = -1, cpu_after_force_ = -1;
  bool cpu_from_neighbor_ = false;
  bool start_check_ = false;    // the next check is the one at the first step of the first run
  bigint last_check_step_ = -1; // step of the last check (cpu_work_ counts from there)

  // Outputs (see docs/fix_balance_graph.md).
  double imbalance_ = 1.0, imbalance_before_ = 1.0, imbalance_predicted_ = 1.0;
  double repartitions_ = 0, migrated_last_ = 0, seconds_total_ = 0;
  double ghost_ratio_ = 1.0, ghosts_total_ = 0, edge_cut_ = 0, checks_ = 0;
  double measured_imbalance_ = 1.0;
  std::vector<double> owner_rank_; // per-atom output: the rank that owns the particle

  bigint next_regular_check() const;
  // Counts every term of the work model per local particle; price() turns counts into costs_.
  void measure(LocalCosts& lc);
  void price(LocalCosts& lc) const;
  // cost timed: the measured CPU time replaces the modelled rank total.
  void scale_to_measured(LocalCosts& lc) const;
  // cost fitted: refits costs_ to the measured time of every rank over the last checks, and
  // prices the particles with them.
  void fit_to_measured(LocalCosts& lc, bigint previous_check);
  void repartition(const LocalCosts& lc);
  void repartition_cells(const LocalCosts& lc);
  void record_repartition(const double stats[2], double migrated);
  std::vector<std::int64_t> vertex_weights(const LocalCosts& lc) const;
  // Vertex and edge arrays of all ranks on rank 0, with each rank's vertex block.
  struct GatheredGraph {
    std::vector<std::int64_t> verts, edges; // on rank 0: exactly vtotal and etotal entries
    std::vector<int> vcount, vdisp;
    int vtotal = 0, etotal = 0;
  };
  GatheredGraph gather_graph(const std::vector<std::int64_t>& verts,
                             const std::vector<std::int64_t>& edges) const;
  // Partition of a gathered graph on rank 0: refine from old_owner, or from scratch by METIS,
  // (partitioner rcb) by RCB of the vertex coordinates xyz (cell centres; null with cells 0) or
  // (partitioner layers) by the layered layout of the vertices' cells of grid_, described in
  // *layout.
  std::vector<int> partition_on_root(const fracdem::balance::Graph& g,
                                     const std::vector<int>& old_owner, double stats[2],
                                     const std::vector<double>* xyz = nullptr,
                                     const std::vector<std::int64_t>* cells = nullptr,
                                     std::string* layout = nullptr) const;
  void write_row(bool repartitioned, double partition_seconds);
  // partitioner layers: the axis of the gravity of fix gravity, never cut by a layout (-1: none).
  int gravity_axis() const;
};

} // namespace LAMMPS_NS

#endif
