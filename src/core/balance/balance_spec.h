// BalanceSpec: every setting of fix balance/graph, its one keyword table and parser.
#ifndef FRACDEM_BALANCE_BALANCE_SPEC_H
#define FRACDEM_BALANCE_BALANCE_SPEC_H

#include <stdexcept>
#include <string>
#include <vector>

#include "balance/cost_model.h"
#include "balance/cost_pricing.h"
#include "balance/partition_strategy.h"

namespace fracdem::balance
{

// An input error of fix balance/graph: the text names the keyword and what was expected; a host
// writes it after "fix balance/graph: ".
class BalanceSpecError : public std::invalid_argument
{
public:
  using std::invalid_argument::invalid_argument;
};

// `fix ID all balance/graph Nevery thresh keyword value ...` (docs/fix_balance_graph.md).
struct BalanceSpec {
  int every = 0;          // Nevery
  double threshold = 1.0; // thresh: repartition when max/avg work exceeds it
  GraphModel graph_model = GraphModel::APosteriori; // model
  CostModel cost_model = CostModel::Timed;          // cost
  Partitioner partitioner = Partitioner::Metis;     // partitioner
  Strategy strategy = Strategy::Auto;               // repartition
  bool have_strategy = false;                       // repartition given
  double cell_factor = 2.0; // cells: cell edge in ghost cutoffs; 0 = one vertex per particle
  bool have_cells = false;  // cells given (a distributed partitioner defaults to 0)
  // counts: take contacts and bridges from pair_style fracdem/gran, which counts them where it
  // computes them (pair, the default), or recount contacts over the neighbour list (recount, as
  // for other pair styles, which gives no bridges)
  bool pair_counts = true;
  std::vector<std::string> insert_regions; // insert_region (repeatable)
  std::string out_file;                    // out; empty: no report
};

// Reads the words after the style name: "Nevery thresh keyword value ...". Each keyword but
// insert_region may appear once. Throws BalanceSpecError.
BalanceSpec parse_balance_spec(const std::vector<std::string>& words);

} // namespace fracdem::balance

#endif
