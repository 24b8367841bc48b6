// Scotch graph repartitioning (SCOTCH_graphRepart) behind the plain-C++ Graph interface.
#include "balance/scotch_partition.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

// scotch.h uses FILE and the fixed-width integer types without including their headers. Its
// directory is added for this file only: some Scotch installs put a METIS-compatibility metis.h
// next to it, which must not shadow the real METIS header of graph_partition.cpp.
#include <stdint.h>
#include <stdio.h>
#include <scotch.h>

namespace fracdem::balance
{

namespace
{

using Num = SCOTCH_Num;

// Scotch sums loads and costs in SCOTCH_Num (32 bit in Debian's default build): keep every sum
// under half its range, headroom for the gains and differences it forms internally. Scaling aims
// at half of that again, so that rounding each weight up (by at most 1/2, or to the minimum of
// 1) cannot push a sum past the limit unless there are that many weights.
const int64_t kSumLimit = static_cast<int64_t>(std::numeric_limits<Num>::max() / 2);
const double kSumTarget = static_cast<double>(kSumLimit / 2);

Num to_num(int64_t v, const char* what)
{
  if (v < std::numeric_limits<Num>::min() || v > std::numeric_limits<Num>::max())
    throw std::overflow_error(std::string("repartition_scotch: ") + what +
                              " does not fit SCOTCH_Num");
  return static_cast<Num>(v);
}

// Every weight divided by factor, rounded, kept >= 1 (Scotch, like METIS, wants positive loads).
std::vector<Num> scale(const std::vector<int64_t>& w, double factor)
{
  std::vector<Num> out(w.size());
  for (size_t k = 0; k < w.size(); ++k)
    out[k] = static_cast<Num>(std::max<int64_t>(
        1, std::llround(static_cast<double>(std::max<int64_t>(w[k], 1)) / factor)));
  return out;
}

double sum_of(const std::vector<int64_t>& w)
{
  double s = 0;
  for (int64_t x : w)
    s += static_cast<double>(std::max<int64_t>(x, 1));
  return s;
}

int64_t sum_of(const std::vector<Num>& w)
{
  return std::accumulate(w.begin(), w.end(), int64_t(0),
                         [](int64_t s, Num x) { return s + static_cast<int64_t>(x); });
}

void check(int rc, const char* routine)
{
  if (rc != 0)
    throw std::runtime_error(std::string("repartition_scotch: ") + routine +
                             " failed with return code " + std::to_string(rc) +
                             " (Scotch printed the reason to stderr)");
}

// Owns the Scotch objects of one call and frees them in reverse order of creation, also when a
// step throws half-way (a context must outlive the container graph bound to it, the graph too).
struct Session {
  SCOTCH_Graph graph, container;
  SCOTCH_Context context;
  SCOTCH_Strat strat;
  bool graph_ok = false, context_ok = false, container_ok = false, strat_ok = false;
  Session() = default;
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  ~Session()
  {
    if (strat_ok) SCOTCH_stratExit(&strat);
    if (container_ok) SCOTCH_graphExit(&container);
    if (context_ok) SCOTCH_contextExit(&context);
    if (graph_ok) SCOTCH_graphExit(&graph);
  }
};

} // namespace

std::vector<int> repartition_scotch(const Graph& g, const std::vector<int>& old_part, int nparts,
                                    double migration_cost, double ubfactor)
{
  const int64_t n = g.num_vertices();
  if (nparts < 1) throw std::invalid_argument("repartition_scotch: nparts must be >= 1");
  if (static_cast<int64_t>(g.vwgt.size()) != n || g.adjwgt.size() != g.adjncy.size() ||
      (n > 0 && (g.xadj.front() != 0 || g.xadj.back() != static_cast<int64_t>(g.adjncy.size()))))
    throw std::invalid_argument("repartition_scotch: inconsistent CSR arrays");
  if (static_cast<int64_t>(old_part.size()) != n)
    throw std::invalid_argument("repartition_scotch: old_part must have one entry per vertex");
  for (int64_t v = 0; v < n; ++v)
    if (old_part[v] < 0 || old_part[v] >= nparts)
      throw std::invalid_argument("repartition_scotch: old_part[" + std::to_string(v) +
                                  "] = " + std::to_string(old_part[v]) +
                                  " is outside [0, nparts); every vertex needs a current " +
                                  "owner here (vertices without one are not supported)");
  if (!std::isfinite(migration_cost) || migration_cost < 0)
    throw std::invalid_argument("repartition_scotch: migration_cost must be finite and >= 0");
  if (!std::isfinite(ubfactor))
    throw std::invalid_argument("repartition_scotch: ubfactor must be finite");
  if (n == 0) return {};
  if (nparts == 1) return std::vector<int>(n, 0);
  // A header of one integer width with a library of another would corrupt every array.
  if (SCOTCH_numSizeof() != static_cast<int>(sizeof(Num)))
    throw std::runtime_error("repartition_scotch: scotch.h and libscotch disagree on the width "
                             "of SCOTCH_Num (" +
                             std::to_string(sizeof(Num)) + " vs " +
                             std::to_string(SCOTCH_numSizeof()) + " bytes)");

  const Num vertnbr = to_num(n, "vertex count");
  const Num edgenbr = to_num(static_cast<int64_t>(g.adjncy.size()), "edge count");
  std::vector<Num> verttab(g.xadj.size()), edgetab(g.adjncy.size());
  for (size_t k = 0; k < verttab.size(); ++k) {
    if (k > 0 && g.xadj[k] < g.xadj[k - 1])
      throw std::invalid_argument("repartition_scotch: xadj must not decrease");
    verttab[k] = static_cast<Num>(g.xadj[k]); // <= edgenbr, which fits
  }
  for (size_t k = 0; k < edgetab.size(); ++k) {
    if (g.adjncy[k] < 0 || g.adjncy[k] >= n)
      throw std::invalid_argument("repartition_scotch: neighbour " + std::to_string(g.adjncy[k]) +
                                  " out of range");
    edgetab[k] = static_cast<Num>(g.adjncy[k]);
  }

  // Vertex loads (balance only): one common factor brings their sum within range.
  const double vsum = sum_of(g.vwgt), limit = static_cast<double>(kSumLimit);
  std::vector<Num> velotab = scale(g.vwgt, std::max(1.0, vsum / kSumTarget));
  if (sum_of(velotab) > kSumLimit) // only when the clamp to 1 dominates
    throw std::overflow_error("repartition_scotch: vertex weights do not fit SCOTCH_Num");

  // Scotch minimises crlo * cut + cmlo * migration, crlo/cmlo the reduced fraction of
  // round(100 * emraval) / 100, in SCOTCH_Num. Edge loads and vertex migration costs share one
  // factor, so their ratio (what migration_cost means) survives the scaling.
  const double emraval_100 = std::floor(migration_cost * 100.0 + 0.5);
  if (emraval_100 > static_cast<double>(std::numeric_limits<Num>::max()))
    throw std::overflow_error("repartition_scotch: migration_cost too large for SCOTCH_Num");
  const int64_t numer = static_cast<int64_t>(emraval_100), gcd = std::gcd(numer, int64_t(100));
  const double crlo = static_cast<double>(100 / gcd), cmlo = static_cast<double>(numer / gcd);
  const double cost = crlo * sum_of(g.adjwgt) + cmlo * vsum;
  const double cost_factor = std::max(1.0, cost / kSumTarget);
  std::vector<Num> edlotab = scale(g.adjwgt, cost_factor), vmlotab = scale(g.vwgt, cost_factor);
  if (crlo * static_cast<double>(sum_of(edlotab)) + cmlo * static_cast<double>(sum_of(vmlotab)) >
      limit)
    throw std::overflow_error("repartition_scotch: edge weights and migration costs (times "
                              "migration_cost) do not fit SCOTCH_Num");

  std::vector<Num> parotab(old_part.begin(), old_part.end()), parttab(n, 0);
  // Scotch may reject a null array pointer on an edgeless graph: give it a valid one.
  Num dummy = 0;
  Num* edges = edgetab.empty() ? &dummy : edgetab.data();
  Num* edlos = edlotab.empty() ? &dummy : edlotab.data();

  Session s;
  check(SCOTCH_graphInit(&s.graph), "SCOTCH_graphInit");
  s.graph_ok = true;
  check(SCOTCH_graphBuild(&s.graph, 0, vertnbr, verttab.data(), nullptr, velotab.data(), nullptr,
                          edgenbr, edges, edlos),
        "SCOTCH_graphBuild");
  // Scotch trusts its input; an asymmetric graph would corrupt its refinement silently.
  check(SCOTCH_graphCheck(&s.graph), "SCOTCH_graphCheck");

  // A private context: deterministic algorithms and its own generator reset to a fixed seed on
  // every call (the global one is shared with other callers and not thread-safe), and a single
  // thread, since fracdem already runs one MPI rank per core and Scotch would otherwise start a
  // thread per core on every rank.
  check(SCOTCH_contextInit(&s.context), "SCOTCH_contextInit");
  s.context_ok = true;
  check(SCOTCH_contextOptionSetNum(&s.context, SCOTCH_OPTIONNUMDETERMINISTIC, 1),
        "SCOTCH_contextOptionSetNum(DETERMINISTIC)");
  check(SCOTCH_contextOptionSetNum(&s.context, SCOTCH_OPTIONNUMRANDOMFIXEDSEED, 1),
        "SCOTCH_contextOptionSetNum(RANDOMFIXEDSEED)");
  check(SCOTCH_contextThreadSpawn(&s.context, 1, nullptr), "SCOTCH_contextThreadSpawn");
  check(SCOTCH_contextRandomClone(&s.context), "SCOTCH_contextRandomClone");
  SCOTCH_contextRandomSeed(&s.context, 7);
  SCOTCH_contextRandomReset(&s.context);
  check(SCOTCH_graphInit(&s.container), "SCOTCH_graphInit(container)");
  s.container_ok = true;
  check(SCOTCH_contextBindGraph(&s.context, &s.graph, &s.container), "SCOTCH_contextBindGraph");

  check(SCOTCH_stratInit(&s.strat), "SCOTCH_stratInit");
  s.strat_ok = true;
  // BALANCE appends an exact-balancing pass: the point of repartitioning is the load limit.
  // Scotch cannot work with a zero tolerance: keep at least 0.1 % as partition_kway does.
  check(SCOTCH_stratGraphMapBuild(&s.strat, SCOTCH_STRATBALANCE, nparts,
                                  std::max(0.001, ubfactor - 1.0)),
        "SCOTCH_stratGraphMapBuild");

  check(SCOTCH_graphRepart(&s.container, nparts, parotab.data(), migration_cost, vmlotab.data(),
                           &s.strat, parttab.data()),
        "SCOTCH_graphRepart");
  std::vector<int> out(n);
  for (int64_t v = 0; v < n; ++v) {
    if (parttab[v] < 0 || parttab[v] >= nparts)
      throw std::runtime_error("repartition_scotch: SCOTCH_graphRepart returned part " +
                               std::to_string(parttab[v]) + " outside [0, nparts)");
    out[v] = static_cast<int>(parttab[v]);
  }
  return out;
}

} // namespace fracdem::balance
