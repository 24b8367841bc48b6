// Opt-in cost statistics of graph-mode borders (thread CPU per owned atom, MPI excluded) for the
// bench.
#include "comm_graph.h"

#include <cstdio>
#include <cstdlib>
#include <ctime>

#include <dlfcn.h>

using namespace LAMMPS_NS;

namespace
{
double thread_cpu()
{
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

// The PMPI counter's thread CPU inside MPI (bench: LD_PRELOADed libfracdem_mpicount.so), so that
// busy-waiting for partners does not count as ghost search; null without the counter.
using MpiCpuFn = double (*)();
MpiCpuFn mpi_cpu_fn()
{
  static const MpiCpuFn fn =
      reinterpret_cast<MpiCpuFn>(dlsym(RTLD_DEFAULT, "fracdem_mpicount_mpi_cpu"));
  return fn;
}
} // namespace

void CommGraph::borders_stats_begin()
{
  if (!stats_on_) return;
  stats_cpu0_ = thread_cpu();
  stats_mpi0_ = mpi_cpu_fn() ? mpi_cpu_fn()() : 0.0;
}

void CommGraph::borders_stats_end(int nlocal)
{
  if (!stats_on_) return;
  stats_.calls += 1;
  stats_.owned += nlocal;
  stats_.cpu += thread_cpu() - stats_cpu0_;
  stats_.mpi_cpu += (mpi_cpu_fn() ? mpi_cpu_fn()() : 0.0) - stats_mpi0_;
}

// One line per rank on stderr at the end (no MPI: this runs from the destructor).
void CommGraph::report_borders_stats() const
{
  if (!stats_on_ || stats_.calls == 0) return;
  const double own = stats_.cpu - stats_.mpi_cpu;
  fprintf(stderr,
          "fracdem borders stats rank %d: calls %ld owned_atom_calls %.0f cpu_s %.6f "
          "mpi_cpu_s %.6f%s us_per_owned_atom %.4f\n",
          me, stats_.calls, stats_.owned, stats_.cpu, stats_.mpi_cpu,
          mpi_cpu_fn() ? "" : " (no counter: MPI included)",
          stats_.owned > 0 ? 1e6 * own / stats_.owned : 0.0);
}

bool CommGraph::borders_stats_wanted()
{
  return std::getenv("FRACDEM_BORDERS_STATS") != nullptr;
}
