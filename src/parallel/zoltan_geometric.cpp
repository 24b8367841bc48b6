// Zoltan's RCB / RIB / HSFC behind fix balance/graph: the query callbacks over this rank's
// positions and weights, the parameters, and the relabelled parts with their balance.
#include "zoltan_geometric.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#ifdef FRACDEM_HAVE_ZOLTAN
#include <zoltan.h>
#endif

namespace fracdem::balance
{

namespace
{

std::string vertex_count(std::size_t mine, MPI_Comm comm)
{
  int nranks = 1;
  MPI_Comm_size(comm, &nranks);
  double n = static_cast<double>(mine), all = 0;
  MPI_Allreduce(&n, &all, 1, MPI_DOUBLE, MPI_SUM, comm);
  return "on " + std::to_string(nranks) + " ranks, " + std::to_string(std::llround(all)) +
         " vertices (particles)";
}

void agree(bool bad, const std::string& what, MPI_Comm comm)
{
  int mine = bad, any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, comm);
  if (any) throw std::runtime_error(what + (mine ? " failed" : " failed on another rank"));
}

#ifdef FRACDEM_HAVE_ZOLTAN

// What the callbacks read: this rank's vertices, numbered from `first` rank by rank.
struct Points {
  const std::vector<double>* coords;
  const std::vector<double>* weight;
  int dim;
  long long first;
};

int num_obj(void* data, int* ierr)
{
  *ierr = ZOLTAN_OK;
  return static_cast<int>(static_cast<Points*>(data)->weight->size());
}

void obj_list(void* data, int, int, ZOLTAN_ID_PTR gids, ZOLTAN_ID_PTR lids, int wdim, float* wgts,
              int* ierr)
{
  const Points& p = *static_cast<Points*>(data);
  for (std::size_t v = 0; v < p.weight->size(); ++v) {
    gids[v] = static_cast<ZOLTAN_ID_TYPE>(p.first + static_cast<long long>(v));
    lids[v] = static_cast<ZOLTAN_ID_TYPE>(v);
    if (wdim > 0) wgts[v] = static_cast<float>((*p.weight)[v]);
  }
  *ierr = ZOLTAN_OK;
}

int num_geom(void* data, int* ierr)
{
  *ierr = ZOLTAN_OK;
  return static_cast<Points*>(data)->dim;
}

void geom_multi(void* data, int, int, int n, ZOLTAN_ID_PTR, ZOLTAN_ID_PTR lids, int dim,
                double* out, int* ierr)
{
  const Points& p = *static_cast<Points*>(data);
  for (int k = 0; k < n; ++k)
    for (int d = 0; d < dim; ++d)
      out[k * dim + d] = (*p.coords)[static_cast<std::size_t>(lids[k]) * p.dim + d];
  *ierr = ZOLTAN_OK;
}

void set_parameters(Zoltan_Struct* zz, const std::string& method, int nparts, double tolerance)
{
  const std::string params[][2] = {
      {"DEBUG_LEVEL", "0"},
      {"LB_METHOD", method},
      // Geometric methods are incremental by themselves; REPARTITION is what the graph methods
      // read, set for the methods of later Zoltan versions that read it too.
      {"LB_APPROACH", "REPARTITION"},
      {"NUM_GID_ENTRIES", "1"},
      {"NUM_LID_ENTRIES", "1"},
      {"OBJ_WEIGHT_DIM", "1"},
      {"RETURN_LISTS", "PARTS"},
      {"NUM_GLOBAL_PARTS", std::to_string(nparts)},
      {"IMBALANCE_TOL", std::to_string(tolerance)},
      // KEEP_CUTS serves point and box queries (Zoltan_LB_Point_Assign); ownership here follows
      // the particles, so the cuts are not kept. RCB's previous cuts seed its next ones.
      {"KEEP_CUTS", "0"},
  };
  for (const auto& p : params)
    Zoltan_Set_Param(zz, p[0].c_str(), p[1].c_str());
  if (method == "RCB") Zoltan_Set_Param(zz, "RCB_REUSE", "1");
}

#endif

} // namespace

ZoltanGeometric::ZoltanGeometric(std::string method, std::string name, MPI_Comm comm)
    : method_(std::move(method)), name_(std::move(name)), comm_(comm)
{
}

ZoltanGeometric::~ZoltanGeometric()
{
#ifdef FRACDEM_HAVE_ZOLTAN
  if (zz_) Zoltan_Destroy(&zz_);
#endif
}

DistributedResult ZoltanGeometric::partition(const std::vector<double>& coords, int dim,
                                             const std::vector<double>& weight, int nparts,
                                             double tolerance)
{
  try {
    const bool bad = nparts < 1 || !(tolerance >= 1.0) || dim < 1 || dim > 3 ||
                     coords.size() != weight.size() * static_cast<std::size_t>(dim);
    agree(bad,
          "the arguments (nparts >= 1, tolerance >= 1, dim 1..3, dim numbers per vertex: " +
              std::to_string(nparts) + ", " + std::to_string(tolerance) + ", " +
              std::to_string(dim) + ", " + std::to_string(coords.size()) + " for " +
              std::to_string(weight.size()) + ")",
          comm_);
    return run(coords, dim, weight, nparts, tolerance);
  } catch (const std::exception& e) {
    DistributedResult r;
    r.failed = true;
    r.failure = "partitioner " + name_ + ": " + e.what() + " " + vertex_count(weight.size(), comm_);
    return r;
  }
}

#ifdef FRACDEM_HAVE_ZOLTAN

DistributedResult ZoltanGeometric::run(const std::vector<double>& coords, int dim,
                                       const std::vector<double>& weight, int nparts,
                                       double tolerance)
{
  if (!zz_) {
    float version = 0;
    agree(Zoltan_Initialize(0, nullptr, &version) != ZOLTAN_OK, "Zoltan_Initialize", comm_);
    zz_ = Zoltan_Create(comm_);
    agree(zz_ == nullptr, "Zoltan_Create", comm_);
  }
  set_parameters(zz_, method_, nparts, tolerance);
  long long mine = static_cast<long long>(weight.size()), first = 0;
  MPI_Exscan(&mine, &first, 1, MPI_LONG_LONG, MPI_SUM, comm_);
  int rank = 0;
  MPI_Comm_rank(comm_, &rank);
  Points points{&coords, &weight, dim, rank == 0 ? 0 : first};
  Zoltan_Set_Num_Obj_Fn(zz_, num_obj, &points);
  Zoltan_Set_Obj_List_Fn(zz_, obj_list, &points);
  Zoltan_Set_Num_Geom_Fn(zz_, num_geom, &points);
  Zoltan_Set_Geom_Multi_Fn(zz_, geom_multi, &points);

  int changes = 0, ngid = 0, nlid = 0, nimp = 0, nexp = 0;
  ZOLTAN_ID_PTR igid = nullptr, ilid = nullptr, egid = nullptr, elid = nullptr;
  int *iproc = nullptr, *ipart = nullptr, *eproc = nullptr, *epart = nullptr;
  const int rc = Zoltan_LB_Partition(zz_, &changes, &ngid, &nlid, &nimp, &igid, &ilid, &iproc,
                                     &ipart, &nexp, &egid, &elid, &eproc, &epart);
  DistributedResult r;
  r.part.assign(weight.size(), -1);
  bool bad = rc != ZOLTAN_OK && rc != ZOLTAN_WARN;
  for (int k = 0; !bad && k < nexp; ++k)
    if (elid[k] < weight.size() && epart[k] >= 0 && epart[k] < nparts) r.part[elid[k]] = epart[k];
  for (std::size_t v = 0; !bad && v < r.part.size(); ++v)
    bad = r.part[v] < 0;
  Zoltan_LB_Free_Part(&igid, &ilid, &iproc, &ipart);
  Zoltan_LB_Free_Part(&egid, &elid, &eproc, &epart);
  agree(bad, "Zoltan_LB_Partition (LB_METHOD " + method_ + ", or a vertex without a part)", comm_);
  // Part numbers follow the cuts, not the ranks: give each part to the rank that has most of it.
  const std::vector<int> label = distributed_labels(r.part, weight, nparts, comm_);
  for (int& p : r.part)
    p = label[p];
  r.predicted_imbalance = distributed_imbalance(r.part, weight, nparts, comm_);
  return r;
}

#else

DistributedResult ZoltanGeometric::run(const std::vector<double>&, int, const std::vector<double>&,
                                       int, double)
{
  throw std::runtime_error("this build has no Zoltan (install libtrilinos-zoltan-dev and "
                           "rebuild)");
}

#endif

} // namespace fracdem::balance
