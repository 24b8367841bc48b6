// What fix balance/graph reports: the CSV report (its columns and one row per check), the
// outputs it keeps between checks (scalar, global vector, restart state) and its log lines.
#ifndef FRACDEM_BALANCE_BALANCE_REPORT_H
#define FRACDEM_BALANCE_BALANCE_REPORT_H

#include <string>
#include <vector>

#include "balance/balance_check.h"
#include "balance/cost_model.h"

namespace fracdem::balance
{

// One check as the report shows it.
struct CheckRow {
  long long step = 0;
  bool repartitioned = false;
  double predicted_imbalance = 1; // of the last partition
  double migrated = 0;            // particles migrated by this check's repartition
  double partition_seconds = 0, migration_seconds_total = 0;
  double edge_cut = 0; // of the last partition
  long long natoms = 0;
  RankSpread work, cpu, ghosts; // the cost model's work, measured CPU seconds, ghost counts
  std::vector<double> cpu_per_rank;
};

// The CSV header: step, imbalance, repartitioned, predicted_imbalance, migrated,
// partition_seconds, migration_seconds_total, ghost_max_over_avg, ghosts_total, edge_cut, natoms,
// work_max, work_avg, measured_imbalance, cpu_work_max, cpu_work_avg, then cpu_rank0 .. cpu_rankN-1;
// with its newline.
std::string report_header(int nranks);
// One row (imbalance: work's max/avg; measured_imbalance: cpu's), with its newline.
std::string report_row(const CheckRow& row);

// What the fix keeps between checks: its scalar (imbalance), its global vector and the part of
// it that restart files keep.
struct BalanceOutputs {
  double imbalance = 1.0, imbalance_before = 1.0, predicted_imbalance = 1.0;
  double repartitions = 0, migrated_last = 0, seconds_total = 0;
  double ghost_ratio = 1.0, ghosts_total = 0, edge_cut = 0, checks = 0;
  double measured_imbalance = 1.0;

  static constexpr int kVectorSize = 10;
  static constexpr int kRestartSize = 6;
  // Entry n (0-based) of the global vector; migration_seconds: the communicator's total.
  double vector(int n, double migration_seconds) const;
  // A check's spreads: imbalance, measured imbalance, ghosts.
  void record_check(const RankSpread& work, const RankSpread& cpu, const RankSpread& ghosts);
  void record_repartition(double predicted, double cut, double migrated);
  void save(double state[kRestartSize]) const;
  void load(const double state[kRestartSize]);
};

// Log lines, each with its newline: the costs relative to a pair check ("calibrated"), the
// fitted ones with the price of a pair check per step, and one repartition.
std::string calibrated_costs_line(const InteractionCosts& c);
std::string fitted_costs_line(const InteractionCosts& c);
std::string repartition_line(long long step, double imbalance, double threshold, GraphModel model,
                             bool cells, double predicted, double migrated, double cut);

} // namespace fracdem::balance

#endif
