// Zoltan (LB_Partition, REPARTITION) behind the distributed graph: the query callbacks over this
// rank's rows, the parameters, and the balance and edge cut of the result.
#include "zoltan_partition.h"

#include <cmath>
#include <stdexcept>
#include <string>

#ifdef FRACDEM_HAVE_ZOLTAN
#include <zoltan.h>
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

#ifdef FRACDEM_HAVE_ZOLTAN

// What the callbacks read: this rank's rows and the owners of the ranges.
struct Rows {
  const DistributedGraph* g;
};

int num_obj(void* data, int* ierr)
{
  *ierr = ZOLTAN_OK;
  return static_cast<int>(static_cast<Rows*>(data)->g->local.vwgt.size());
}

void obj_list(void* data, int, int, ZOLTAN_ID_PTR gids, ZOLTAN_ID_PTR lids, int wdim, float* wgts,
              int* ierr)
{
  const DistributedGraph& g = *static_cast<Rows*>(data)->g;
  for (std::size_t v = 0; v < g.local.vwgt.size(); ++v) {
    gids[v] = static_cast<ZOLTAN_ID_TYPE>(g.first() + static_cast<std::int64_t>(v));
    lids[v] = static_cast<ZOLTAN_ID_TYPE>(v);
    if (wdim > 0) wgts[v] = static_cast<float>(g.local.vwgt[v]);
  }
  *ierr = ZOLTAN_OK;
}

void num_edges(void* data, int, int, int n, ZOLTAN_ID_PTR, ZOLTAN_ID_PTR lids, int* counts,
               int* ierr)
{
  const Graph& l = static_cast<Rows*>(data)->g->local;
  for (int k = 0; k < n; ++k)
    counts[k] = static_cast<int>(l.xadj[lids[k] + 1] - l.xadj[lids[k]]);
  *ierr = ZOLTAN_OK;
}

void edge_list(void* data, int, int, int n, ZOLTAN_ID_PTR, ZOLTAN_ID_PTR lids, int*,
               ZOLTAN_ID_PTR nbor, int* procs, int wdim, float* wgts, int* ierr)
{
  const DistributedGraph& g = *static_cast<Rows*>(data)->g;
  std::size_t out = 0;
  for (int k = 0; k < n; ++k)
    for (std::int64_t e = g.local.xadj[lids[k]]; e < g.local.xadj[lids[k] + 1]; ++e, ++out) {
      nbor[out] = static_cast<ZOLTAN_ID_TYPE>(g.local.adjncy[e]);
      procs[out] = owner_of(g.vtxdist, g.local.adjncy[e]);
      if (wdim > 0) wgts[out] = static_cast<float>(g.local.adjwgt[e]);
    }
  *ierr = ZOLTAN_OK;
}

void agree(int rc, const char* what, MPI_Comm comm)
{
  int mine = rc != ZOLTAN_OK && rc != ZOLTAN_WARN, any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, comm);
  if (any)
    throw std::runtime_error(
        std::string(what) + " failed " +
        (mine ? "with return code " + std::to_string(rc) : std::string("on another rank")));
}

void set_parameters(Zoltan_Struct* zz, int nparts, double tolerance, bool hypergraph)
{
  const std::string params[][2] = {
      {"DEBUG_LEVEL", "0"},
      {"LB_METHOD", hypergraph ? "HYPERGRAPH" : "GRAPH"},
      {"GRAPH_PACKAGE", "PHG"},
      {"LB_APPROACH", "REPARTITION"},
      {"NUM_GID_ENTRIES", "1"},
      {"NUM_LID_ENTRIES", "1"},
      {"OBJ_WEIGHT_DIM", "1"},
      {"EDGE_WEIGHT_DIM", "1"},
      {"RETURN_LISTS", "PARTS"},
      {"NUM_GLOBAL_PARTS", std::to_string(nparts)},
      {"IMBALANCE_TOL", std::to_string(tolerance)},
      {"CHECK_GRAPH", "0"},
      {"PHG_RANDOMIZE_INPUT", "0"},
      // PHG minimises multiplier x edge cut + particles moved. Zoltan's default (100) prices a
      // cut edge so far above a move that parts already within the tolerance get reshuffled;
      // 1 weighs a cut edge of unit weight like one particle moved.
      {"PHG_REPART_MULTIPLIER", "1"},
  };
  for (const auto& p : params)
    Zoltan_Set_Param(zz, p[0].c_str(), p[1].c_str());
}

// Zoltan_LB_Partition with every local vertex in its export list (RETURN_LISTS PARTS).
std::vector<int> zoltan_parts(Zoltan_Struct* zz, std::size_t n, MPI_Comm comm)
{
  int changes = 0, ngid = 0, nlid = 0, nimp = 0, nexp = 0;
  ZOLTAN_ID_PTR igid = nullptr, ilid = nullptr, egid = nullptr, elid = nullptr;
  int *iproc = nullptr, *ipart = nullptr, *eproc = nullptr, *epart = nullptr;
  const int rc = Zoltan_LB_Partition(zz, &changes, &ngid, &nlid, &nimp, &igid, &ilid, &iproc,
                                     &ipart, &nexp, &egid, &elid, &eproc, &epart);
  std::vector<int> part(n, -1);
  int bad = rc != ZOLTAN_OK && rc != ZOLTAN_WARN;
  for (int k = 0; !bad && k < nexp; ++k)
    if (elid[k] < n) part[elid[k]] = epart[k];
  for (std::size_t v = 0; !bad && v < n; ++v)
    bad |= part[v] < 0;
  Zoltan_LB_Free_Part(&igid, &ilid, &iproc, &ipart);
  Zoltan_LB_Free_Part(&egid, &elid, &eproc, &epart);
  agree(bad ? (rc == ZOLTAN_OK ? ZOLTAN_FATAL : rc) : ZOLTAN_OK,
        "Zoltan_LB_Partition (or a vertex without a part)", comm);
  return part;
}

DistributedResult run_zoltan(const DistributedGraph& g, int nparts, double tolerance,
                             bool hypergraph, MPI_Comm comm)
{
  static bool initialised = false; // Zoltan_Initialize once per process (MPI is running)
  float version = 0;
  if (!initialised) agree(Zoltan_Initialize(0, nullptr, &version), "Zoltan_Initialize", comm);
  initialised = true;
  Rows rows{&g};
  Zoltan_Struct* zz = Zoltan_Create(comm);
  set_parameters(zz, nparts, tolerance, hypergraph);
  Zoltan_Set_Num_Obj_Fn(zz, num_obj, &rows);
  Zoltan_Set_Obj_List_Fn(zz, obj_list, &rows);
  Zoltan_Set_Num_Edges_Multi_Fn(zz, num_edges, &rows);
  Zoltan_Set_Edge_List_Multi_Fn(zz, edge_list, &rows);
  DistributedResult r;
  try {
    r.part = zoltan_parts(zz, g.local.vwgt.size(), comm);
  } catch (...) {
    Zoltan_Destroy(&zz);
    throw;
  }
  Zoltan_Destroy(&zz);
  const std::vector<double> load(g.local.vwgt.begin(), g.local.vwgt.end());
  r.predicted_imbalance = distributed_imbalance(r.part, load, nparts, comm);
  r.edge_cut = distributed_edge_cut(g, r.part, comm);
  return r;
}

#endif

} // namespace

#ifdef FRACDEM_HAVE_ZOLTAN

bool have_zoltan()
{
  return true;
}

DistributedResult partition_zoltan(const DistributedGraph& g, int nparts, double tolerance,
                                   bool hypergraph, MPI_Comm comm)
{
  int nranks = 1;
  MPI_Comm_size(comm, &nranks);
  const GraphTotals t = graph_totals(g, comm);
  const char* method = hypergraph ? "partitioner zoltan-phg" : "partitioner zoltan-graph";
  try {
    if (nparts < 1 || !(tolerance >= 1.0))
      throw std::invalid_argument("needs nparts >= 1 and a tolerance >= 1, got " +
                                  std::to_string(nparts) + " and " + std::to_string(tolerance));
    return run_zoltan(g, nparts, tolerance, hypergraph, comm);
  } catch (const std::exception& e) {
    DistributedResult r;
    r.failed = true;
    r.failure = std::string(method) + ": " + e.what() + " " + graph_size(nranks, t);
    return r;
  }
}

#else

bool have_zoltan()
{
  return false;
}

DistributedResult partition_zoltan(const DistributedGraph& g, int, double, bool hypergraph,
                                   MPI_Comm comm)
{
  int nranks = 1;
  MPI_Comm_size(comm, &nranks);
  DistributedResult r;
  r.failed = true;
  r.failure = std::string(hypergraph ? "partitioner zoltan-phg" : "partitioner zoltan-graph") +
              ": this build has no Zoltan (install libtrilinos-zoltan-dev and rebuild) " +
              graph_size(nranks, graph_totals(g, comm));
  return r;
}

#endif

} // namespace fracdem::balance
