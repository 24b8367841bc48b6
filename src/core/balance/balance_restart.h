// What fix balance/graph keeps in a restart file besides the particles: its outputs, the check
// schedule, the cost model's state and the cell owners, packed into one array of numbers.
#ifndef FRACDEM_BALANCE_BALANCE_RESTART_H
#define FRACDEM_BALANCE_BALANCE_RESTART_H

#include <cstddef>
#include <vector>

#include "balance/balance_report.h"
#include "balance/cell_grid.h"

namespace fracdem::balance
{

struct BalanceRestart {
  BalanceOutputs outputs;
  int nranks = 0;            // ranks of the run that wrote it (the owners are rank numbers)
  long long last_check = -1; // step of the last check (the interval the next one measures)
  CellGrid grid;             // cell ownership: the grid and its owners (empty: none)
  std::vector<int> cell_owners;
  std::vector<double> pricing; // CostPricing::state()
  bool complete = false;       // false: a file of the older format (outputs only)
};

// The numbers a restart file holds: the first is minus their count, which tells them from the
// older format (BalanceOutputs::save, whose first number is an imbalance >= 0).
std::vector<double> pack_balance_restart(const BalanceRestart& r);

// Reads what pack_balance_restart wrote, or the older format's BalanceOutputs::kRestartSize
// numbers (complete false). Throws std::invalid_argument on counts that do not add up.
BalanceRestart unpack_balance_restart(const double* state);

} // namespace fracdem::balance

#endif
