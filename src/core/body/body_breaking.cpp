// A distributed body that breaks: the fracture check on the whole body gathered on rank 0, and
// the parts of the changed body scattered again (docs/distributed_bodies.md).
#include "body/body_driver.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "body/body_setup.h"
#include "body/part_restart.h"

namespace fracdem
{

namespace
{

// Modelled cost of a damaged element against an intact one of the same type: a damaged Rankine
// point takes the eigen-solve and spectral split that an intact point below f_t skips (materials/
// rankine.cpp). A yielded J2 element likewise: its points that flow take the radial return
// (materials/plasticity.cpp) that an elastic trial skips. Models, not measurements
// (docs/distributed_bodies.md).
constexpr int kDamagedElementCost = 2;
constexpr int kYieldedElementCost = 2;

// Per element: its integration points, times kDamagedElementCost where one is damaged (or
// kYieldedElementCost where one has yielded); 0 for eroded elements. These are the dual graph's
// vertex weights and the parts' work.
std::vector<int64_t> element_costs(const Body& body)
{
  const Mesh& mesh = body.mesh();
  std::vector<int64_t> cost(mesh.num_elems(), 0);
  for (int e = 0; e < mesh.num_elems(); ++e)
    if (mesh.active[e])
      cost[e] = points_per_elem(mesh.etype[e]) *
                (body.element_damaged(e)   ? kDamagedElementCost
                 : body.element_yielded(e) ? kYieldedElementCost
                                           : 1);
  return cost;
}

// The parts decide a crack point alone only where its whole star is theirs (fracture_may_change),
// so the partition keeps the stars of the crack points (the nodes of the failed elements) whole:
// stars that overlap form a cluster (a crack band and the elements around it), and each cluster is
// one vertex of the dual graph that METIS partitions, so it goes to one part with its cost while
// the other elements balance around it. A cluster above the mean part's cost stays elements (its
// points on part boundaries then gather the body at every check). Per element: its vertex.
std::vector<int> crack_vertices(const Body& whole, const std::vector<int64_t>& cost, int nparts,
                                int& vertices)
{
  const Mesh& mesh = whole.mesh();
  const NodeStars& stars = whole.stars();
  const int ne = mesh.num_elems();
  std::vector<int> root(ne);
  for (int e = 0; e < ne; ++e)
    root[e] = e;
  const auto find = [&root](int e) {
    while (root[e] != e)
      e = root[e] = root[root[e]];
    return e;
  };
  for (int f = 0; f < ne; ++f) {
    double n[3];
    if (!mesh.active[f] || whole.element_failure(f, n) < 1.0) continue;
    for (int a = 0; a < nodes_per_elem(mesh.etype[f]); ++a)
      for (const int* e = stars.begin(mesh.conn[f][a]); e != stars.end(mesh.conn[f][a]); ++e)
        root[find(*e)] = find(f);
  }
  std::vector<double> weight(ne, 0.0);
  double total = 0;
  for (int e = 0; e < ne; ++e) {
    weight[find(e)] += static_cast<double>(cost[e]);
    total += static_cast<double>(cost[e]);
  }
  std::vector<int> vertex(ne, -1);
  vertices = 0;
  for (int e = 0; e < ne; ++e) {
    const int r = find(e);
    const bool contract = r != e || weight[r] > static_cast<double>(cost[e]);
    if (contract && weight[r] <= total / nparts) {
      if (vertex[r] < 0) vertex[r] = vertices++;
      vertex[e] = vertex[r];
    } else {
      vertex[e] = vertices++;
    }
  }
  return vertex;
}

// METIS parts of the active elements (cost: their weights) with each crack cluster in one part.
std::vector<int> partition_keeping_cracks(const Body& whole, const std::vector<int64_t>& cost,
                                          int nparts)
{
  const Mesh& mesh = whole.mesh();
  int vertices = 0;
  const std::vector<int> vertex = crack_vertices(whole, cost, nparts, vertices);
  if (vertices == mesh.num_elems()) return partition_elements(mesh, nparts, cost); // no cluster
  const balance::Graph dual = element_dual_graph(mesh, cost);
  std::vector<int64_t> weight(vertices, 0);
  std::vector<balance::WeightedPair> pairs;
  for (int e = 0; e < mesh.num_elems(); ++e) {
    weight[vertex[e]] += dual.vwgt[e];
    for (int64_t k = dual.xadj[e]; k < dual.xadj[e + 1]; ++k)
      if (vertex[e] < vertex[dual.adjncy[k]])
        pairs.push_back({vertex[e], vertex[dual.adjncy[k]], dual.adjwgt[k]});
  }
  const std::vector<int> by_vertex =
      balance::partition_kway(balance::build_graph(vertices, weight, pairs), nparts);
  std::vector<int> part(mesh.num_elems(), -1);
  for (int e = 0; e < mesh.num_elems(); ++e)
    if (mesh.active[e]) part[e] = by_vertex[vertex[e]];
  return part;
}
} // namespace

// Every decision of the replicated check (crack points, the collapsed elements it erodes) comes
// from the elements whose last force evaluation found a point that carries no more tension, and
// once a body has cracked they stay failed: so each part also asks whether the check can change
// anything there (fracture_may_change). One integer max-reduction of both tells every rank; the
// parts are gathered on rank 0 only when some part holds a failed element and some part says the
// check may change the body. Rank 0 runs the replicated check on the whole body (its log lines,
// its numbering). Without a change one more reduction says so (and whether a pinched node is
// left) and every part goes on untouched; after a change rank 0 partitions the new body and
// every rank takes its new part.
void BodyDriver::distributed_fracture(std::int64_t step, double dt)
{
  int flag[2] = {0, 0}; // a part holds an active failed element; the check may change the body
  if (body_.damaged_points() > 0)
    for (int e : *body_.failed_elements()) // a part's evaluation covers all its elements
      if (body_.mesh().active[e]) flag[0] = 1;
  const bool separation_due = separation_watch_.due(body_);
  flag[1] = separation_due || (flag[0] && fracture_may_change(dt)) ? 1 : 0;
  host_.max_int(flag, 2);
  if (!flag[0] || !flag[1]) return;
  Body whole;
  std::vector<int> owner;
  int changed[4] = {0, 0, 0, 0}; // topology changed, elements cut, the outlook's two answers
  if (gather_whole(whole, owner)) {
    FractureOutcome out;
    SeparationOutlook outlook;
    std::swap(body_, whole); // the replicated check and its log lines, on the whole body
    changed[0] = crack_body(step, dt, out, &outlook) ? 1 : 0;
    changed[1] = out.cuts.empty() ? 0 : 1;
    changed[2] = outlook.pinch_left ? 1 : 0;
    changed[3] = outlook.pieces_touch ? 1 : 0;
    if (changed[0]) log_cracks(step, out);
    std::swap(body_, whole);
  }
  host_.max_int(changed, 4);
  separation_watch_.checked(body_, {changed[2] != 0, changed[3] != 0});
  if (!changed[0]) return;
  broken_ = true;
  std::vector<int> elem_part;
  if (host_.rank == 0) {
    count_whole(whole);
    elem_part = repartition(whole, owner);
  }
  scatter_whole(whole, elem_part); // adopt_part notes the new part's eroded elements
  check_step_after_cracks(step, dt, changed[1] != 0);
}

// Whether the whole body's check may change anything at this part's failed elements: the plan of
// the check on the part is not empty (plan_fracture with the part's crack marks: a crack point
// whose star is not wholly here is undecided, a change). The part's elements are pieces of cut
// elements of unknown fraction: 1 is taken (an upper bound, so a cut the check would make is
// never missed).
bool BodyDriver::fracture_may_change(double dt)
{
  if (!body_.failed_elements()) return true; // the last evaluation saw part of the elements
  build_failure_map(body_, failure_map_);
  const CrackNodes nodes = part_crack_nodes(part_, topo_, spec_->min_size);
  FracturePlanInput in = fracture_input(failure_map_, dt);
  in.part = &nodes;
  in.fraction = [](int) { return 1.0; };
  return !plan_fracture(body_, in).empty();
}

// Every rank sends rank 0 its part (pack_part_whole); rank 0 (true) builds the whole body from the
// mesh and the gathered state; owner: each element's part.
bool BodyDriver::gather_whole(Body& whole, std::vector<int>& owner) const
{
  const std::vector<double> all = host_.gather(pack_part_whole(body_, part_, topo_));
  if (host_.rank != 0) return false;
  try {
    GatheredBody g = merge_part_wholes(all, global_nodes_, global_elems_, mesh_elems_,
                                       body_.bulk_viscosity().on);
    build_body(*spec_, dimension_, whole);
    restore_gathered(g, whole);
    owner = std::move(g.owner);
  } catch (const std::exception& e) {
    fail_one(prefix() + "gathering the parts of the broken body: " + e.what());
  }
  return true;
}

// The whole body's split nodes and fragments (rank 0 writes them in the energy file).
void BodyDriver::count_whole(const Body& whole)
{
  whole_split_nodes_ = split_node_count(whole);
  whole_fragments_ = fragment_count(whole);
}

// METIS parts of the active elements (each crack cluster whole: partition_keeping_cracks),
// relabelled so that as many elements as possible stay with the rank that held them (as
// balance/graph relabels); an eroded element stays where it was (its material state still counts
// in the dissipated energy; the free nodes it leaves go on moving).
std::vector<int> BodyDriver::repartition(const Body& whole, const std::vector<int>& owner) const
{
  const Mesh& mesh = whole.mesh();
  std::vector<int64_t> cost = element_costs(whole);
  for (int64_t& c : cost)
    c = std::max<int64_t>(c, 1); // METIS weights >= 1 (eroded elements take no part anyway)
  std::vector<int> part = partition_keeping_cracks(whole, cost, host_.nprocs);
  std::vector<int> old(owner);
  old.resize(part.size(), -1); // elements made by cuts had no owner
  std::vector<double> moved(part.size(), 1.0);
  for (size_t e = 0; e < part.size(); ++e)
    if (!mesh.active[e]) { // not partitioned (-1): weightless in the relabelling
      part[e] = 0;
      moved[e] = 0.0;
    }
  part = balance::relabel_max_overlap(part, old, moved, host_.nprocs);
  for (size_t e = 0; e < part.size(); ++e)
    if (!mesh.active[e]) part[e] = old[e] >= 0 ? old[e] : 0;
  return part;
}

// Rank 0 sends each rank its part of the whole body with its state (one message at a time);
// every rank builds its part afresh from it.
void BodyDriver::scatter_whole(const Body& whole, const std::vector<int>& elem_part)
{
  std::vector<double> packed_surface;
  PartTopology topo;
  if (host_.rank == 0) {
    packed_surface = pack_surface(global_surface(whole.mesh(), elem_part));
    topo = whole_topology(whole);
  }
  const auto make = [&](int r) {
    return part_message_with_state(whole, topo, elem_part, packed_surface, r);
  };
  adopt_part(host_.scatter(make));
}

// This rank's part from its message: body, topology, interface sums, facet ghosts, surfaces.
void BodyDriver::adopt_part(const std::vector<double>& message)
{
  GlobalSurface surface;
  std::size_t at = 0;
  body_ = Body();
  try {
    part_ = build_body_part(*spec_, message, body_, global_nodes_, global_elems_, &surface, &at);
    unpack_part_message_state(message, at, body_, part_, topo_);
  } catch (const std::exception& e) {
    fail_one(prefix() + "taking the new part of the broken body: " + e.what());
  }
  ghosts_.init(part_, std::move(surface));
  boxes_due_ = true;
  whole_mesh_known_ = false; // the parts changed: rank 0 gathers them again at the next erosion
  separation_watch_.adopted(body_);
  shared_sum_ = host_.shared_sum_for(part_);
  double pairs = 0;
  for (const PartNeighbour& nb : part_.neighbours)
    pairs += static_cast<double>(nb.nodes.size());
  host_.sum(&pairs, 1);
  interface_pairs_ = static_cast<long long>(pairs);
  rebuild_surfaces();
}

// Item 4 of issue #13: every rebalance_every steps the parts compare their modelled work (one
// max- and one sum-reduction of a double); above rebalance times the mean the body is gathered,
// partitioned afresh and scattered as after a topology change, and rank 0 logs it.
void BodyDriver::check_balance(std::int64_t step)
{
  const std::vector<int64_t> cost = element_costs(body_);
  double work[2] = {0, 0};
  for (int64_t c : cost)
    work[0] += static_cast<double>(c);
  work[1] = work[0];
  host_.max(&work[0], 1);
  host_.sum(&work[1], 1);
  const double mean = work[1] / host_.nprocs;
  if (!(mean > 0) || !(work[0] / mean > spec_->rebalance)) return;
  separation_watch_.note_erosion(body_); // before the part is built afresh
  Body whole;
  std::vector<int> owner, elem_part;
  if (gather_whole(whole, owner)) {
    elem_part = repartition(whole, owner);
    std::vector<double> load(host_.nprocs, 0.0);
    const std::vector<int64_t> whole_cost = element_costs(whole);
    long moved = 0;
    for (size_t e = 0; e < elem_part.size(); ++e) {
      load[elem_part[e]] += static_cast<double>(whole_cost[e]);
      moved += elem_part[e] != owner[e] ? 1 : 0;
    }
    const double predicted = *std::max_element(load.begin(), load.end()) / mean;
    char line[256];
    std::snprintf(line, sizeof line,
                  "step %lld: parts max/mean %.3g > %g, repartitioned (predicted %.3g, %ld "
                  "elements moved)\n",
                  static_cast<long long>(step), work[0] / mean, spec_->rebalance, predicted, moved);
    print(prefix() + line);
  }
  scatter_whole(whole, elem_part);
}

} // namespace fracdem
