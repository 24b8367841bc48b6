// Element partitions of a body: dual graph against facet counts, parts against the whole mesh,
// interface sums against a brute-force sum, and parts stepped in lockstep against the whole body.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "fem/body.h"
#include "body/body_partition.h"
#include "body/body_setup.h"
#include "body/facet_ghosts.h"
#include "io/mesh_generators.h"
#include "test_support.h"

using namespace fracdem;

namespace
{

Mesh test_mesh(ElemType type)
{
  return type == ElemType::Tet4 ? make_box_tet_mesh(6, 3, 3, 0.6, 0.3, 0.3)
                                : make_rect_mesh(12, 6, 1.2, 0.6, {0, 0}, type);
}

std::vector<MeshPart> all_parts(const Mesh& mesh, int nparts)
{
  const std::vector<int> part = partition_elements(mesh, nparts);
  std::vector<MeshPart> parts;
  for (int p = 0; p < nparts; ++p)
    parts.push_back(extract_part(mesh, part, p));
  return parts;
}

// Every part's messages to every neighbour, as the host's exchange would deliver them.
std::vector<std::vector<double>> messages_to(const std::vector<MeshPart>& parts,
                                             const std::vector<InterfaceSum>& sums,
                                             const std::vector<const double*>& fields, int width,
                                             int p)
{
  std::vector<std::vector<double>> received;
  for (const PartNeighbour& nb : parts[p].neighbours) {
    const MeshPart& q = parts[nb.part];
    int k = 0;
    while (q.neighbours[k].part != p)
      ++k;
    received.emplace_back();
    sums[nb.part].pack(k, fields[nb.part], width, received.back());
  }
  return received;
}

// A body's parts, each with its interface sum and its Body, stepped in one process: exchange()
// does in memory what the host's exchange between ranks does.
struct PartsInMemory {
  std::vector<MeshPart> parts;
  std::vector<InterfaceSum> sums;
  std::vector<Body> bodies;

  PartsInMemory(const Mesh& mesh, int nparts)
      : parts(all_parts(mesh, nparts)), sums(parts.begin(), parts.end()), bodies(nparts)
  {
  }
  int size() const { return static_cast<int>(parts.size()); }
  // Every part's field_of(p) (width values per node) summed over the sharers of each node;
  // after(p, sum) takes part p's result.
  template <class FieldOf, class After> void exchange(int width, FieldOf field_of, After after)
  {
    std::vector<std::vector<double>> fields(size());
    std::vector<const double*> ptrs;
    for (int p = 0; p < size(); ++p) {
      fields[p] = field_of(p);
      ptrs.push_back(fields[p].data());
    }
    for (int p = 0; p < size(); ++p) {
      std::vector<double> f = fields[p];
      sums[p].combine(f.data(), width, messages_to(parts, sums, ptrs, width, p));
      after(p, f);
    }
  }
  // The lumped masses summed over the parts that share a node.
  void sum_masses()
  {
    exchange(
        1, [&](int p) { return bodies[p].masses(); },
        [&](int p, const std::vector<double>& m) { bodies[p].set_masses(m); });
  }
};

} // namespace

class BodyPartition : public ::testing::TestWithParam<ElemType>
{
};

// Interior facets are shared by two elements: the dual graph has (facets - boundary facets) / 2
// edges, counted here from boundary_facets, an independent path.
TEST_P(BodyPartition, DualGraphHasAnEdgePerInteriorFacet)
{
  const Mesh mesh = test_mesh(GetParam());
  const balance::Graph g = element_dual_graph(mesh);
  const int per_elem = GetParam() == ElemType::Tri3 ? 3 : 4;
  const int64_t interior = (per_elem * mesh.num_elems() - boundary_facets(mesh).size()) / 2;
  EXPECT_EQ(g.num_edges(), interior);
  EXPECT_EQ(g.num_vertices(), mesh.num_elems());
}

// Parts cover every element once, agree with the whole mesh's connectivity, list their shared
// nodes in the same order on both sides, and carry about the same number of elements.
TEST_P(BodyPartition, PartsCoverTheMeshAndAgreeOnTheirInterfaces)
{
  const Mesh mesh = test_mesh(GetParam());
  for (int nparts : {1, 2, 3, 4}) {
    const std::vector<MeshPart> parts = all_parts(mesh, nparts);
    std::vector<int> seen(mesh.num_elems(), 0);
    for (const MeshPart& p : parts) {
      EXPECT_LE(p.global_elem.size(), 1.05 * mesh.num_elems() / nparts + 1) << nparts;
      for (size_t e = 0; e < p.global_elem.size(); ++e) {
        const int g = p.global_elem[e];
        ++seen[g];
        for (int a = 0; a < nodes_per_elem(mesh.etype[g]); ++a)
          EXPECT_EQ(p.global_node[p.mesh.conn[e][a]], mesh.conn[g][a]);
      }
      for (const PartNeighbour& nb : p.neighbours) {
        const MeshPart& q = parts[nb.part];
        const auto it = std::find_if(q.neighbours.begin(), q.neighbours.end(),
                                     [&](const PartNeighbour& x) { return x.part == p.part; });
        ASSERT_NE(it, q.neighbours.end());
        ASSERT_EQ(it->nodes.size(), nb.nodes.size());
        for (size_t i = 0; i < nb.nodes.size(); ++i)
          EXPECT_EQ(p.global_node[nb.nodes[i]], q.global_node[it->nodes[i]]);
      }
    }
    for (int s : seen)
      EXPECT_EQ(s, 1);
    // Every node is owned by exactly one part.
    std::vector<int> owners(mesh.num_nodes(), 0);
    for (const MeshPart& p : parts)
      for (int n = 0; n < p.num_nodes(); ++n)
        owners[p.global_node[n]] += p.owns(n) ? 1 : 0;
    for (int o : owners)
      EXPECT_EQ(o, 1);
  }
}

// Random contributions per part: after the exchange every sharer holds the same bits, equal to
// the brute-force sum over the node's sharers in ascending part order.
TEST_P(BodyPartition, InterfaceSumIsTheSameOnEverySharer)
{
  const Mesh mesh = test_mesh(GetParam());
  const int nparts = 4, width = 3;
  const std::vector<MeshPart> parts = all_parts(mesh, nparts);
  std::vector<InterfaceSum> sums(parts.begin(), parts.end());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<std::vector<double>> own(nparts), field(nparts);
  for (int p = 0; p < nparts; ++p) {
    own[p].resize(width * parts[p].num_nodes());
    for (double& x : own[p])
      x = u(rng);
  }
  std::vector<const double*> ptrs;
  for (auto& o : own)
    ptrs.push_back(o.data());
  std::vector<double> brute(width * mesh.num_nodes(), 0.0);
  for (int p = 0; p < nparts; ++p) // ascending part order, as the sum promises
    for (int n = 0; n < parts[p].num_nodes(); ++n)
      for (int d = 0; d < width; ++d)
        brute[width * parts[p].global_node[n] + d] += own[p][width * n + d];
  size_t sent = 0;
  for (int p = 0; p < nparts; ++p) {
    field[p] = own[p];
    const auto received = messages_to(parts, sums, ptrs, width, p);
    for (const auto& m : received)
      sent += m.size();
    sums[p].combine(field[p].data(), width, received);
    for (int n = 0; n < parts[p].num_nodes(); ++n)
      for (int d = 0; d < width; ++d)
        EXPECT_EQ(field[p][width * n + d], brute[width * parts[p].global_node[n] + d]);
  }
  // The messages carry width doubles per (shared node, neighbour) pair and nothing else.
  size_t pairs = 0;
  for (const MeshPart& p : parts)
    for (const PartNeighbour& nb : p.neighbours)
      pairs += nb.nodes.size();
  EXPECT_EQ(sent, width * pairs);
}

// Parts of a body stepped in lockstep (the exchange done in memory) follow the whole body: same
// total mass, positions within 1e-10 of the body's size after 300 steps of a shaken, clamped body,
// and bit-identical positions of a shared node on every part that holds it.
TEST_P(BodyPartition, PartsInLockstepFollowTheWholeBody)
{
  const ElemType type = GetParam();
  const Mesh mesh = test_mesh(type);
  Material steel = fracdem_test::steel();
  steel.kinematics = Kinematics::Corotational;
  auto velocity = [&](const double* X, double* v) {
    v[0] = 2.0 * X[1];
    v[1] = 3.0 * X[0] * X[0];
    v[2] = type == ElemType::Tet4 ? -2.0 * X[0] * X[1] : 0.0;
  };
  auto set_up = [&](Body& b, const Mesh& m) {
    b.build(m, steel, false);
    for (int n = 0; n < m.num_nodes(); ++n) {
      double v[3];
      velocity(&m.X[3 * n], v);
      b.set_velocity({n}, v);
    }
    b.set_fixed(m.node_sets.at("xmin"));
    b.impose_velocity_conditions();
  };
  Body whole;
  set_up(whole, mesh);
  const double dt = 0.5 * whole.stable_time_step();
  const int nparts = 3;
  PartsInMemory in_memory(mesh, nparts);
  const std::vector<MeshPart>& parts = in_memory.parts;
  std::vector<Body>& bodies = in_memory.bodies;
  for (int p = 0; p < nparts; ++p)
    set_up(bodies[p], parts[p].mesh);
  in_memory.sum_masses();
  double owned_mass = 0, whole_mass = 0;
  for (int p = 0; p < nparts; ++p)
    for (int n = 0; n < parts[p].num_nodes(); ++n)
      if (parts[p].owns(n)) owned_mass += bodies[p].masses()[n];
  for (double m : whole.masses())
    whole_mass += m;
  EXPECT_NEAR(owned_mass, whole_mass, 1e-13 * whole_mass);

  const double g[3] = {0, 0, 0};
  auto step = [&](Body& b, auto sum_forces) {
    b.half_kick_drift(dt);
    b.begin_forces();
    int inverted = -1;
    const double e = b.add_internal_forces(&inverted);
    ASSERT_LT(inverted, 0);
    sum_forces();
    b.finish_forces(e, g, dt, true);
    b.half_kick(dt);
  };
  for (int s = 0; s < 300; ++s) {
    step(whole, [] {});
    for (int p = 0; p < nparts; ++p) {
      bodies[p].half_kick_drift(dt);
      bodies[p].begin_forces();
    }
    for (int p = 0; p < nparts; ++p) {
      int inverted = -1;
      bodies[p].add_internal_forces(&inverted);
      ASSERT_LT(inverted, 0);
    }
    in_memory.exchange(
        3, [&](int p) { return bodies[p].forces(); },
        [&](int p, const std::vector<double>& f) {
          std::copy(f.begin(), f.end(), bodies[p].forces_data());
        });
    for (int p = 0; p < nparts; ++p) {
      bodies[p].finish_forces(0.0, g, dt, true);
      bodies[p].half_kick(dt);
    }
  }
  double moved = 0, worst = 0;
  std::vector<std::vector<double>> seen(mesh.num_nodes());
  for (int n = 0; n < mesh.num_nodes(); ++n)
    for (int d = 0; d < 3; ++d)
      moved = std::max(moved, std::abs(whole.positions()[3 * n + d] - mesh.X[3 * n + d]));
  ASSERT_GT(moved, 1e-6); // the body did deform
  for (int p = 0; p < nparts; ++p)
    for (int n = 0; n < parts[p].num_nodes(); ++n) {
      const int gn = parts[p].global_node[n];
      const double* x = &bodies[p].positions()[3 * n];
      for (int d = 0; d < 3; ++d)
        worst = std::max(worst, std::abs(x[d] - whole.positions()[3 * gn + d]));
      if (seen[gn].empty())
        seen[gn].assign(x, x + 3);
      else
        for (int d = 0; d < 3; ++d)
          EXPECT_EQ(x[d], seen[gn][d]) << "node " << gn << " part " << p;
    }
  EXPECT_LT(worst, 1e-10 * 1.2);
}

// erosion_mass remove on parts (the exchange done in memory, as sum_forces_and_masses does with
// the force sum): every part erodes its own elements of each batch, the mass taken off shared
// nodes and the active elements around them are summed over the sharers, and the parts then hold
// the whole body's masses and velocities (a node of the first batch, the star of a shared node,
// left without elements on every part: neither mass nor velocity), every sharer the same bits,
// and the parts' accounts (mass, momentum, kinetic energy) sum to the whole body's.
TEST_P(BodyPartition, PartsErodingWithRemovedMassFollowTheWholeBody)
{
  const Mesh mesh = test_mesh(GetParam());
  const Material steel = fracdem_test::steel();
  auto set_up = [&](Body& b, const Mesh& m) {
    b.build(m, steel, false);
    for (int n = 0; n < m.num_nodes(); ++n) {
      const double* X = &m.X[3 * n];
      const double v[3] = {2.0 * X[1], 3.0 * X[0] * X[0], -X[0] * X[1]};
      b.set_velocity({n}, v);
    }
  };
  Body whole;
  set_up(whole, mesh);
  const double m0 = whole.total_mass();
  const int nparts = 3;
  PartsInMemory in_memory(mesh, nparts);
  const std::vector<MeshPart>& parts = in_memory.parts;
  std::vector<Body>& bodies = in_memory.bodies;
  for (int p = 0; p < nparts; ++p) {
    set_up(bodies[p], parts[p].mesh);
    std::vector<std::uint8_t> owned(parts[p].num_nodes()), shared(parts[p].num_nodes());
    for (int n = 0; n < parts[p].num_nodes(); ++n) {
      owned[n] = parts[p].owns(n);
      shared[n] = parts[p].shared(n);
    }
    bodies[p].set_counted_nodes(owned);
    bodies[p].set_shared_nodes(shared);
  }
  in_memory.sum_masses();
  // Batch 1: every element around a node that three parts share (else two); batch 2: the
  // elements of the lower third in x.
  int centre = -1, most = 0;
  for (int p = 0; p < nparts; ++p)
    for (int n = 0; n < parts[p].num_nodes(); ++n) {
      const int k = parts[p].sharer_start[n + 1] - parts[p].sharer_start[n];
      if (k > most) most = k, centre = parts[p].global_node[n];
    }
  ASSERT_GE(most, 2);
  std::vector<std::vector<int>> batches(2);
  for (const int* e = whole.stars().begin(centre); e != whole.stars().end(centre); ++e)
    batches[0].push_back(*e);
  std::sort(batches[0].begin(), batches[0].end());
  for (int e = 0; e < mesh.num_elems(); ++e) {
    double cx = 0;
    const int k = nodes_per_elem(mesh.etype[e]);
    for (int a = 0; a < k; ++a)
      cx += mesh.X[3 * mesh.conn[e][a]] / k;
    if (cx < 0.2 * (GetParam() == ElemType::Tet4 ? 0.6 : 1.2) &&
        std::find(batches[0].begin(), batches[0].end(), e) == batches[0].end())
      batches[1].push_back(e);
  }
  for (const std::vector<int>& batch : batches) {
    whole.erode(batch, true);
    for (int p = 0; p < nparts; ++p) {
      std::vector<int> mine;
      for (int e = 0; e < parts[p].mesh.num_elems(); ++e)
        if (std::binary_search(batch.begin(), batch.end(), parts[p].global_elem[e]))
          mine.push_back(e);
      bodies[p].erode(mine, true);
    }
    in_memory.exchange(
        2,
        [&](int p) {
          std::vector<double> f(2 * parts[p].num_nodes());
          for (int n = 0; n < parts[p].num_nodes(); ++n)
            f[2 * n] = bodies[p].shared_taken(n), f[2 * n + 1] = bodies[p].active_elements(n);
          return f;
        },
        [&](int p, const std::vector<double>& f) {
          bodies[p].settle_shared_masses(f.data(), 2, 0);
        });
  }
  double mmax = 0;
  for (double m : whole.masses())
    mmax = std::max(mmax, m);
  std::vector<double> seen(mesh.num_nodes(), -1.0);
  int bare_shared = 0;
  double parts_mass = 0, eroded_mass = 0, energy = 0, momentum[3] = {0, 0, 0};
  for (int p = 0; p < nparts; ++p) {
    for (int n = 0; n < parts[p].num_nodes(); ++n) {
      const int g = parts[p].global_node[n];
      const double m = bodies[p].masses()[n];
      EXPECT_NEAR(m, whole.masses()[g], 1e-13 * mmax) << "node " << g << " part " << p;
      EXPECT_EQ(m == 0, whole.masses()[g] == 0) << "node " << g << " part " << p;
      for (int d = 0; d < 3; ++d)
        EXPECT_EQ(bodies[p].velocities()[3 * n + d], whole.velocities()[3 * g + d]);
      if (seen[g] >= 0) EXPECT_EQ(m, seen[g]) << "node " << g << " sharers differ";
      seen[g] = m;
      if (parts[p].shared(n) && parts[p].owns(n) && m == 0) ++bare_shared;
    }
    parts_mass += bodies[p].total_mass();
    eroded_mass += bodies[p].eroded().mass;
    energy += bodies[p].eroded().energy;
    for (int d = 0; d < 3; ++d)
      momentum[d] += bodies[p].eroded().momentum[d];
  }
  EXPECT_GE(bare_shared, 1); // the centre node, at least
  EXPECT_GT(whole.eroded().mass, 0.0);
  EXPECT_NEAR(eroded_mass, whole.eroded().mass, 1e-13 * m0);
  EXPECT_NEAR(energy, whole.eroded().energy, 1e-13 * whole.eroded().energy);
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(momentum[d], whole.eroded().momentum[d], 1e-13 * m0 * 3.0);
  EXPECT_NEAR(parts_mass + eroded_mass, m0, 1e-14 * m0);
  EXPECT_NEAR(whole.total_mass() + whole.eroded().mass, m0, 1e-14 * m0);
}

// parallel distributed set-up: rank 0 packs each rank's part and the whole surface into one
// message (part_message); what the rank unpacks is the part it would have cut itself, field for
// field (element order and numbering, sets, neighbours, sharers), and the same surface.
TEST_P(BodyPartition, PartMessagesCarryThePartAndTheSurfaceExactly)
{
  Mesh mesh = test_mesh(GetParam());
  for (int n = 0; n < mesh.num_nodes(); n += 3)
    mesh.node_sets["every third"].push_back(n);
  mesh.node_sets["none"] = {};
  for (int e = 0; e < mesh.num_elems(); e += 2)
    mesh.elem_sets["even"].push_back(e);
  for (int nparts : {1, 2, 3, 4}) {
    const std::vector<int> elem_part = partition_elements(mesh, nparts);
    const GlobalSurface surface = global_surface(mesh, elem_part);
    const std::vector<double> packed = pack_surface(surface);
    for (int p = 0; p < nparts; ++p) {
      const MeshPart want = extract_part(mesh, elem_part, p);
      const std::vector<double> message = part_message(mesh, elem_part, packed, p);
      EXPECT_EQ(message[0], mesh.num_nodes());
      EXPECT_EQ(message[1], mesh.num_elems());
      std::size_t at = 2;
      const MeshPart got = unpack_part(message, at);
      EXPECT_EQ(got.part, want.part);
      EXPECT_EQ(got.nparts, want.nparts);
      EXPECT_EQ(got.mesh.dim, want.mesh.dim);
      EXPECT_EQ(got.mesh.X, want.mesh.X); // bit for bit
      EXPECT_EQ(got.mesh.etype, want.mesh.etype);
      EXPECT_EQ(got.mesh.conn, want.mesh.conn);
      EXPECT_EQ(got.mesh.active, want.mesh.active);
      EXPECT_EQ(got.mesh.region, want.mesh.region);
      EXPECT_EQ(got.mesh.node_sets, want.mesh.node_sets);
      EXPECT_EQ(got.mesh.elem_sets, want.mesh.elem_sets);
      EXPECT_EQ(got.global_node, want.global_node);
      EXPECT_EQ(got.global_elem, want.global_elem);
      ASSERT_EQ(got.neighbours.size(), want.neighbours.size());
      for (size_t k = 0; k < want.neighbours.size(); ++k) {
        EXPECT_EQ(got.neighbours[k].part, want.neighbours[k].part);
        EXPECT_EQ(got.neighbours[k].nodes, want.neighbours[k].nodes);
      }
      EXPECT_EQ(got.sharer_start, want.sharer_start);
      EXPECT_EQ(got.sharers, want.sharers);
      const GlobalSurface s = unpack_surface(message, at);
      EXPECT_EQ(at, message.size());
      ASSERT_EQ(s.facets.size(), surface.facets.size());
      for (size_t f = 0; f < s.facets.size(); ++f) {
        EXPECT_EQ(s.facets[f].n, surface.facets[f].n);
        EXPECT_EQ(s.facets[f].nn, surface.facets[f].nn);
        EXPECT_EQ(s.facets[f].elem, surface.facets[f].elem);
        EXPECT_EQ(s.facets[f].local_face, surface.facets[f].local_face);
      }
      EXPECT_EQ(s.part, surface.part);
      EXPECT_EQ(s.ref_normal, surface.ref_normal);
      EXPECT_EQ(s.piece, surface.piece);
      EXPECT_EQ(s.nodes, surface.nodes);
      EXPECT_EQ(s.X, surface.X);
      EXPECT_EQ(s.area, surface.area);
      // A message cut short is refused, not read past its end.
      std::vector<double> cut(message.begin(), message.begin() + message.size() / 2);
      at = 2;
      EXPECT_THROW(
          {
            unpack_part(cut, at);
            unpack_surface(cut, at);
          },
          std::runtime_error);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Elements, BodyPartition,
                         ::testing::Values(ElemType::Tet4, ElemType::Tri3, ElemType::Quad4),
                         [](const auto& info) {
                           return info.param == ElemType::Tet4   ? std::string("Tet4")
                                  : info.param == ElemType::Tri3 ? std::string("Tri3")
                                                                 : std::string("Quad4");
                         });
