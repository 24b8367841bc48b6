// MPI check of a distributed body: each rank steps its METIS part with the neighbour exchange, rank
// 0 steps the whole body, and the two must agree (positions, energy); shared nodes bit-identical.
//
//   mpirun -np P fracdem_dist_check [tet|tri|quad] [STEPS] [CELLS] [check|time|time_replicated]
//       [corotational|elastic]
//
// Prints one line "dist_check ..." on rank 0 and exits 1 when a check fails. `time` skips the
// whole body (no comparison) and prints the step loop's wall time and the ranks' peak memory
// instead; `time_replicated` times today's replicated body the same way (every rank holds the
// whole body, computes a share of the elements, and all-reduces all nodal forces each step, as
// fix fem/body does without `parallel distributed`): bench/distributed_body.py. Run under the PMPI
// counter (tests/integration/test_distributed_counts.py) it shows what one step sends: set-up and
// the final comparison are the same for any STEPS and cancel in the difference of two runs.
#include <mpi.h>
#include <sys/resource.h>

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "fem/body.h"
#include "body/body_partition.h"
#include "body/body_setup.h"
#include "io/mesh_generators.h"
#include "node_exchange.h"

using namespace fracdem;

namespace
{

Mesh make_mesh(const std::string& kind, int cells)
{
  if (kind == "tet") return make_box_tet_mesh(2 * cells, cells, cells, 0.2, 0.1, 0.1);
  return make_rect_mesh(4 * cells, 2 * cells, 0.2, 0.1, {0, 0},
                        kind == "tri" ? ElemType::Tri3 : ElemType::Quad4);
}

// A clamped steel body set swinging and twisting: every element strains.
Kinematics kinematics = Kinematics::Corotational;

void set_up(Body& b, const Mesh& m)
{
  Material steel;
  steel.E = 2e11;
  steel.nu = 0.3;
  steel.rho = 7800;
  steel.kinematics = kinematics;
  b.build(m, steel, false);
  for (int n = 0; n < m.num_nodes(); ++n) {
    const double* X = &m.X[3 * n];
    const double v[3] = {20.0 * X[1], 30.0 * X[0], m.dim == 3 ? -40.0 * X[0] * X[1] : 0.0};
    b.set_velocity({n}, v);
  }
  b.set_fixed(m.node_sets.at("xmin"), 7, 0); // reaction group 0
  b.impose_velocity_conditions();
}

// One velocity-Verlet step; `sum` completes the internal forces (exchange or nothing).
template <class Sum> double step(Body& b, double dt, Sum sum)
{
  const double g[3] = {0, 0, 0};
  b.half_kick_drift(dt);
  b.begin_forces();
  int inverted = -1;
  const double energy = b.add_internal_forces(&inverted);
  if (inverted >= 0) {
    std::fprintf(stderr, "dist_check: element %d inverted\n", inverted);
    std::exit(2);
  }
  sum(b.forces_data());
  b.finish_forces(energy, g, dt, true);
  b.half_kick(dt);
  return energy;
}

// `time` mode: the slowest rank's loop time and every rank's peak resident memory.
int report_timing(const char* mode, int rank, int nprocs, const Mesh& mesh, int steps, double loop)
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  double peak_mb = usage.ru_maxrss / 1024.0, peak_max = peak_mb;
  MPI_Allreduce(MPI_IN_PLACE, &loop, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &peak_max, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  if (rank == 0)
    std::printf("dist_time mode=%s np=%d steps=%d elements=%d nodes=%d loop_seconds=%.6f "
                "ms_per_step=%.4f peak_rss_mb_max=%.1f\n",
                mode, nprocs, steps, mesh.num_elems(), mesh.num_nodes(), loop, 1e3 * loop / steps,
                peak_max);
  MPI_Finalize();
  return 0;
}

// Today's replicated body: element work split by ranges, nodal forces all-reduced every step.
int time_replicated(int rank, int nprocs, const Mesh& mesh, int steps)
{
  Body body;
  set_up(body, mesh);
  split_element_work(body, rank, nprocs);
  const double dt = 0.5 * body.stable_time_step();
  const int n3 = 3 * body.num_nodes();
  MPI_Barrier(MPI_COMM_WORLD);
  const double t0 = MPI_Wtime();
  for (int s = 0; s < steps; ++s)
    step(body, dt, [&](double* f) {
      if (nprocs > 1) MPI_Allreduce(MPI_IN_PLACE, f, n3, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    });
  return report_timing("replicated", rank, nprocs, mesh, steps, MPI_Wtime() - t0);
}

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  int rank = 0, nprocs = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &nprocs);
  const std::string kind = argc > 1 ? argv[1] : "tet";
  const int steps = argc > 2 ? std::atoi(argv[2]) : 200;
  const int cells = argc > 3 ? std::atoi(argv[3]) : 4;
  const std::string mode = argc > 4 ? argv[4] : "check";
  if (argc > 5 && std::string(argv[5]) == "elastic") kinematics = Kinematics::SmallStrain;
  const bool timing = mode == "time";
  const Mesh mesh = make_mesh(kind, cells);
  if (mode == "time_replicated") return time_replicated(rank, nprocs, mesh, steps);

  // Set-up: every rank partitions the same mesh the same way and keeps its part.
  const MeshPart part = extract_part(mesh, partition_elements(mesh, nprocs), rank);
  Body body;
  set_up(body, part.mesh);
  NodeExchange exchange(MPI_COMM_WORLD, part);
  std::vector<double> mass = body.masses();
  exchange.sum(mass.data(), 1);
  body.set_masses(mass);
  std::vector<std::uint8_t> owned(part.num_nodes());
  for (int n = 0; n < part.num_nodes(); ++n)
    owned[n] = part.owns(n);
  body.set_counted_nodes(owned);
  // The stable step of the whole body: the smallest of the parts'.
  double dt = 0.5 * body.stable_time_step();
  MPI_Allreduce(MPI_IN_PLACE, &dt, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);

  MPI_Barrier(MPI_COMM_WORLD);
  const double t0 = MPI_Wtime();
  double strain = 0;
  for (int s = 0; s < steps; ++s)
    strain = step(body, dt, [&](double* f) { exchange.sum(f, 3); });
  double loop = MPI_Wtime() - t0;
  if (timing) return report_timing("distributed", rank, nprocs, mesh, steps, loop);

  // Comparison (after the steps; its traffic does not depend on STEPS).
  std::vector<double> mine; // global node, x, y, z
  for (int n = 0; n < part.num_nodes(); ++n) {
    mine.push_back(part.global_node[n]);
    mine.insert(mine.end(), &body.positions()[3 * n], &body.positions()[3 * n] + 3);
  }
  // Sums over the parts (each counts its owned nodes): energy, reaction of the clamp, momentum.
  double sums[8] = {body.kinetic_energy(), strain};
  for (int d = 0; d < 3; ++d) {
    sums[2 + d] = body.reactions()[d];
    sums[5 + d] = body.momentum(d);
  }
  MPI_Allreduce(MPI_IN_PLACE, sums, 8, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  int count = static_cast<int>(mine.size());
  std::vector<int> counts(nprocs), offsets(nprocs, 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  for (int r = 1; r < nprocs; ++r)
    offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<double> all(rank == 0 ? offsets.back() + counts.back() : 0);
  MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE,
              0, MPI_COMM_WORLD);
  int shared_sum = part.num_shared_nodes(), neighbours = static_cast<int>(part.neighbours.size());
  long long interface_pairs = 0;
  for (const PartNeighbour& nb : part.neighbours)
    interface_pairs += static_cast<long long>(nb.nodes.size());
  MPI_Allreduce(MPI_IN_PLACE, &shared_sum, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &neighbours, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &interface_pairs, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  int failed = 0;
  if (rank == 0) {
    Body whole;
    set_up(whole, mesh);
    double whole_strain = 0;
    for (int s = 0; s < steps; ++s)
      whole_strain = step(whole, dt, [](double*) {});
    const double whole_total = whole.kinetic_energy() + whole_strain;
    double worst = 0, moved = 0;
    bool identical = true;
    std::vector<std::vector<double>> seen(mesh.num_nodes());
    for (size_t i = 0; i < all.size(); i += 4) {
      const int g = static_cast<int>(all[i]);
      const double* x = &all[i + 1];
      for (int d = 0; d < 3; ++d) {
        worst = std::max(worst, std::abs(x[d] - whole.positions()[3 * g + d]));
        moved = std::max(moved, std::abs(whole.positions()[3 * g + d] - mesh.X[3 * g + d]));
      }
      if (seen[g].empty())
        seen[g].assign(x, x + 3);
      else if (!std::equal(x, x + 3, seen[g].begin()))
        identical = false;
    }
    const double energy_rel = std::abs(sums[0] + sums[1] - whole_total) / whole_total;
    double reaction_rel = 0, momentum_rel = 0, reaction_scale = 0, momentum_scale = 0;
    for (int d = 0; d < 3; ++d) {
      reaction_scale = std::max(reaction_scale, std::abs(whole.reactions()[d]));
      momentum_scale = std::max(momentum_scale, std::abs(whole.momentum(d)));
    }
    for (int d = 0; d < 3; ++d) {
      reaction_rel =
          std::max(reaction_rel, std::abs(sums[2 + d] - whole.reactions()[d]) / reaction_scale);
      momentum_rel =
          std::max(momentum_rel, std::abs(sums[5 + d] - whole.momentum(d)) / momentum_scale);
    }
    // Tolerances: positions within 1e-10 of the body's size (round-off of a different summation
    // order, ~1e-15 m here), energy within 1e-10 relative (issue #13, item 3).
    failed = !(worst < 1e-10 * 0.2) || !(energy_rel < 1e-10) || !identical || !(moved > 1e-6) ||
             !(reaction_rel < 1e-10) || !(momentum_rel < 1e-10);
    std::printf("dist_check kind=%s np=%d steps=%d elements=%d nodes=%d shared_nodes=%d "
                "interface_pairs=%lld max_neighbours=%d max_position_difference=%.3e "
                "moved=%.3e energy_relative_difference=%.3e reaction_relative_difference=%.3e "
                "momentum_relative_difference=%.3e shared_identical=%s result=%s\n",
                kind.c_str(), nprocs, steps, mesh.num_elems(), mesh.num_nodes(), shared_sum,
                interface_pairs, neighbours, worst, moved, energy_rel, reaction_rel, momentum_rel,
                identical ? "yes" : "no", failed ? "FAIL" : "ok");
  }
  MPI_Bcast(&failed, 1, MPI_INT, 0, MPI_COMM_WORLD);
  MPI_Finalize();
  return failed;
}
