// fix balance/graph's settings: the one keyword table, its handlers and the parser.
#include "balance/balance_spec.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>

#include "io/input_help.h"

namespace fracdem::balance
{

namespace
{

[[noreturn]] void fail(const std::string& what)
{
  throw BalanceSpecError(what);
}

template <typename T> struct Choice {
  const char* name;
  T value;
};
// Sub-model tables: one place maps words to models (partitioners: partition_strategy.cpp).
const Choice<GraphModel> kGraphModels[] = {{"apriori", GraphModel::APriori},
                                           {"aposteriori", GraphModel::APosteriori}};
const Choice<CostModel> kCostModels[] = {{"counts", CostModel::Counts},
                                         {"calibrated", CostModel::Calibrated},
                                         {"timed", CostModel::Timed},
                                         {"fitted", CostModel::Fitted}};
const Choice<Strategy> kStrategies[] = {
    {"auto", Strategy::Auto}, {"refine", Strategy::Refine}, {"scratch", Strategy::Scratch}};

// The value of `key` looked up in `table`; else "keyword 'KEY': expected a, b or c, got 'V'".
template <typename T, std::size_t N>
T choose(const Choice<T> (&table)[N], const std::string& key, const std::string& value)
{
  std::string expected;
  for (std::size_t k = 0; k < N; ++k) {
    if (value == table[k].name) return table[k].value;
    expected += std::string(k == 0 ? "" : k + 1 == N ? " or " : ", ") + table[k].name;
  }
  fail("keyword '" + key + "': expected " + expected + ", got '" + value + "'");
}

// ---- the handlers of the keyword table, in the documentation's order ----
using Handler = void (*)(const std::string& value, BalanceSpec& s);

void parse_model(const std::string& v, BalanceSpec& s)
{
  s.graph_model = choose(kGraphModels, "model", v);
}

void parse_cost(const std::string& v, BalanceSpec& s)
{
  s.cost_model = choose(kCostModels, "cost", v);
}

void parse_partitioner(const std::string& v, BalanceSpec& s)
{
  try {
    s.partitioner = find_partitioner(v).id;
  } catch (const std::invalid_argument& e) {
    fail(e.what());
  }
}

void parse_repartition(const std::string& v, BalanceSpec& s)
{
  s.strategy = choose(kStrategies, "repartition", v);
  s.have_strategy = true;
}

void parse_cells(const std::string& v, BalanceSpec& s)
{
  char* end = nullptr;
  s.cell_factor = std::strtod(v.c_str(), &end);
  s.have_cells = true;
  if (*end || !(s.cell_factor == 0.0 || s.cell_factor >= 1.0))
    fail("keyword 'cells': expected 0 (one vertex per particle) or a cell edge >= 1 in ghost "
         "cutoffs, got '" +
         v + "'");
}

void parse_counts(const std::string& v, BalanceSpec& s)
{
  if (v != "pair" && v != "recount")
    fail("keyword 'counts': expected pair or recount, got '" + v + "'");
  s.pair_counts = v == "pair";
}

void parse_insert_region(const std::string& v, BalanceSpec& s)
{
  s.insert_regions.push_back(v);
}

void parse_out(const std::string& v, BalanceSpec& s)
{
  s.out_file = v;
}

struct Keyword {
  const char* keyword;
  Handler handle;
  bool repeatable;
};

// The one keyword table of fix balance/graph.
const Keyword kKeywords[] = {
    {"model", parse_model, false},
    {"cost", parse_cost, false},
    {"partitioner", parse_partitioner, false},
    {"repartition", parse_repartition, false},
    {"cells", parse_cells, false},
    {"counts", parse_counts, false},
    {"insert_region", parse_insert_region, true},
    {"out", parse_out, false},
};

const Keyword& find_keyword(const std::string& key)
{
  std::string names;
  std::vector<std::string> known;
  const std::size_t n = sizeof kKeywords / sizeof kKeywords[0];
  for (std::size_t k = 0; k < n; ++k) {
    if (key == kKeywords[k].keyword) return kKeywords[k];
    names += std::string(k == 0 ? "" : k + 1 == n ? " or " : ", ") + kKeywords[k].keyword;
    known.push_back(kKeywords[k].keyword);
  }
  fail("unknown keyword '" + key + "' (expected " + names + ")" + did_you_mean(key, known));
}

int parse_every(const std::string& word)
{
  char* end = nullptr;
  errno = 0;
  const long long every = std::strtoll(word.c_str(), &end, 10);
  const int n = every > 0 && every <= INT_MAX ? static_cast<int>(every) : 0; // no silent wrap
  if (end == word.c_str() || *end || errno == ERANGE || n <= 0)
    fail("Nevery must be a positive integer, got '" + word + "'");
  return n;
}

double parse_threshold(const std::string& word)
{
  char* end = nullptr;
  const double t = std::strtod(word.c_str(), &end);
  if (end == word.c_str() || *end || !std::isfinite(t) || !(t >= 1.0))
    fail("thresh must be a number >= 1.0 (max/avg work), got '" + word + "'");
  return t;
}

// A distributed partitioner keeps the graph where it is built: one vertex per particle (every
// rank would need the owner of every cell), each repartition one call from scratch.
void check_distributed(BalanceSpec& s, const PartitionerInfo& p)
{
  if (s.have_strategy)
    fail(std::string("keyword 'repartition' chooses how METIS is used; 'partitioner ") + p.name +
         "' partitions on all ranks in one call (drop 'repartition')");
  if (s.have_cells && s.cell_factor > 0.0)
    fail(std::string("keyword 'partitioner ") + p.name +
         "' partitions one vertex per particle where the particles are (the graph stays "
         "distributed; cells would need every cell's owner on every rank): use 'cells 0' or "
         "leave 'cells' out");
  s.cell_factor = 0.0;
}

// Settings that exclude each other.
void check_combinations(BalanceSpec& s)
{
  const PartitionerInfo& p = partitioner_info(s.partitioner);
  if (p.distributed) return check_distributed(s, p);
  if (p.repartitions && s.have_strategy)
    fail("keyword 'repartition' chooses how METIS is used; with 'partitioner scotch' each "
         "repartition is one SCOTCH_graphRepart call (drop 'repartition')");
  if (p.geometric && s.cell_factor == 0.0)
    fail(std::string("keyword 'partitioner ") + p.name +
         "' cuts the cell grid by coordinates and needs cells (a cell edge >= 1); it does not "
         "work with 'cells 0'");
}

} // namespace

BalanceSpec parse_balance_spec(const std::vector<std::string>& words)
{
  if (words.size() < 2)
    fail("expected 'fix ID all balance/graph Nevery thresh [keyword value ...]'");
  BalanceSpec s;
  s.every = parse_every(words[0]);
  s.threshold = parse_threshold(words[1]);
  std::vector<std::string> seen;
  for (std::size_t i = 2; i < words.size(); i += 2) {
    const std::string& key = words[i];
    if (i + 1 >= words.size()) fail("keyword '" + key + "' needs a value");
    const Keyword& k = find_keyword(key);
    if (!k.repeatable) {
      if (std::find(seen.begin(), seen.end(), key) != seen.end())
        fail("keyword '" + key + "' given twice");
      seen.push_back(key);
    }
    k.handle(words[i + 1], s);
  }
  check_combinations(s);
  return s;
}

} // namespace fracdem::balance
