// The .pvtu index of a frame written in pieces: ParaView's reader (VTK) joins the parts of a
// partitioned body back into the whole body's cells and fields.
#include <gtest/gtest.h>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPUnstructuredGridReader.h>

#include "body/body_partition.h"
#include "io/mesh_generators.h"
#include "io/pvtu_writer.h"
#include "test_support.h"

using namespace fracdem;

class IoPvtu : public fracdem_test::TempDirTest
{
};

// Three METIS parts of a tet box, each written as a piece with a per-node field (x coordinate
// plus 1) and a per-element field (its global element number): the joined grid has every element
// once, the pieces' nodes (shared ones repeated), and the fields of the whole body.
TEST_F(IoPvtu, PiecesOfAPartitionedBodyJoinIntoTheWholeBody)
{
  const Mesh mesh = make_box_tet_mesh(4, 3, 2, 0.4, 0.3, 0.2);
  const std::vector<int> part = partition_elements(mesh, 3);
  std::vector<std::string> pieces;
  int piece_nodes = 0;
  const std::vector<VtkField> declared = {{"shifted_x", 1, nullptr, false},
                                          {"global_element", 1, nullptr, true}};
  for (int p = 0; p < 3; ++p) {
    const MeshPart mp = extract_part(mesh, part, p);
    std::vector<double> shifted, global_element;
    for (int n = 0; n < mp.num_nodes(); ++n)
      shifted.push_back(mp.mesh.X[3 * n] + 1.0);
    global_element.assign(mp.global_elem.begin(), mp.global_elem.end());
    pieces.push_back((dir_ / "frame" / ("piece_" + std::to_string(p) + ".vtu")).string());
    std::filesystem::create_directories(dir_ / "frame");
    write_vtu(pieces.back(), mp.mesh, nullptr,
              {{"shifted_x", 1, shifted.data(), false},
               {"global_element", 1, global_element.data(), true}});
    piece_nodes += mp.num_nodes();
  }
  const std::string index = (dir_ / "frame.pvtu").string();
  write_pvtu(index, pieces, declared);

  auto reader = vtkSmartPointer<vtkXMLPUnstructuredGridReader>::New();
  reader->SetFileName(index.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  ASSERT_EQ(grid->GetNumberOfCells(), mesh.num_elems());
  ASSERT_EQ(grid->GetNumberOfPoints(), piece_nodes);
  vtkDataArray* ge = grid->GetCellData()->GetArray("global_element");
  vtkDataArray* sx = grid->GetPointData()->GetArray("shifted_x");
  ASSERT_NE(ge, nullptr);
  ASSERT_NE(sx, nullptr);
  std::vector<int> seen(mesh.num_elems(), 0);
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    ++seen[static_cast<int>(ge->GetTuple1(c))];
  for (int s : seen)
    EXPECT_EQ(s, 1);
  for (vtkIdType n = 0; n < grid->GetNumberOfPoints(); ++n)
    EXPECT_DOUBLE_EQ(sx->GetTuple1(n), grid->GetPoint(n)[0] + 1.0);
}

// Erosion of a distributed body can leave a part without active elements: its piece has the
// part's nodes and no cell, and the frame still joins into the body's active elements (eroded
// ones, of that part and of another, are left out) with their fields.
TEST_F(IoPvtu, APieceWithEveryElementErodedJoinsIntoTheActiveElements)
{
  const Mesh mesh = make_box_tet_mesh(4, 3, 2, 0.4, 0.3, 0.2);
  const std::vector<int> part = partition_elements(mesh, 3);
  std::vector<std::string> pieces;
  std::vector<int> active(mesh.num_elems(), 1);
  const std::vector<VtkField> declared = {{"global_element", 1, nullptr, true},
                                          {"velocity", 3, nullptr, false}};
  for (int p = 0; p < 3; ++p) {
    MeshPart mp = extract_part(mesh, part, p);
    for (int e = 0; e < mp.mesh.num_elems(); ++e)
      if (p == 1 || (p == 2 && e % 2 == 0)) { // part 1 eroded whole, part 2 in half
        mp.mesh.active[e] = 0;
        active[mp.global_elem[e]] = 0;
      }
    const std::vector<double> global_element(mp.global_elem.begin(), mp.global_elem.end());
    const std::vector<double> velocity(3 * mp.num_nodes(), 1.5);
    pieces.push_back((dir_ / ("piece_" + std::to_string(p) + ".vtu")).string());
    write_vtu(pieces.back(), mp.mesh, nullptr,
              {{"global_element", 1, global_element.data(), true},
               {"velocity", 3, velocity.data(), false}});
  }
  const std::string index = (dir_ / "eroded.pvtu").string();
  write_pvtu(index, pieces, declared);

  auto reader = vtkSmartPointer<vtkXMLPUnstructuredGridReader>::New();
  reader->SetFileName(index.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  int want = 0;
  for (int a : active)
    want += a;
  ASSERT_GT(want, 0);
  ASSERT_LT(want, mesh.num_elems());
  ASSERT_EQ(grid->GetNumberOfCells(), want);
  vtkDataArray* ge = grid->GetCellData()->GetArray("global_element");
  vtkDataArray* v = grid->GetPointData()->GetArray("velocity");
  ASSERT_NE(ge, nullptr);
  ASSERT_NE(v, nullptr);
  std::vector<int> seen(mesh.num_elems(), 0);
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    ++seen[static_cast<int>(ge->GetTuple1(c))];
  for (int e = 0; e < mesh.num_elems(); ++e)
    EXPECT_EQ(seen[e], active[e]) << "element " << e;
  for (vtkIdType n = 0; n < grid->GetNumberOfPoints(); ++n)
    EXPECT_EQ(v->GetTuple3(n)[2], 1.5);
}

TEST_F(IoPvtu, Errors)
{
  EXPECT_THROW(write_pvtu((dir_ / "a.pvtu").string(), {}, {}), std::invalid_argument);
  EXPECT_THROW(write_pvtu((dir_ / "a.pvtu").string(), {"p.vtu"}, {{"region", 1, nullptr, true}}),
               std::invalid_argument);
  EXPECT_THROW(write_pvtu((dir_ / "missing" / "a.pvtu").string(), {"p.vtu"}, {}),
               std::runtime_error);
}
