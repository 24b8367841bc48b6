// Unit tests for the structured box/rectangle mesh generators: counts, measure, orientation,
// conformity, sets.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <stdexcept>

#include "io/mesh_generators.h"
#include "test_support.h"

using namespace fracdem;
using fracdem_test::signed_area;
using fracdem_test::tet_volume;

namespace
{

void expect_set_on_plane(const Mesh& m, const std::string& name, int axis, double value,
                         std::size_t count)
{
  ASSERT_TRUE(m.node_sets.count(name)) << name;
  const auto& s = m.node_sets.at(name);
  EXPECT_EQ(s.size(), count) << name;
  EXPECT_TRUE(std::is_sorted(s.begin(), s.end())) << name;
  for (int n : s)
    EXPECT_NEAR(m.X[3 * n + axis], value, 1e-12) << name << " node " << n;
  // ... and every node on that plane is in the set.
  std::size_t on_plane = 0;
  for (int n = 0; n < m.num_nodes(); ++n)
    on_plane += std::abs(m.X[3 * n + axis] - value) < 1e-12;
  EXPECT_EQ(on_plane, count) << name;
}

} // namespace

TEST(IoGenerators, BoxCountsVolumeAndOrientation)
{
  const int nx = 3, ny = 2, nz = 4;
  const double lx = 1.5, ly = 0.4, lz = 2.2;
  const Mesh m = make_box_tet_mesh(nx, ny, nz, lx, ly, lz, {-1.0, 2.0, 0.5});
  EXPECT_EQ(m.dim, 3);
  EXPECT_EQ(m.num_nodes(), (nx + 1) * (ny + 1) * (nz + 1));
  ASSERT_EQ(m.num_elems(), 6 * nx * ny * nz);
  EXPECT_EQ(m.etype.size(), m.conn.size());
  EXPECT_EQ(m.num_active_elems(), m.num_elems());
  EXPECT_EQ(m.region, std::vector<int>(m.num_elems(), 0));
  double total = 0;
  const double cell = lx * ly * lz / (nx * ny * nz);
  for (int e = 0; e < m.num_elems(); ++e) {
    EXPECT_EQ(m.etype[e], ElemType::Tet4);
    const double v = tet_volume(m, e);
    EXPECT_GT(v, 0) << "element " << e;
    EXPECT_NEAR(v, cell / 6, 1e-12) << "element " << e;
    total += v;
  }
  EXPECT_NEAR(total, lx * ly * lz, 1e-12);
  expect_set_on_plane(m, "xmin", 0, -1.0, (ny + 1) * (nz + 1));
  expect_set_on_plane(m, "xmax", 0, -1.0 + lx, (ny + 1) * (nz + 1));
  expect_set_on_plane(m, "ymin", 1, 2.0, (nx + 1) * (nz + 1));
  expect_set_on_plane(m, "ymax", 1, 2.0 + ly, (nx + 1) * (nz + 1));
  expect_set_on_plane(m, "zmin", 2, 0.5, (nx + 1) * (ny + 1));
  expect_set_on_plane(m, "zmax", 2, 0.5 + lz, (nx + 1) * (ny + 1));
  EXPECT_EQ(m.node_sets.size(), 6u);
  EXPECT_TRUE(m.elem_sets.empty());
}

// Neighbouring cells must be split compatibly: every interior triangle is
// shared by exactly two tets, and the boundary is 2 triangles per cell face.
TEST(IoGenerators, BoxIsConforming)
{
  const int nx = 2, ny = 3, nz = 2;
  const Mesh m = make_box_tet_mesh(nx, ny, nz, 1, 1, 1);
  std::map<std::array<int, 3>, int> faces;
  static const int f[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (const auto& c : m.conn)
    for (const auto& fl : f) {
      std::array<int, 3> t{{c[fl[0]], c[fl[1]], c[fl[2]]}};
      std::sort(t.begin(), t.end());
      ++faces[t];
    }
  int boundary = 0;
  for (const auto& kv : faces) {
    EXPECT_LE(kv.second, 2);
    boundary += kv.second == 1;
  }
  EXPECT_EQ(boundary, 4 * (nx * ny + ny * nz + nx * nz));
}

TEST(IoGenerators, RectQuadAndTri)
{
  const int nx = 4, ny = 3;
  const double lx = 2.0, ly = 0.9;
  for (ElemType t : {ElemType::Quad4, ElemType::Tri3}) {
    const Mesh m = make_rect_mesh(nx, ny, lx, ly, {0.5, -0.25}, t);
    EXPECT_EQ(m.dim, 2);
    EXPECT_EQ(m.num_nodes(), (nx + 1) * (ny + 1));
    const int per_cell = t == ElemType::Quad4 ? 1 : 2;
    ASSERT_EQ(m.num_elems(), per_cell * nx * ny);
    double area = 0;
    for (int e = 0; e < m.num_elems(); ++e) {
      EXPECT_EQ(m.etype[e], t);
      if (t == ElemType::Tri3) EXPECT_EQ(m.conn[e][3], -1);
      const double a = signed_area(m, e);
      EXPECT_GT(a, 0) << "element " << e;
      area += a;
    }
    EXPECT_NEAR(area, lx * ly, 1e-12);
    for (int n = 0; n < m.num_nodes(); ++n)
      EXPECT_EQ(m.X[3 * n + 2], 0.0);
    expect_set_on_plane(m, "xmin", 0, 0.5, ny + 1);
    expect_set_on_plane(m, "xmax", 0, 0.5 + lx, ny + 1);
    expect_set_on_plane(m, "ymin", 1, -0.25, nx + 1);
    expect_set_on_plane(m, "ymax", 1, -0.25 + ly, nx + 1);
    EXPECT_EQ(m.node_sets.size(), 4u);
  }
}

TEST(IoGenerators, RejectsBadArguments)
{
  EXPECT_THROW(make_box_tet_mesh(0, 1, 1, 1, 1, 1), std::invalid_argument);
  EXPECT_THROW(make_box_tet_mesh(1, 1, 1, 1, -1, 1), std::invalid_argument);
  EXPECT_THROW(make_rect_mesh(1, 0, 1, 1), std::invalid_argument);
  EXPECT_THROW(make_rect_mesh(1, 1, 1, 1, {0, 0}, ElemType::Tet4), std::invalid_argument);
}
