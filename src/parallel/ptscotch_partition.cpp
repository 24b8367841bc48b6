// PT-Scotch (SCOTCH_dgraphPart) behind the distributed graph: build, partition, relabel, and the
// balance and edge cut of the result, with failures agreed by all ranks.
#include "ptscotch_partition.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#ifdef FRACDEM_HAVE_PTSCOTCH
// ptscotch.h uses FILE, the fixed-width integer types and MPI without including their headers.
#include <stdint.h>
#include <stdio.h>
#include <ptscotch.h>
#endif

namespace fracdem::balance
{

namespace
{

std::string graph_size(int nranks, const GraphTotals& t)
{
  return "on " + std::to_string(nranks) + " ranks, graph of " +
         std::to_string(std::llround(t.vertices)) + " vertices and " +
         std::to_string(std::llround(t.edges)) + " edges";
}

#ifdef FRACDEM_HAVE_PTSCOTCH

using Num = SCOTCH_Num;
// Scotch sums loads and edge weights in SCOTCH_Num: keep every sum at a quarter of its range
// (headroom for the gains it forms and for rounding each scaled weight up to 1).
const double kSumTarget = static_cast<double>(std::numeric_limits<Num>::max() / 4);

// Every rank's return code of one collective step; any failure fails the step on all ranks.
void agree(int rc, const char* routine, MPI_Comm comm)
{
  int mine = rc != 0, any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, comm);
  if (!any) return;
  throw std::runtime_error(
      std::string(routine) + " failed " +
      (rc ? "with return code " + std::to_string(rc) : std::string("on another rank")) +
      " (PT-Scotch printed the reason to stderr)");
}

// The local rows in SCOTCH_Num, weights divided by a common factor where their global sums would
// pass kSumTarget (each kept >= 1).
struct ScotchRows {
  std::vector<Num> vert, velo, edge, edlo;
};

ScotchRows scotch_rows(const DistributedGraph& g, const GraphTotals& t)
{
  if (g.global_vertices() >= std::numeric_limits<Num>::max() ||
      2 * t.edges >= static_cast<double>(std::numeric_limits<Num>::max()))
    throw std::overflow_error("the graph does not fit SCOTCH_Num (" +
                              std::to_string(sizeof(Num) * 8) + " bit)");
  const double fv = std::max(1.0, t.vertex_weight / kSumTarget);
  const double fe = std::max(1.0, 2 * t.edge_weight / kSumTarget);
  const Graph& l = g.local;
  ScotchRows r;
  r.vert.assign(l.xadj.begin(), l.xadj.end());
  for (std::int64_t w : l.vwgt)
    r.velo.push_back(static_cast<Num>(std::max<long long>(1, std::llround(w / fv))));
  r.edge.assign(l.adjncy.begin(), l.adjncy.end());
  for (std::int64_t w : l.adjwgt)
    r.edlo.push_back(static_cast<Num>(std::max<long long>(1, std::llround(w / fe))));
  // Valid pointers for ranks without vertices or edges.
  r.velo.resize(std::max<std::size_t>(r.velo.size(), 1), 1);
  r.edge.resize(std::max<std::size_t>(r.edge.size(), 1), 0);
  r.edlo.resize(std::max<std::size_t>(r.edlo.size(), 1), 1);
  return r;
}

// Owns the PT-Scotch objects of one call; frees them in reverse order of creation, also when a
// step throws half-way (the context outlives the container graph bound to it, the graph too).
struct Session {
  SCOTCH_Dgraph graph, container;
  SCOTCH_Context context;
  SCOTCH_Strat strat;
  bool graph_ok = false, context_ok = false, container_ok = false, strat_ok = false;
  Session() = default;
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  ~Session()
  {
    if (strat_ok) SCOTCH_stratExit(&strat);
    if (container_ok) SCOTCH_dgraphExit(&container);
    if (context_ok) SCOTCH_contextExit(&context);
    if (graph_ok) SCOTCH_dgraphExit(&graph);
  }
};

// A private context: one thread per rank (PT-Scotch would start a thread per core on every rank,
// calling MPI from them, which a run initialised without MPI_THREAD_MULTIPLE does not allow: it
// crashed or hung), deterministic algorithms and its own generator at a fixed seed.
void bind_context(Session& s, MPI_Comm comm)
{
  agree(SCOTCH_contextInit(&s.context), "SCOTCH_contextInit", comm);
  s.context_ok = true;
  agree(SCOTCH_contextOptionSetNum(&s.context, SCOTCH_OPTIONNUMDETERMINISTIC, 1) |
            SCOTCH_contextOptionSetNum(&s.context, SCOTCH_OPTIONNUMRANDOMFIXEDSEED, 1),
        "SCOTCH_contextOptionSetNum", comm);
  agree(SCOTCH_contextThreadSpawn(&s.context, 1, nullptr), "SCOTCH_contextThreadSpawn", comm);
  agree(SCOTCH_contextRandomClone(&s.context), "SCOTCH_contextRandomClone", comm);
  SCOTCH_contextRandomSeed(&s.context, 7);
  SCOTCH_contextRandomReset(&s.context);
  agree(SCOTCH_dgraphInit(&s.container, comm), "SCOTCH_dgraphInit(container)", comm);
  s.container_ok = true;
  agree(SCOTCH_contextBindDgraph(&s.context, &s.graph, &s.container), "SCOTCH_contextBindDgraph",
        comm);
}

void build(Session& s, const DistributedGraph& g, ScotchRows& r, MPI_Comm comm)
{
  agree(SCOTCH_dgraphInit(&s.graph, comm), "SCOTCH_dgraphInit", comm);
  s.graph_ok = true;
  const Num n = static_cast<Num>(g.local.vwgt.size());
  const Num arcs = static_cast<Num>(g.local.adjncy.size());
  agree(SCOTCH_dgraphBuild(&s.graph, 0, n, n, r.vert.data(), nullptr, r.velo.data(), nullptr, arcs,
                           arcs, r.edge.data(), nullptr, r.edlo.data()),
        "SCOTCH_dgraphBuild", comm);
  bind_context(s, comm);
}

// The mapping strategy: recursive bipartitioning, each bipartition multilevel on the ranks that
// hold the (sub)graph, refined on the band around the cut by parallel diffusion and balanced by
// the parallel exactifier. Only a coarsest graph of under kCoarsest vertices is gathered (on
// every rank of the bipartition, for a sequential initial cut); PT-Scotch's predefined strategy
// gathers graphs of up to max(2000 x ranks, 10000) vertices and the band graph of every level,
// which puts the whole graph of a bed of a few thousand particles on every rank.
constexpr int kCoarsest = 200;

std::string strategy(double imbalance)
{
  const std::string bal = std::to_string(imbalance);
  const std::string seq = "m{vert=80,low=h{pass=10}f{bal=" + bal +
                          ",move=80},asc=b{bnd=f{bal=" + bal + ",move=80},org=f{bal=" + bal +
                          ",move=80}}}";
  return "r{bal=" + bal + ",sep=m{vert=" + std::to_string(kCoarsest) +
         ",asc=b{bnd=(d{pass=40}|)x{bal=" + bal + "},org=x{bal=" + bal + "}},low=q{strat=" + seq +
         "},seq=q{strat=" + seq + "}},seq=r{bal=" + bal + ",poli=S,sep=" + seq + "}}";
}

std::vector<int> scotch_parts(Session& s, std::size_t n, int nparts, double tolerance,
                              MPI_Comm comm)
{
  int nranks = 1;
  MPI_Comm_size(comm, &nranks);
  agree(SCOTCH_stratInit(&s.strat), "SCOTCH_stratInit", comm);
  s.strat_ok = true;
  agree(SCOTCH_stratDgraphMap(&s.strat, strategy(tolerance - 1.0).c_str()), "SCOTCH_stratDgraphMap",
        comm);
  std::vector<Num> part(std::max<std::size_t>(n, 1), 0);
  agree(SCOTCH_dgraphPart(&s.container, nparts, &s.strat, part.data()), "SCOTCH_dgraphPart", comm);
  std::vector<int> out(n);
  int bad = 0;
  for (std::size_t v = 0; v < n; ++v)
    out[v] = static_cast<int>(part[v]), bad |= part[v] < 0 || part[v] >= nparts;
  agree(bad, "SCOTCH_dgraphPart (a part number out of range)", comm);
  return out;
}

// Sum of the weights of edges whose ends lie in different parts; the parts of other ranks'
// vertices come from SCOTCH_dgraphHalo.
double scotch_edge_cut(Session& s, const DistributedGraph& g, const std::vector<int>& part,
                       MPI_Comm comm)
{
  agree(SCOTCH_dgraphGhst(&s.container), "SCOTCH_dgraphGhst", comm);
  Num nghost_total = 0;
  Num* edgegst = nullptr;
  SCOTCH_dgraphData(&s.container, nullptr, nullptr, nullptr, nullptr, &nghost_total, nullptr,
                    nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, &edgegst,
                    nullptr, nullptr);
  std::vector<Num> halo(std::max<Num>(nghost_total, 1), 0);
  std::copy(part.begin(), part.end(), halo.begin());
  const MPI_Datatype type = sizeof(Num) == 8 ? MPI_INT64_T : MPI_INT32_T;
  agree(SCOTCH_dgraphHalo(&s.container, halo.data(), type), "SCOTCH_dgraphHalo", comm);
  double mine = 0, sum = 0;
  const Graph& l = g.local;
  for (std::size_t v = 0; v + 1 < l.xadj.size(); ++v)
    for (std::int64_t e = l.xadj[v]; e < l.xadj[v + 1]; ++e)
      if (halo[edgegst[e]] != halo[v]) mine += static_cast<double>(l.adjwgt[e]);
  MPI_Allreduce(&mine, &sum, 1, MPI_DOUBLE, MPI_SUM, comm);
  return sum / 2;
}

DistributedResult run_ptscotch(const DistributedGraph& g, const GraphTotals& t, int nparts,
                               double tolerance, MPI_Comm comm)
{
  ScotchRows rows = scotch_rows(g, t);
  Session s;
  build(s, g, rows, comm);
  DistributedResult r;
  r.part = scotch_parts(s, g.local.vwgt.size(), nparts, tolerance, comm);
  const std::vector<double> load(g.local.vwgt.begin(), g.local.vwgt.end());
  const std::vector<int> label = distributed_labels(r.part, load, nparts, comm);
  for (int& p : r.part)
    p = label[p];
  r.predicted_imbalance = distributed_imbalance(r.part, load, nparts, comm);
  r.edge_cut = scotch_edge_cut(s, g, r.part, comm);
  return r;
}

#endif

} // namespace

#ifdef FRACDEM_HAVE_PTSCOTCH

bool have_ptscotch()
{
  return true;
}

DistributedResult partition_ptscotch(const DistributedGraph& g, int nparts, double tolerance,
                                     MPI_Comm comm)
{
  int nranks = 1;
  MPI_Comm_size(comm, &nranks);
  const GraphTotals t = graph_totals(g, comm);
  try {
    if (nparts < 1 || !(tolerance >= 1.0))
      throw std::invalid_argument("needs nparts >= 1 and a tolerance >= 1, got " +
                                  std::to_string(nparts) + " and " + std::to_string(tolerance));
    if (nparts == 1) {
      DistributedResult r;
      r.part.assign(g.local.vwgt.size(), 0);
      return r;
    }
    return run_ptscotch(g, t, nparts, tolerance, comm);
  } catch (const std::exception& e) {
    DistributedResult r;
    r.failed = true;
    r.failure = std::string("partitioner ptscotch: ") + e.what() + " " + graph_size(nranks, t);
    return r;
  }
}

#else

bool have_ptscotch()
{
  return false;
}

DistributedResult partition_ptscotch(const DistributedGraph& g, int, double, MPI_Comm comm)
{
  int nranks = 1;
  MPI_Comm_size(comm, &nranks);
  DistributedResult r;
  r.failed = true;
  r.failure = "partitioner ptscotch: this build has no PT-Scotch (install libptscotch-dev and "
              "rebuild) " +
              graph_size(nranks, graph_totals(g, comm));
  return r;
}

#endif

} // namespace fracdem::balance
