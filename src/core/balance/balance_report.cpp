// fix balance/graph's CSV report, its outputs between checks and its log lines.
#include "balance/balance_report.h"

#include <cstdio>

namespace fracdem::balance
{

std::string report_header(int nranks)
{
  std::string h = "step,imbalance,repartitioned,predicted_imbalance,migrated,partition_seconds,"
                  "migration_seconds_total,ghost_max_over_avg,ghosts_total,edge_cut,natoms,"
                  "work_max,work_avg,measured_imbalance,cpu_work_max,cpu_work_avg";
  // Per-rank CPU work of each interval, for per-rank work plots.
  for (int p = 0; p < nranks; ++p)
    h += ",cpu_rank" + std::to_string(p);
  return h + "\n";
}

std::string report_row(const CheckRow& r)
{
  char row[512];
  snprintf(row, sizeof row,
           "%lld,%.6g,%d,%.6g,%.0f,%.6g,%.6g,%.6g,%.0f,%.0f,%lld,%.6g,%.6g,%.6g,%.6g,%.6g", r.step,
           r.work.imbalance, r.repartitioned ? 1 : 0, r.predicted_imbalance, r.migrated,
           r.partition_seconds, r.migration_seconds_total, r.ghosts.imbalance, r.ghosts.sum,
           r.edge_cut, r.natoms, r.work.max, r.work.avg, r.cpu.imbalance, r.cpu.max, r.cpu.avg);
  std::string line = row;
  for (double w : r.cpu_per_rank) {
    snprintf(row, sizeof row, ",%.6g", w);
    line += row;
  }
  return line + "\n";
}

double BalanceOutputs::vector(int n, double migration_seconds) const
{
  const double entries[kVectorSize] = {imbalance_before,    repartitions,
                                       migrated_last,       seconds_total + migration_seconds,
                                       ghost_ratio,         edge_cut,
                                       checks,              predicted_imbalance,
                                       ghosts_total,        measured_imbalance};
  return n >= 0 && n < kVectorSize ? entries[n] : 0.0;
}

void BalanceOutputs::record_check(const RankSpread& work, const RankSpread& cpu,
                                  const RankSpread& ghosts)
{
  imbalance = work.imbalance;
  measured_imbalance = cpu.imbalance;
  ghosts_total = ghosts.sum;
  ghost_ratio = ghosts.imbalance;
  checks += 1;
}

void BalanceOutputs::record_repartition(double predicted, double cut, double migrated)
{
  imbalance_before = imbalance;
  predicted_imbalance = predicted;
  edge_cut = cut;
  migrated_last = migrated;
  repartitions += 1;
}

void BalanceOutputs::save(double state[kRestartSize]) const
{
  const double s[kRestartSize] = {imbalance_before, repartitions, migrated_last,
                                  seconds_total,    edge_cut,     checks};
  for (int k = 0; k < kRestartSize; ++k)
    state[k] = s[k];
}

void BalanceOutputs::load(const double state[kRestartSize])
{
  imbalance_before = state[0], repartitions = state[1], migrated_last = state[2];
  seconds_total = state[3], edge_cut = state[4], checks = state[5];
}

std::string calibrated_costs_line(const InteractionCosts& c)
{
  char line[400];
  snprintf(line, sizeof line,
           "fix balance/graph: calibrated costs relative to a pair check: particle %.2f, "
           "sphere contact %.2f, wall check %.2f, wall contact %.2f, facet check %.2f, "
           "facet contact %.2f, bridge %.2f\n",
           c.particle, c.sphere_contact, c.wall_check, c.wall_contact, c.facet_check,
           c.facet_contact, c.bridge);
  return line;
}

std::string fitted_costs_line(const InteractionCosts& c)
{
  const double unit = c.pair_check;
  char line[512];
  snprintf(line, sizeof line,
           "fix balance/graph: fitted costs relative to a pair check (%.3g ns per step): particle "
           "%.2f, sphere contact %.2f, wall check %.2f, wall contact %.2f, facet check %.2f, "
           "facet contact %.2f, bridge %.2f\n",
           1e9 * unit, c.particle / unit, c.sphere_contact / unit, c.wall_check / unit,
           c.wall_contact / unit, c.facet_check / unit, c.facet_contact / unit, c.bridge / unit);
  return line;
}

std::string repartition_line(long long step, double imbalance, double threshold, GraphModel model,
                             bool cells, double predicted, double migrated, double cut)
{
  char line[512];
  snprintf(line, sizeof line,
           "fix balance/graph: step %lld imbalance %.3f > %.3f: repartitioned (%s%s graph), "
           "predicted %.3f, %.0f particles migrate, edge cut %.0f\n",
           step, imbalance, threshold, model == GraphModel::APriori ? "a priori" : "a posteriori",
           cells ? " cell" : " particle", predicted, migrated, cut);
  return line;
}

} // namespace fracdem::balance
