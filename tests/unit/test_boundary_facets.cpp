// boundary_facets against a brute-force reference (every facet counted in a map): tet, tri and
// quad meshes, with eroded elements and with nodes split apart as fracture does.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>

#include "fem/body.h"
#include "fem/mesh.h"
#include "io/mesh_generators.h"
#include "test_support.h"

using namespace fracdem;

namespace
{

// Facets of active elements that no other active element has, as (element, local face), with
// each element's faces from element_facet_keys counted in a map.
std::vector<std::pair<int, int>> reference(const Mesh& mesh)
{
  std::map<std::array<int, 3>, int> count;
  std::array<int, 3> keys[4];
  for (int e = 0; e < mesh.num_elems(); ++e)
    if (mesh.active[e])
      for (int k = 0; k < element_facet_keys(mesh, e, keys); ++k)
        ++count[keys[k]];
  std::vector<std::pair<int, int>> out;
  for (int e = 0; e < mesh.num_elems(); ++e)
    if (mesh.active[e])
      for (int k = 0; k < element_facet_keys(mesh, e, keys); ++k)
        if (count[keys[k]] == 1) out.push_back({e, k});
  return out;
}

void expect_reference(const Mesh& mesh, const char* what)
{
  const std::vector<Facet> got = boundary_facets(mesh);
  const auto want = reference(mesh);
  ASSERT_EQ(got.size(), want.size()) << what;
  std::array<int, 3> keys[4];
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].elem, want[i].first) << what;
    EXPECT_EQ(got[i].local_face, want[i].second) << what;
    element_facet_keys(mesh, got[i].elem, keys);
    std::array<int, 3> nodes = got[i].n;
    std::sort(nodes.begin(), nodes.begin() + got[i].nn);
    for (int q = 0; q < got[i].nn; ++q)
      EXPECT_EQ(nodes[q], keys[got[i].local_face][q]) << what;
  }
}

using fracdem_test::steel;

} // namespace

TEST(BoundaryFacets, MatchesBruteForceWithErosionAndSplits)
{
  std::mt19937 rng(11);
  for (const Mesh& start : {make_box_tet_mesh(4, 3, 3, 0.4, 0.3, 0.3),
                            make_rect_mesh(8, 5, 0.8, 0.5, {0, 0}, ElemType::Tri3),
                            make_rect_mesh(8, 5, 0.8, 0.5, {0, 0}, ElemType::Quad4)}) {
    Mesh mesh = start;
    expect_reference(mesh, "intact");
    std::uniform_int_distribution<int> pick(0, mesh.num_elems() - 1);
    for (int i = 0; i < mesh.num_elems() / 6; ++i)
      mesh.active[pick(rng)] = 0;
    expect_reference(mesh, "eroded");
    // Split interior nodes along random planes, as fracture does (new facets inside the body).
    Body body;
    body.build(start, steel(), false);
    std::uniform_int_distribution<int> node(0, body.num_nodes() - 1);
    std::uniform_real_distribution<double> u(-1, 1);
    int splits = 0;
    for (int tries = 0; tries < 200 && splits < 12; ++tries) {
      const double n[3] = {u(rng), u(rng), start.dim == 3 ? u(rng) : 0.0};
      const SplitPlan plan = body.plan_split(node(rng), n);
      if (!plan.splittable()) continue;
      body.split_node(plan);
      ++splits;
    }
    ASSERT_GT(splits, 0);
    expect_reference(body.mesh(), "split");
  }
}
