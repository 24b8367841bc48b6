// Unit tests of the contact of a distributed body's pieces by neighbour messages: parts stepped
// in one process (messages routed by hand) against the whole surface's contact, node to facet and
// edge to edge; partners from the boxes; the travel check.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "body/body_partition.h"
#include "body/piece_ghosts.h"
#include "io/mesh_generators.h"
#include "test_support.h"

using namespace fracdem;

namespace
{

constexpr double kDt = 1e-4;

// Two 30 mm tet blocks in one mesh: B beside A along x, turned by 30 degrees about x (so that
// the edges of the faces in contact cross), its face on A's, moving into A at 1 m/s.
Mesh two_blocks(std::vector<double>& v)
{
  Mesh m = make_box_tet_mesh(3, 3, 3, 0.03, 0.03, 0.03);
  const Mesh b = m;
  const int na = m.num_nodes();
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  for (int i = 0; i < b.num_nodes(); ++i) {
    const double y = b.X[3 * i + 1] - 0.015, z = b.X[3 * i + 2] - 0.015;
    m.X.insert(m.X.end(), {b.X[3 * i] + 0.03, 0.015 + c * y - s * z, 0.015 + s * y + c * z});
  }
  for (int e = 0; e < b.num_elems(); ++e) {
    std::array<int, 4> conn = b.conn[e];
    for (int& n : conn)
      n = n >= 0 ? n + na : n;
    m.conn.push_back(conn);
    m.etype.push_back(b.etype[e]);
    m.active.push_back(b.active[e]);
    m.region.push_back(b.region[e]);
  }
  v.assign(m.X.size(), 0.0);
  for (int i = na; i < m.num_nodes(); ++i)
    v[3 * i] = -1.0;
  return m;
}

SurfaceContactOptions options()
{
  SurfaceContactOptions o;
  o.youngs = 30e9;
  o.friction = 0.3;
  return o;
}

// The parts of the body and their ranks' objects in one process.
struct Pieces {
  ContactSurface surface;
  std::vector<MeshPart> parts;
  std::vector<PieceGhosts> ghosts;
  std::vector<SurfaceContact> nodes;
  std::vector<EdgeContact> edges;
  std::vector<std::vector<double>> rx, rv, rf, f_part;
  std::vector<double> m;

  // elem_part: the element partition (empty: partition_elements').
  Pieces(const Mesh& mesh, int nparts, std::vector<int> elem_part = {})
      : ghosts(nparts), nodes(nparts), edges(nparts), rx(nparts, mesh.X), rv(nparts), rf(nparts),
        f_part(nparts)
  {
    surface.build(mesh, boundary_facets(mesh));
    if (elem_part.empty()) elem_part = partition_elements(mesh, nparts);
    std::vector<int> facet_part;
    for (const Facet& f : surface.facets)
      facet_part.push_back(elem_part[f.elem]);
    m.assign(mesh.num_nodes(), 1e-3);
    for (int p = 0; p < nparts; ++p) {
      parts.push_back(extract_part(mesh, elem_part, p));
      nodes[p].configure(options());
      edges[p].configure(options());
      rv[p].assign(mesh.X.size(), 0.0);
      rf[p].assign(mesh.X.size(), 0.0);
    }
    for (int p = 0; p < nparts; ++p) // after the parts: init keeps a pointer to the surface
      ghosts[p].init(surface, facet_part, parts[p]);
  }
  std::vector<double> local(const std::vector<double>& whole, int p) const
  {
    return fracdem_test::part_vectors(parts[p], whole);
  }
  // p's message to q is out[p][k] with partners(p)[k] == q; both sides list each other.
  void route(const std::vector<std::vector<std::vector<double>>>& out,
             std::vector<std::vector<std::vector<double>>>& in)
  {
    const int np = static_cast<int>(parts.size());
    for (int q = 0; q < np; ++q) {
      const std::vector<int>& from = ghosts[q].partners();
      in[q].assign(from.size(), {});
      for (size_t k = 0; k < from.size(); ++k) {
        const std::vector<int>& to = ghosts[from[k]].partners();
        auto it = std::find(to.begin(), to.end(), q);
        ASSERT_NE(it, to.end()) << from[k] << " does not list " << q;
        in[q][k] = out[from[k]][it - to.begin()];
      }
    }
  }
  // One step of every part; returns the contacts evaluated, all parts together.
  int step(const std::vector<double>& x, const std::vector<double>& v, bool boxes)
  {
    const int np = static_cast<int>(parts.size());
    std::vector<std::vector<double>> xp(np), vp(np);
    for (int p = 0; p < np; ++p)
      xp[p] = local(x, p), vp[p] = local(v, p);
    if (boxes)
      fracdem_test::exchange_boxes(ghosts, [&](int p) {
        return ghosts[p].local_box(xp[p].data(), 1e-3 + surface.max_reach);
      });
    std::vector<std::vector<std::vector<double>>> out(np), in(np), back(np), ret(np);
    for (int p = 0; p < np; ++p)
      ghosts[p].outgoing(xp[p].data(), vp[p].data(), out[p]);
    route(out, in);
    int contacts = 0;
    for (int p = 0; p < np; ++p) {
      ghosts[p].take(in[p], xp[p].data(), vp[p].data(), rx[p].data(), rv[p].data(), rf[p].data());
      const ContactBodyState st{rx[p].data(), rv[p].data(), m.data(), rf[p].data()};
      contacts += ghosts[p].evaluate(surface, nodes[p], &edges[p], st, kDt);
      f_part[p].assign(xp[p].size(), 0.0);
      ghosts[p].forces_back(rf[p].data(), f_part[p].data(), back[p]);
    }
    route(back, ret);
    for (int p = 0; p < np; ++p)
      ghosts[p].add_returned(ret[p], f_part[p].data());
    return contacts;
  }
  // The body's nodal forces: each contribution is on one part before the shared-node sum.
  std::vector<double> gathered(int nnodes) const
  {
    std::vector<double> f(3 * nnodes, 0.0);
    for (size_t p = 0; p < parts.size(); ++p)
      for (int n = 0; n < parts[p].num_nodes(); ++n)
        for (int d = 0; d < 3; ++d)
          f[3 * parts[p].global_node[n] + d] += f_part[p][3 * n + d];
    return f;
  }
};

void against_whole_surface(int nparts)
{
  std::vector<double> v;
  const Mesh mesh = two_blocks(v);
  const int nn = mesh.num_nodes();
  std::vector<double> x = mesh.X;
  Pieces pieces(mesh, nparts);
  SurfaceContact whole_nodes;
  EdgeContact whole_edges;
  whole_nodes.configure(options());
  whole_edges.configure(options());
  int node_contacts = 0, edge_contacts = 0;
  for (int step = 0; step < 5; ++step) {
    for (int k = 0; k < 3 * nn; ++k) // B moves into A
      x[k] += kDt * v[k];
    std::vector<double> f_whole(3 * nn, 0.0);
    const ContactBodyState st{x.data(), v.data(), pieces.m.data(), f_whole.data()};
    const int nc = whole_nodes.evaluate(pieces.surface, st, pieces.surface, st, true, kDt);
    const int ec = whole_edges.evaluate(pieces.surface, st, pieces.surface, st, true, kDt);
    node_contacts += nc;
    edge_contacts += ec;
    EXPECT_EQ(pieces.step(x, v, step == 0 || step == 3), nc + ec) << "step " << step;
    const std::vector<double> f = pieces.gathered(nn);
    double fmax = 0;
    for (double q : f_whole)
      fmax = std::max(fmax, std::fabs(q));
    for (int k = 0; k < 3 * nn; ++k)
      EXPECT_NEAR(f[k], f_whole[k], 1e-12 * fmax) << "node " << k / 3 << ", step " << step;
  }
  EXPECT_GT(node_contacts, 20);
  EXPECT_GT(edge_contacts, 0);
  // Each part's edge search holds its own edges against the edges it knows, not the whole
  // surface's: every candidate's first edge is the part's, and the parts' candidates together
  // are fewer than every part searching the whole surface (the build before: nparts times the
  // whole search's, each part's first edges from every part).
  size_t part_candidates = 0;
  for (int p = 0; p < nparts; ++p) {
    const std::vector<int>& mine = pieces.parts[p].global_elem; // ascending
    for (const auto& c : pieces.edges[p].candidates()) {
      const int elem = pieces.surface.facets[pieces.surface.edges[c.first].facet[0]].elem;
      EXPECT_TRUE(std::binary_search(mine.begin(), mine.end(), elem))
          << "part " << p << ": edge " << c.first << " of another part";
      ++part_candidates;
    }
  }
  EXPECT_LT(part_candidates, nparts * whole_edges.candidates().size());
  size_t partners = 0; // the parts did exchange
  for (const PieceGhosts& g : pieces.ghosts)
    partners += g.partners().size();
  EXPECT_GT(partners, 0u);
}

} // namespace

TEST(PieceGhosts, ThreePartsGiveTheWholeSurfacesSelfContact)
{
  against_whole_surface(3);
}

TEST(PieceGhosts, FivePartsGiveTheWholeSurfacesSelfContact)
{
  against_whole_surface(5);
}

TEST(PieceGhosts, PartnersFromBoxesAndTravelBeyondTheBuffer)
{
  // Two blocks 10 mm apart, one part each: partners only when the grown boxes meet.
  std::vector<double> v;
  Mesh mesh = two_blocks(v);
  const int na = mesh.num_nodes() / 2;
  for (int i = na; i < mesh.num_nodes(); ++i)
    mesh.X[3 * i] += 0.01;
  std::vector<int> blocks(mesh.num_elems(), 0);
  std::fill(blocks.begin() + mesh.num_elems() / 2, blocks.end(), 1);
  Pieces pieces(mesh, 2, blocks);
  for (double grow : {0.004, 0.006}) {
    fracdem_test::exchange_boxes(pieces.ghosts, [&](int p) {
      return pieces.ghosts[p].local_box(pieces.local(mesh.X, p).data(), grow);
    });
    for (int p = 0; p < 2; ++p)
      EXPECT_EQ(pieces.ghosts[p].partners().size(), grow > 0.005 ? 1u : 0u) << grow;
  }
  std::vector<double> x = pieces.local(mesh.X, 0);
  EXPECT_FALSE(pieces.ghosts[0].moved_beyond(x.data(), 1e-3));
  for (size_t k = 0; k < x.size(); k += 3) // block A 2 mm further along -x
    x[k] -= 2e-3;
  EXPECT_FALSE(pieces.ghosts[0].moved_beyond(x.data(), 3e-3));
  EXPECT_TRUE(pieces.ghosts[0].moved_beyond(x.data(), 1e-3));
}
