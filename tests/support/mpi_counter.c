// PMPI counting library (LD_PRELOAD): per-rank messages, bytes, partners, collectives, call sites.
//
// Counts are exact on any machine, oversubscribed or not, which timings on a shared 2-core VM are
// not (docs/balance_comparison.md). Each wrapped MPI call is attributed to its call site (the
// return address, as module + offset) so that a reader can tell the project's own calls from the
// host's; tests/support/mpicount.py resolves the offsets to function names.
//
// Environment: FRACDEM_MPICOUNT=PREFIX writes PREFIX.RANK.json at MPI_Finalize (nothing without).
#define _GNU_SOURCE
#include <dlfcn.h>
#include <limits.h>
#include <mpi.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

// What a wrapped call is: a point-to-point send, a receive post, a blocking completion (a wait
// or probe: a latency on the caller's path), a collective, or communicator management. A
// collective is also recorded a second time as "crecv" with the bytes this rank receives from it
// (the root of a gather all of them), so that a rank that collects more than the others shows.
enum Category { CAT_SEND, CAT_RECV, CAT_WAIT, CAT_COLL, CAT_COMM, CAT_CRECV, CAT_N };
static const char* const kCategoryName[CAT_N] = {"send", "recv", "wait", "coll", "comm", "crecv"};

// One call site: a return address in some module, and the MPI function it called.
typedef struct {
  void* addr;
  const char* func;
  int cat;
  int module;
  uint64_t count, bytes;
} Site;

enum { kMaxModules = 64, kSiteSlots = 1 << 14, kCommCache = 32 };

static struct {
  int rank, size;
  uint64_t total_count[CAT_N], total_bytes[CAT_N];
  uint64_t *dest_msgs, *dest_bytes; // per world rank, sends only
  Site sites[kSiteSlots];           // open addressing on (addr, func)
  int nsites, sites_full;
  double mpi_cpu;
  const char* module_name[kMaxModules];
  uintptr_t module_base[kMaxModules];
  int nmodules;
  struct {
    MPI_Comm comm;
    int n;
    int* to_world;
  } comms[kCommCache];
  int ncomms;
} g;

// Index of the module that holds addr (registered on first sight; -1 if unknown).
static int module_of(void* addr)
{
  Dl_info info;
  if (!dladdr(addr, &info) || !info.dli_fname) return -1;
  for (int m = 0; m < g.nmodules; ++m)
    if (g.module_base[m] == (uintptr_t)info.dli_fbase) return m;
  if (g.nmodules == kMaxModules) return -1;
  g.module_base[g.nmodules] = (uintptr_t)info.dli_fbase;
  g.module_name[g.nmodules] = strdup(info.dli_fname);
  return g.nmodules++;
}

static Site* site_of(void* addr, const char* func, int cat)
{
  uintptr_t h = ((uintptr_t)addr * 0x9E3779B97F4A7C15ull) ^ (uintptr_t)func ^ (uintptr_t)cat;
  for (int probe = 0; probe < kSiteSlots; ++probe) {
    Site* s = &g.sites[(h + probe) & (kSiteSlots - 1)];
    if (s->addr == addr && s->func == func && s->cat == cat) return s;
    if (s->addr == NULL) {
      if (g.nsites * 2 > kSiteSlots) break; // keep probing short; count in the overflow site
      s->addr = addr, s->func = func, s->cat = cat, s->module = module_of(addr);
      ++g.nsites;
      return s;
    }
  }
  g.sites_full = 1;
  return NULL;
}

// World rank of rank r of comm (cached per communicator; -1 for MPI_PROC_NULL and the like).
static int world_rank(MPI_Comm comm, int r)
{
  if (r < 0) return -1;
  if (comm == MPI_COMM_WORLD) return r;
  for (int k = 0; k < g.ncomms; ++k)
    if (g.comms[k].comm == comm) return r < g.comms[k].n ? g.comms[k].to_world[r] : -1;
  MPI_Group grp, wgrp;
  int n;
  PMPI_Comm_group(comm, &grp);
  PMPI_Comm_group(MPI_COMM_WORLD, &wgrp);
  PMPI_Group_size(grp, &n);
  int* ranks = malloc(sizeof(int) * (size_t)n);
  int* out = malloc(sizeof(int) * (size_t)n);
  for (int i = 0; i < n; ++i)
    ranks[i] = i;
  PMPI_Group_translate_ranks(grp, n, ranks, wgrp, out);
  free(ranks);
  PMPI_Group_free(&grp);
  PMPI_Group_free(&wgrp);
  const int result = r < n ? out[r] : -1;
  if (g.ncomms < kCommCache) {
    g.comms[g.ncomms].comm = comm, g.comms[g.ncomms].n = n, g.comms[g.ncomms].to_world = out;
    ++g.ncomms;
  } else {
    free(out);
  }
  return result;
}

static uint64_t bytes_of(int count, MPI_Datatype type)
{
  int size = 0;
  if (count <= 0 || type == MPI_DATATYPE_NULL) return 0;
  PMPI_Type_size(type, &size);
  return (uint64_t)count * (uint64_t)size;
}

static void record(void* addr, const char* func, int cat, uint64_t bytes)
{
  g.total_count[cat] += 1;
  g.total_bytes[cat] += bytes;
  Site* s = site_of(addr, func, cat);
  if (s) s->count += 1, s->bytes += bytes;
}

static void record_send(void* addr, const char* func, int count, MPI_Datatype type, int dest,
                        MPI_Comm comm)
{
  if (dest == MPI_PROC_NULL) return;
  const uint64_t bytes = bytes_of(count, type);
  record(addr, func, CAT_SEND, bytes);
  const int w = world_rank(comm, dest);
  if (g.dest_msgs && w >= 0 && w < g.size) g.dest_msgs[w] += 1, g.dest_bytes[w] += bytes;
}

#define CALLER __builtin_return_address(0)

static double cpu_now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

// Calls the PMPI function, adding the thread CPU time it takes (busy waiting included) to
// g.mpi_cpu, and returns its result.
#define MPI_TIMED(call)                                                                            \
  do {                                                                                             \
    const double t0_ = cpu_now();                                                                  \
    const int rc_ = (call);                                                                        \
    g.mpi_cpu += cpu_now() - t0_;                                                                  \
    return rc_;                                                                                    \
  } while (0)

// Thread CPU seconds spent inside wrapped MPI calls so far: a program (or an instrumented build)
// may look it up with dlsym(RTLD_DEFAULT, "fracdem_mpicount_mpi_cpu") to time its own work
// without the waits.
double fracdem_mpicount_mpi_cpu(void)
{
  return g.mpi_cpu;
}

// ---- set-up and output ------------------------------------------------------------------------

static void start(void)
{
  PMPI_Comm_rank(MPI_COMM_WORLD, &g.rank);
  PMPI_Comm_size(MPI_COMM_WORLD, &g.size);
  g.dest_msgs = calloc((size_t)g.size, sizeof(uint64_t));
  g.dest_bytes = calloc((size_t)g.size, sizeof(uint64_t));
}

int MPI_Init(int* argc, char*** argv)
{
  const int rc = PMPI_Init(argc, argv);
  start();
  return rc;
}

int MPI_Init_thread(int* argc, char*** argv, int required, int* provided)
{
  const int rc = PMPI_Init_thread(argc, argv, required, provided);
  start();
  return rc;
}

static void write_sites(FILE* f)
{
  int first = 1;
  fprintf(f, "\"sites\": [");
  for (int k = 0; k < kSiteSlots; ++k) {
    const Site* s = &g.sites[k];
    if (!s->addr) continue;
    const uintptr_t off = s->module >= 0 ? (uintptr_t)s->addr - g.module_base[s->module] : 0;
    fprintf(f,
            "%s\n  {\"module\": %d, \"offset\": %lu, \"func\": \"%s\", \"cat\": \"%s\", "
            "\"count\": %lu, \"bytes\": %lu}",
            first ? "" : ",", s->module, (unsigned long)off, s->func, kCategoryName[s->cat],
            (unsigned long)s->count, (unsigned long)s->bytes);
    first = 0;
  }
  fprintf(f, "],\n");
}

static void write_report(const char* prefix)
{
  char path[PATH_MAX], exe[PATH_MAX];
  snprintf(path, sizeof path, "%s.%d.json", prefix, g.rank);
  FILE* f = fopen(path, "w");
  if (!f) return;
  const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  exe[n > 0 ? n : 0] = '\0';
  fprintf(f, "{\"rank\": %d, \"size\": %d, \"exe\": \"%s\", \"sites_overflow\": %d,\n", g.rank,
          g.size, exe, g.sites_full);
  fprintf(f, "\"totals\": {");
  for (int c = 0; c < CAT_N; ++c)
    fprintf(f, "%s\"%s\": [%lu, %lu]", c ? ", " : "", kCategoryName[c],
            (unsigned long)g.total_count[c], (unsigned long)g.total_bytes[c]);
  fprintf(f, "},\n\"mpi_cpu\": %.6f,\n\"dest\": [", g.mpi_cpu);
  for (int r = 0; r < g.size; ++r)
    fprintf(f, "%s[%lu, %lu]", r ? ", " : "", (unsigned long)g.dest_msgs[r],
            (unsigned long)g.dest_bytes[r]);
  fprintf(f, "],\n\"modules\": [");
  for (int m = 0; m < g.nmodules; ++m)
    fprintf(f, "%s\"%s\"", m ? ", " : "", g.module_name[m]);
  fprintf(f, "],\n");
  write_sites(f);
  fprintf(f, "\"end\": 0}\n");
  fclose(f);
}

int MPI_Finalize(void)
{
  const char* prefix = getenv("FRACDEM_MPICOUNT");
  if (prefix && *prefix && g.dest_msgs) write_report(prefix);
  return PMPI_Finalize();
}

// ---- point-to-point ---------------------------------------------------------------------------

int MPI_Send(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm)
{
  record_send(CALLER, "MPI_Send", count, type, dest, comm);
  MPI_TIMED(PMPI_Send(buf, count, type, dest, tag, comm));
}

int MPI_Ssend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm)
{
  record_send(CALLER, "MPI_Ssend", count, type, dest, comm);
  MPI_TIMED(PMPI_Ssend(buf, count, type, dest, tag, comm));
}

int MPI_Bsend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm)
{
  record_send(CALLER, "MPI_Bsend", count, type, dest, comm);
  MPI_TIMED(PMPI_Bsend(buf, count, type, dest, tag, comm));
}

int MPI_Rsend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm)
{
  record_send(CALLER, "MPI_Rsend", count, type, dest, comm);
  MPI_TIMED(PMPI_Rsend(buf, count, type, dest, tag, comm));
}

int MPI_Isend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm,
              MPI_Request* req)
{
  record_send(CALLER, "MPI_Isend", count, type, dest, comm);
  MPI_TIMED(PMPI_Isend(buf, count, type, dest, tag, comm, req));
}

int MPI_Issend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm,
               MPI_Request* req)
{
  record_send(CALLER, "MPI_Issend", count, type, dest, comm);
  MPI_TIMED(PMPI_Issend(buf, count, type, dest, tag, comm, req));
}

int MPI_Ibsend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm,
               MPI_Request* req)
{
  record_send(CALLER, "MPI_Ibsend", count, type, dest, comm);
  MPI_TIMED(PMPI_Ibsend(buf, count, type, dest, tag, comm, req));
}

int MPI_Irsend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm,
               MPI_Request* req)
{
  record_send(CALLER, "MPI_Irsend", count, type, dest, comm);
  MPI_TIMED(PMPI_Irsend(buf, count, type, dest, tag, comm, req));
}

int MPI_Sendrecv(const void* sbuf, int scount, MPI_Datatype stype, int dest, int stag, void* rbuf,
                 int rcount, MPI_Datatype rtype, int source, int rtag, MPI_Comm comm,
                 MPI_Status* status)
{
  record_send(CALLER, "MPI_Sendrecv", scount, stype, dest, comm);
  if (source != MPI_PROC_NULL) record(CALLER, "MPI_Sendrecv", CAT_RECV, bytes_of(rcount, rtype));
  MPI_TIMED(PMPI_Sendrecv(sbuf, scount, stype, dest, stag, rbuf, rcount, rtype, source, rtag, comm,
                          status));
}

int MPI_Sendrecv_replace(void* buf, int count, MPI_Datatype type, int dest, int stag, int source,
                         int rtag, MPI_Comm comm, MPI_Status* status)
{
  record_send(CALLER, "MPI_Sendrecv_replace", count, type, dest, comm);
  if (source != MPI_PROC_NULL) record(CALLER, "MPI_Sendrecv_replace", CAT_RECV, 0);
  MPI_TIMED(PMPI_Sendrecv_replace(buf, count, type, dest, stag, source, rtag, comm, status));
}

int MPI_Recv(void* buf, int count, MPI_Datatype type, int source, int tag, MPI_Comm comm,
             MPI_Status* status)
{
  if (source != MPI_PROC_NULL) record(CALLER, "MPI_Recv", CAT_RECV, bytes_of(count, type));
  MPI_TIMED(PMPI_Recv(buf, count, type, source, tag, comm, status));
}

int MPI_Irecv(void* buf, int count, MPI_Datatype type, int source, int tag, MPI_Comm comm,
              MPI_Request* req)
{
  if (source != MPI_PROC_NULL) record(CALLER, "MPI_Irecv", CAT_RECV, bytes_of(count, type));
  MPI_TIMED(PMPI_Irecv(buf, count, type, source, tag, comm, req));
}

// ---- blocking completions: each one a point where the caller waits for a peer ----------------

int MPI_Wait(MPI_Request* req, MPI_Status* status)
{
  record(CALLER, "MPI_Wait", CAT_WAIT, 0);
  MPI_TIMED(PMPI_Wait(req, status));
}

int MPI_Waitall(int n, MPI_Request reqs[], MPI_Status statuses[])
{
  record(CALLER, "MPI_Waitall", CAT_WAIT, 0);
  MPI_TIMED(PMPI_Waitall(n, reqs, statuses));
}

int MPI_Waitany(int n, MPI_Request reqs[], int* index, MPI_Status* status)
{
  record(CALLER, "MPI_Waitany", CAT_WAIT, 0);
  MPI_TIMED(PMPI_Waitany(n, reqs, index, status));
}

int MPI_Waitsome(int n, MPI_Request reqs[], int* outcount, int indices[], MPI_Status statuses[])
{
  record(CALLER, "MPI_Waitsome", CAT_WAIT, 0);
  MPI_TIMED(PMPI_Waitsome(n, reqs, outcount, indices, statuses));
}

int MPI_Probe(int source, int tag, MPI_Comm comm, MPI_Status* status)
{
  record(CALLER, "MPI_Probe", CAT_WAIT, 0);
  MPI_TIMED(PMPI_Probe(source, tag, comm, status));
}

// ---- collectives (bytes: this rank's contribution) --------------------------------------------

#define COLL(name, bytes) record(CALLER, name, CAT_COLL, bytes)
#define CRECV(name, bytes) record(CALLER, name, CAT_CRECV, bytes)

static uint64_t sum_bytes(const int counts[], MPI_Datatype type, MPI_Comm comm)
{
  int n = 0;
  uint64_t total = 0;
  PMPI_Comm_size(comm, &n);
  for (int i = 0; i < n; ++i)
    total += bytes_of(counts[i], type);
  return total;
}

static int rank_in(MPI_Comm comm)
{
  int r = 0;
  PMPI_Comm_rank(comm, &r);
  return r;
}

static int size_of(MPI_Comm comm)
{
  int n = 0;
  PMPI_Comm_size(comm, &n);
  return n;
}

int MPI_Barrier(MPI_Comm comm)
{
  COLL("MPI_Barrier", 0);
  MPI_TIMED(PMPI_Barrier(comm));
}

int MPI_Ibarrier(MPI_Comm comm, MPI_Request* req)
{
  COLL("MPI_Ibarrier", 0);
  MPI_TIMED(PMPI_Ibarrier(comm, req));
}

int MPI_Bcast(void* buf, int count, MPI_Datatype type, int root, MPI_Comm comm)
{
  COLL("MPI_Bcast", bytes_of(count, type));
  CRECV("MPI_Bcast", rank_in(comm) == root ? 0 : bytes_of(count, type));
  MPI_TIMED(PMPI_Bcast(buf, count, type, root, comm));
}

int MPI_Reduce(const void* sbuf, void* rbuf, int count, MPI_Datatype type, MPI_Op op, int root,
               MPI_Comm comm)
{
  COLL("MPI_Reduce", bytes_of(count, type));
  CRECV("MPI_Reduce", rank_in(comm) == root ? bytes_of(count, type) : 0);
  MPI_TIMED(PMPI_Reduce(sbuf, rbuf, count, type, op, root, comm));
}

int MPI_Allreduce(const void* sbuf, void* rbuf, int count, MPI_Datatype type, MPI_Op op,
                  MPI_Comm comm)
{
  COLL("MPI_Allreduce", bytes_of(count, type));
  CRECV("MPI_Allreduce", bytes_of(count, type));
  MPI_TIMED(PMPI_Allreduce(sbuf, rbuf, count, type, op, comm));
}

int MPI_Iallreduce(const void* sbuf, void* rbuf, int count, MPI_Datatype type, MPI_Op op,
                   MPI_Comm comm, MPI_Request* req)
{
  COLL("MPI_Iallreduce", bytes_of(count, type));
  CRECV("MPI_Iallreduce", bytes_of(count, type));
  MPI_TIMED(PMPI_Iallreduce(sbuf, rbuf, count, type, op, comm, req));
}

int MPI_Scan(const void* sbuf, void* rbuf, int count, MPI_Datatype type, MPI_Op op, MPI_Comm comm)
{
  COLL("MPI_Scan", bytes_of(count, type));
  CRECV("MPI_Scan", bytes_of(count, type));
  MPI_TIMED(PMPI_Scan(sbuf, rbuf, count, type, op, comm));
}

int MPI_Exscan(const void* sbuf, void* rbuf, int count, MPI_Datatype type, MPI_Op op, MPI_Comm comm)
{
  COLL("MPI_Exscan", bytes_of(count, type));
  CRECV("MPI_Exscan", bytes_of(count, type));
  MPI_TIMED(PMPI_Exscan(sbuf, rbuf, count, type, op, comm));
}

int MPI_Gather(const void* sbuf, int scount, MPI_Datatype stype, void* rbuf, int rcount,
               MPI_Datatype rtype, int root, MPI_Comm comm)
{
  COLL("MPI_Gather", bytes_of(scount, stype));
  CRECV("MPI_Gather",
        rank_in(comm) == root ? bytes_of(rcount, rtype) * (uint64_t)size_of(comm) : 0);
  MPI_TIMED(PMPI_Gather(sbuf, scount, stype, rbuf, rcount, rtype, root, comm));
}

int MPI_Gatherv(const void* sbuf, int scount, MPI_Datatype stype, void* rbuf, const int rcounts[],
                const int displs[], MPI_Datatype rtype, int root, MPI_Comm comm)
{
  COLL("MPI_Gatherv", bytes_of(scount, stype));
  CRECV("MPI_Gatherv", rank_in(comm) == root ? sum_bytes(rcounts, rtype, comm) : 0);
  MPI_TIMED(PMPI_Gatherv(sbuf, scount, stype, rbuf, rcounts, displs, rtype, root, comm));
}

int MPI_Scatter(const void* sbuf, int scount, MPI_Datatype stype, void* rbuf, int rcount,
                MPI_Datatype rtype, int root, MPI_Comm comm)
{
  COLL("MPI_Scatter", bytes_of(rcount, rtype));
  CRECV("MPI_Scatter", bytes_of(rcount, rtype));
  MPI_TIMED(PMPI_Scatter(sbuf, scount, stype, rbuf, rcount, rtype, root, comm));
}

int MPI_Scatterv(const void* sbuf, const int scounts[], const int displs[], MPI_Datatype stype,
                 void* rbuf, int rcount, MPI_Datatype rtype, int root, MPI_Comm comm)
{
  COLL("MPI_Scatterv", bytes_of(rcount, rtype));
  CRECV("MPI_Scatterv", bytes_of(rcount, rtype));
  MPI_TIMED(PMPI_Scatterv(sbuf, scounts, displs, stype, rbuf, rcount, rtype, root, comm));
}

int MPI_Allgather(const void* sbuf, int scount, MPI_Datatype stype, void* rbuf, int rcount,
                  MPI_Datatype rtype, MPI_Comm comm)
{
  COLL("MPI_Allgather", bytes_of(scount, stype));
  CRECV("MPI_Allgather", bytes_of(rcount, rtype) * (uint64_t)size_of(comm));
  MPI_TIMED(PMPI_Allgather(sbuf, scount, stype, rbuf, rcount, rtype, comm));
}

int MPI_Allgatherv(const void* sbuf, int scount, MPI_Datatype stype, void* rbuf,
                   const int rcounts[], const int displs[], MPI_Datatype rtype, MPI_Comm comm)
{
  COLL("MPI_Allgatherv", bytes_of(scount, stype));
  CRECV("MPI_Allgatherv", sum_bytes(rcounts, rtype, comm));
  MPI_TIMED(PMPI_Allgatherv(sbuf, scount, stype, rbuf, rcounts, displs, rtype, comm));
}

int MPI_Alltoall(const void* sbuf, int scount, MPI_Datatype stype, void* rbuf, int rcount,
                 MPI_Datatype rtype, MPI_Comm comm)
{
  int n = 0;
  PMPI_Comm_size(comm, &n);
  COLL("MPI_Alltoall", bytes_of(scount, stype) * (uint64_t)n);
  CRECV("MPI_Alltoall", bytes_of(rcount, rtype) * (uint64_t)n);
  MPI_TIMED(PMPI_Alltoall(sbuf, scount, stype, rbuf, rcount, rtype, comm));
}

int MPI_Alltoallv(const void* sbuf, const int scounts[], const int sdispls[], MPI_Datatype stype,
                  void* rbuf, const int rcounts[], const int rdispls[], MPI_Datatype rtype,
                  MPI_Comm comm)
{
  COLL("MPI_Alltoallv", sum_bytes(scounts, stype, comm));
  CRECV("MPI_Alltoallv", sum_bytes(rcounts, rtype, comm));
  MPI_TIMED(PMPI_Alltoallv(sbuf, scounts, sdispls, stype, rbuf, rcounts, rdispls, rtype, comm));
}

int MPI_Reduce_scatter(const void* sbuf, void* rbuf, const int rcounts[], MPI_Datatype type,
                       MPI_Op op, MPI_Comm comm)
{
  COLL("MPI_Reduce_scatter", sum_bytes(rcounts, type, comm));
  CRECV("MPI_Reduce_scatter", bytes_of(rcounts[rank_in(comm)], type));
  MPI_TIMED(PMPI_Reduce_scatter(sbuf, rbuf, rcounts, type, op, comm));
}

int MPI_Reduce_scatter_block(const void* sbuf, void* rbuf, int rcount, MPI_Datatype type, MPI_Op op,
                             MPI_Comm comm)
{
  COLL("MPI_Reduce_scatter_block", bytes_of(rcount, type));
  CRECV("MPI_Reduce_scatter_block", bytes_of(rcount, type));
  MPI_TIMED(PMPI_Reduce_scatter_block(sbuf, rbuf, rcount, type, op, comm));
}

// ---- communicator management (collective, counted apart) --------------------------------------

int MPI_Comm_dup(MPI_Comm comm, MPI_Comm* out)
{
  record(CALLER, "MPI_Comm_dup", CAT_COMM, 0);
  MPI_TIMED(PMPI_Comm_dup(comm, out));
}

int MPI_Comm_split(MPI_Comm comm, int color, int key, MPI_Comm* out)
{
  record(CALLER, "MPI_Comm_split", CAT_COMM, 0);
  MPI_TIMED(PMPI_Comm_split(comm, color, key, out));
}

int MPI_Comm_free(MPI_Comm* comm)
{
  record(CALLER, "MPI_Comm_free", CAT_COMM, 0);
  for (int k = 0; k < g.ncomms; ++k) // a freed handle may come back for another communicator
    if (g.comms[k].comm == *comm) {
      free(g.comms[k].to_world);
      g.comms[k] = g.comms[--g.ncomms];
      break;
    }
  return PMPI_Comm_free(comm);
}
