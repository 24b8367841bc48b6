// Unit tests for the VTU writer (read back through VTK) and the PVD time-series index.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "io/mesh_generators.h"
#include "io/vtk_writer.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace fracdem;

namespace
{

vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const std::string& path)
{
  auto r = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  r->SetFileName(path.c_str());
  r->Update();
  return r->GetOutput();
}

std::string slurp(const fs::path& p)
{
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

} // namespace

class IoVtk : public fracdem_test::TempDirTest
{
};

class IoPvd : public fracdem_test::TempDirTest
{
};

TEST_F(IoVtk, TetMeshFieldsAndInactiveElementOmitted)
{
  Mesh m = make_box_tet_mesh(1, 1, 1, 1, 1, 1); // 8 nodes, 6 tets
  m.region = {1, 1, 1, 2, 2, 2};
  m.active[2] = 0;
  const int nn = m.num_nodes(), ne = m.num_elems();
  std::vector<double> x(m.X);
  for (int i = 0; i < nn; ++i)
    x[3 * i] += 0.25 * m.X[3 * i + 2]; // sheared current configuration
  std::vector<double> disp(3 * nn), damage(ne), stress(6 * ne);
  for (int k = 0; k < 3 * nn; ++k)
    disp[k] = x[k] - m.X[k];
  for (int e = 0; e < ne; ++e) {
    damage[e] = 0.1 * e;
    for (int c = 0; c < 6; ++c)
      stress[6 * e + c] = 10.0 * e + c;
  }
  const std::string path = (dir_ / "tets.vtu").string();
  write_vtu(path, m, x.data(),
            {{"displacement", 3, disp.data(), false},
             {"damage", 1, damage.data(), true},
             {"stress", 6, stress.data(), true}});
  EXPECT_FALSE(fs::exists(path + ".tmp"));

  auto g = read_vtu(path);
  ASSERT_EQ(g->GetNumberOfPoints(), nn);
  ASSERT_EQ(g->GetNumberOfCells(), ne - 1);
  for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c)
    EXPECT_EQ(g->GetCellType(c), VTK_TETRA);
  for (int i = 0; i < nn; ++i) {
    double p[3];
    g->GetPoint(i, p);
    for (int k = 0; k < 3; ++k)
      EXPECT_DOUBLE_EQ(p[k], x[3 * i + k]);
  }
  vtkDataArray* id = g->GetCellData()->GetArray("element_id");
  vtkDataArray* region = g->GetCellData()->GetArray("region");
  vtkDataArray* dmg = g->GetCellData()->GetArray("damage");
  vtkDataArray* sig = g->GetCellData()->GetArray("stress");
  vtkDataArray* u = g->GetPointData()->GetArray("displacement");
  ASSERT_TRUE(id && region && dmg && sig && u);
  EXPECT_EQ(id->GetDataType(), VTK_INT);
  EXPECT_EQ(sig->GetNumberOfComponents(), 6);
  EXPECT_EQ(u->GetNumberOfComponents(), 3);
  const std::vector<int> kept = {0, 1, 3, 4, 5};
  for (int c = 0; c < 5; ++c) {
    const int e = kept[c];
    EXPECT_EQ(id->GetComponent(c, 0), e);
    EXPECT_EQ(region->GetComponent(c, 0), m.region[e]);
    EXPECT_DOUBLE_EQ(dmg->GetComponent(c, 0), damage[e]);
    for (int k = 0; k < 6; ++k)
      EXPECT_DOUBLE_EQ(sig->GetComponent(c, k), stress[6 * e + k]);
    vtkIdType npts;
    const vtkIdType* pts;
    g->GetCellPoints(c, npts, pts);
    ASSERT_EQ(npts, 4);
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(pts[k], m.conn[e][k]);
  }
  for (int i = 0; i < nn; ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_DOUBLE_EQ(u->GetComponent(i, k), disp[3 * i + k]);
}

TEST_F(IoVtk, MixedTriQuadCellTypes)
{
  Mesh m = make_rect_mesh(2, 1, 2, 1, {0, 0}, ElemType::Quad4);
  // Replace the second quad by two triangles: a mixed mesh.
  const auto q = m.conn[1];
  m.conn[1] = {{q[0], q[1], q[2], -1}};
  m.etype[1] = ElemType::Tri3;
  m.conn.push_back({{q[0], q[2], q[3], -1}});
  m.etype.push_back(ElemType::Tri3);
  m.active.push_back(1);
  m.region.push_back(0);
  const std::string path = (dir_ / "mixed.vtu").string();
  write_vtu(path, m, nullptr, {}); // nullptr: reference configuration
  auto g = read_vtu(path);
  ASSERT_EQ(g->GetNumberOfCells(), 3);
  EXPECT_EQ(g->GetCellType(0), VTK_QUAD);
  EXPECT_EQ(g->GetCellType(1), VTK_TRIANGLE);
  EXPECT_EQ(g->GetCellType(2), VTK_TRIANGLE);
  EXPECT_EQ(g->GetNumberOfPoints(), 6);
}

TEST_F(IoVtk, AllElementsInactiveStillWritesNodes)
{
  Mesh m = make_rect_mesh(1, 1, 1, 1, {0, 0}, ElemType::Tri3);
  m.active.assign(m.num_elems(), 0);
  std::vector<double> dmg(m.num_elems(), 1.0);
  const std::string path = (dir_ / "empty.vtu").string();
  write_vtu(path, m, m.X.data(), {{"damage", 1, dmg.data(), true}});
  auto g = read_vtu(path);
  EXPECT_EQ(g->GetNumberOfPoints(), 4);
  EXPECT_EQ(g->GetNumberOfCells(), 0);
}

TEST_F(IoVtk, Errors)
{
  const Mesh m = make_rect_mesh(1, 1, 1, 1);
  const std::string bad = (dir_ / "missing_dir" / "a.vtu").string();
  try {
    write_vtu(bad, m, nullptr, {});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
  const std::string ok = (dir_ / "a.vtu").string();
  std::vector<double> v(m.num_nodes(), 0.0);
  EXPECT_THROW(write_vtu(ok, m, nullptr, {{"region", 1, v.data(), false}}), std::invalid_argument);
  EXPECT_THROW(write_vtu(ok, m, nullptr, {{"a", 1, v.data(), false}, {"a", 1, v.data(), false}}),
               std::invalid_argument);
  EXPECT_THROW(write_vtu(ok, m, nullptr, {{"a", 0, v.data(), false}}), std::invalid_argument);
  EXPECT_THROW(write_vtu(ok, m, nullptr, {{"a", 1, nullptr, false}}), std::invalid_argument);
  Mesh broken = m;
  broken.conn[0][2] = 99;
  EXPECT_THROW(write_vtu(ok, broken, nullptr, {}), std::invalid_argument);
}

TEST_F(IoPvd, SeriesListsEntriesRelativeToPvd)
{
  const fs::path dir = dir_;
  fs::create_directories(dir / "frames");
  const Mesh m = make_rect_mesh(1, 1, 1, 1);
  const std::string pvd = (dir / "run.pvd").string();
  PvdSeries series(pvd);
  EXPECT_FALSE(fs::exists(pvd));
  const std::string f0 = (dir / "frames" / "run_0.vtu").string();
  const std::string f1 = (dir / "frames" / "run_1.vtu").string();
  write_vtu(f0, m, nullptr, {});
  series.add(0.0, f0);
  // Valid after the first entry already (a killed run keeps its series).
  std::string text = slurp(pvd);
  EXPECT_NE(text.find("<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"frames/run_0.vtu\"/>"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("</VTKFile>"), std::string::npos);
  write_vtu(f1, m, nullptr, {});
  series.add(0.1, f1);
  text = slurp(pvd);
  EXPECT_NE(text.find("file=\"frames/run_0.vtu\""), std::string::npos) << text;
  EXPECT_NE(
      text.find("<DataSet timestep=\"0.1\" group=\"\" part=\"0\" file=\"frames/run_1.vtu\"/>"),
      std::string::npos)
      << text;
  EXPECT_LT(text.find("run_0.vtu"), text.find("run_1.vtu"));
  EXPECT_FALSE(fs::exists(pvd + ".tmp"));
  ASSERT_EQ(series.entries().size(), 2u);
  EXPECT_EQ(series.entries()[1].first, 0.1);
  EXPECT_EQ(series.entries()[1].second, "frames/run_1.vtu");
  // The listed names resolve from the pvd's directory.
  for (const auto& e : series.entries())
    EXPECT_TRUE(fs::exists(dir / e.second)) << e.second;
}

TEST_F(IoPvd, RelativePathsFromWorkingDirectory)
{
  const fs::path dir = dir_;
  fs::create_directories(dir / "out");
  const fs::path old = fs::current_path();
  fs::current_path(dir);
  PvdSeries series("out/s.pvd");
  series.add(2.5, "out/s_7.vtu");
  series.add(3.0, (dir / "elsewhere.vtu").string());
  fs::current_path(old);
  EXPECT_EQ(series.entries()[0].second, "s_7.vtu");
  EXPECT_EQ(series.entries()[1].second, "../elsewhere.vtu");
  EXPECT_NE(slurp(dir / "out" / "s.pvd").find("timestep=\"2.5\""), std::string::npos);
}

TEST_F(IoPvd, UnwritableThrowsWithPath)
{
  const std::string pvd = (dir_ / "no_dir" / "s.pvd").string();
  PvdSeries series(pvd);
  try {
    series.add(0.0, "x.vtu");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(pvd), std::string::npos) << e.what();
  }
}
