// Packing of fix balance/graph's restart state: outputs, schedule, costs and cell owners.
#include "balance/balance_restart.h"

#include <stdexcept>
#include <string>

namespace fracdem::balance
{

namespace
{

constexpr int kOutputs = 11;

void put_outputs(const BalanceOutputs& o, std::vector<double>& s)
{
  s.insert(s.end(), {o.imbalance, o.imbalance_before, o.predicted_imbalance, o.repartitions,
                     o.migrated_last, o.seconds_total, o.ghost_ratio, o.ghosts_total, o.edge_cut,
                     o.checks, o.measured_imbalance});
}

BalanceOutputs get_outputs(const double* s)
{
  BalanceOutputs o;
  o.imbalance = s[0], o.imbalance_before = s[1], o.predicted_imbalance = s[2];
  o.repartitions = s[3], o.migrated_last = s[4], o.seconds_total = s[5];
  o.ghost_ratio = s[6], o.ghosts_total = s[7], o.edge_cut = s[8], o.checks = s[9];
  o.measured_imbalance = s[10];
  return o;
}

void put_grid(const CellGrid& g, std::vector<double>& s)
{
  for (int d = 0; d < 3; ++d)
    s.insert(s.end(), {g.lo[d], g.size[d], static_cast<double>(g.n[d]), g.periodic[d] ? 1.0 : 0.0});
}

CellGrid get_grid(const double* s)
{
  CellGrid g;
  for (int d = 0; d < 3; ++d) {
    g.lo[d] = s[4 * d], g.size[d] = s[4 * d + 1];
    g.n[d] = static_cast<int64_t>(s[4 * d + 2]), g.periodic[d] = s[4 * d + 3] != 0.0;
  }
  return g;
}

} // namespace

std::vector<double> pack_balance_restart(const BalanceRestart& r)
{
  std::vector<double> s{0.0}; // minus the count, below
  put_outputs(r.outputs, s);
  s.insert(s.end(), {static_cast<double>(r.nranks), static_cast<double>(r.last_check)});
  put_grid(r.grid, s);
  s.push_back(static_cast<double>(r.cell_owners.size()));
  s.insert(s.end(), r.cell_owners.begin(), r.cell_owners.end());
  s.push_back(static_cast<double>(r.pricing.size()));
  s.insert(s.end(), r.pricing.begin(), r.pricing.end());
  s[0] = -static_cast<double>(s.size());
  return s;
}

BalanceRestart unpack_balance_restart(const double* state)
{
  BalanceRestart r;
  if (state[0] >= 0) { // the older format
    r.outputs.load(state);
    return r;
  }
  const std::size_t total = static_cast<std::size_t>(-state[0]);
  std::size_t k = 1;
  const auto need = [&](std::size_t n) {
    if (k + n > total)
      throw std::invalid_argument("fix balance/graph restart state: " + std::to_string(total) +
                                  " numbers, but its counts need more than " +
                                  std::to_string(k + n));
  };
  need(kOutputs + 2 + 12 + 1);
  r.outputs = get_outputs(state + k), k += kOutputs;
  r.nranks = static_cast<int>(state[k]), r.last_check = static_cast<long long>(state[k + 1]);
  r.grid = get_grid(state + k + 2), k += 2 + 12;
  const std::size_t ncells = static_cast<std::size_t>(state[k++]);
  need(ncells + 1);
  r.cell_owners.assign(state + k, state + k + ncells), k += ncells;
  const std::size_t npricing = static_cast<std::size_t>(state[k++]);
  need(npricing);
  r.pricing.assign(state + k, state + k + npricing), k += npricing;
  if (k != total)
    throw std::invalid_argument("fix balance/graph restart state: " + std::to_string(total) +
                                " numbers, " + std::to_string(k) + " read");
  r.complete = true;
  return r;
}

} // namespace fracdem::balance
