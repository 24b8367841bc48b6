// Unit tests for the Gmsh reader/writer: formats 2.2 and 4.1, physical groups, 2D orientation,
// errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "io/gmsh_reader.h"
#include "io/mesh_generators.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace fracdem;
using fracdem_test::signed_area;
using fracdem_test::tet_volume;

namespace
{

// 1-based number of the first line containing `needle` (nth occurrence).
int line_of(const std::string& text, const std::string& needle, int nth = 1)
{
  std::size_t pos = std::string::npos, from = 0;
  for (int k = 0; k < nth; ++k) {
    pos = text.find(needle, from);
    if (pos == std::string::npos) return -1;
    from = pos + 1;
  }
  int line = 1;
  for (std::size_t i = 0; i < pos; ++i)
    line += text[i] == '\n';
  return line;
}

std::string replace_once(std::string text, const std::string& from, const std::string& to)
{
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

// Runs read_gmsh and returns the error message ("" if it did not throw).
std::string read_error(const std::string& path, int dim = 0)
{
  try {
    read_gmsh(path, dim);
  } catch (const MeshReadError& e) {
    return e.what();
  }
  return "";
}

// Two tets sharing face (20,30,40); node tags sparse and out of order, a
// stray node 35 used only by a point group; groups of dims 0, 2, 3 (one
// unnamed, one with a blank in its name); each tet repeated for its second
// physical group, as Gmsh 2.2 writes it.
const std::string kTwoTets22 = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
6
0 1 "corner"
0 2 "stray"
2 5 "bottom"
3 7 "left"
3 8 "right"
3 10 "all body"
$EndPhysicalNames
$Nodes
6
50 1 1 1
10 0 0 0
35 5 5 5
30 0 1 0
20 1 0 0
40 0 0 1
$EndNodes
$Elements
8
1 15 2 1 1 10
2 15 2 2 2 35
3 2 2 5 1 10 20 30
4 2 2 9 1 10 20 40
5 4 2 7 1 10 20 30 40
6 4 2 10 1 10 20 30 40
7 4 2 8 2 20 30 40 50
8 4 2 10 2 20 30 40 50
$EndElements
)";

// The same mesh in format 4.1 (entities carry the physical tags; an unknown
// section is skipped).
const std::string kTwoTets41 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
6
0 1 "corner"
0 2 "stray"
2 5 "bottom"
3 7 "left"
3 8 "right"
3 10 "all body"
$EndPhysicalNames
$Comments
anything $ here
$EndComments
$Entities
2 0 2 2
1 0 0 0 1 1
2 5 5 5 1 2
1 0 0 0 1 1 0 1 5 0
2 0 0 0 1 0 1 1 9 0
1 0 0 0 1 1 1 2 7 10 0
2 0 0 0 1 1 1 2 8 10 4 1 -2 3 4
$EndEntities
$Nodes
3 6 10 50
3 1 0 4
40
10
30
20
0 0 1
0 0 0
0 1 0
1 0 0
0 2 0 1
35
5 5 5
3 2 0 1
50
1 1 1
$EndNodes
$Elements
6 6 1 7
0 1 15 1
1 10
0 2 15 1
2 35
2 1 2 1
3 10 20 30
2 2 2 1
4 10 20 40
3 1 4 1
5 10 20 30 40
3 2 4 1
7 20 30 40 50
$EndElements
)";

// 2D: a clockwise quad and a clockwise triangle (both must be flipped), a
// counter-clockwise triangle, a boundary line and a point; no $PhysicalNames.
const std::string kMixed2D22 = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
6
1 0 0 0
2 1 0 0
3 2 0 0
4 0 1 0
5 1 1 0
6 2 1 0
$EndNodes
$Elements
5
1 1 2 11 1 1 4
2 3 2 2 1 1 4 5 2
3 2 2 2 1 2 5 3
4 2 2 2 1 3 6 5
5 15 2 12 1 6
$EndElements
)";

// The same 2D mesh in 4.1, nodes stored parametric (x y z u v).
const std::string kMixed2D41 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Entities
1 1 1 0
1 2 1 0 1 12
1 0 0 0 0 1 0 1 11 0
1 0 0 0 2 1 0 1 2 0
$EndEntities
$Nodes
1 6 1 6
2 1 1 6
1
2
3
4
5
6
0 0 0 0 0
1 0 0 0.5 0
2 0 0 1 0
0 1 0 0 1
1 1 0 0.5 1
2 1 0 1 1
$EndNodes
$Elements
4 5 1 5
1 1 1 1
1 1 4
2 1 3 1
2 1 4 5 2
2 1 2 2
3 2 5 3
4 3 6 5
0 1 15 1
5 6
$EndElements
)";

void expect_same_mesh(const Mesh& a, const Mesh& b)
{
  EXPECT_EQ(a.dim, b.dim);
  EXPECT_EQ(a.X, b.X);
  EXPECT_EQ(a.etype, b.etype);
  EXPECT_EQ(a.conn, b.conn);
  EXPECT_EQ(a.active, b.active);
  EXPECT_EQ(a.region, b.region);
  EXPECT_EQ(a.node_sets, b.node_sets);
  EXPECT_EQ(a.elem_sets, b.elem_sets);
}

} // namespace

class IoGmsh : public fracdem_test::TempDirTest
{
};

TEST_F(IoGmsh, TwoTets22)
{
  const Mesh m = read_gmsh(write_file("two.msh", kTwoTets22));
  EXPECT_EQ(m.dim, 3);
  // Body nodes by increasing tag 10,20,30,40,50; stray node 35 dropped.
  EXPECT_EQ(m.X, (std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1}));
  ASSERT_EQ(m.num_elems(), 2); // repeats for group "all body" merged
  EXPECT_EQ(m.etype, (std::vector<ElemType>{ElemType::Tet4, ElemType::Tet4}));
  EXPECT_EQ(m.conn[0], (std::array<int, 4>{{0, 1, 2, 3}}));
  EXPECT_EQ(m.conn[1], (std::array<int, 4>{{1, 2, 3, 4}}));
  EXPECT_EQ(m.active, (std::vector<std::uint8_t>{1, 1}));
  EXPECT_EQ(m.region, (std::vector<int>{7, 8}));
  EXPECT_GT(tet_volume(m, 0), 0);
  EXPECT_GT(tet_volume(m, 1), 0);

  const std::map<std::string, std::vector<int>> nodes = {{"corner", {0}},
                                                         {"stray", {}},
                                                         {"bottom", {0, 1, 2}},
                                                         {"physical_9", {0, 1, 3}},
                                                         {"left", {0, 1, 2, 3}},
                                                         {"right", {1, 2, 3, 4}},
                                                         {"all body", {0, 1, 2, 3, 4}}};
  EXPECT_EQ(m.node_sets, nodes);
  const std::map<std::string, std::vector<int>> elems = {
      {"left", {0}}, {"right", {1}}, {"all body", {0, 1}}};
  EXPECT_EQ(m.elem_sets, elems);
}

TEST_F(IoGmsh, SameMeshFrom22And41)
{
  const Mesh a = read_gmsh(write_file("a.msh", kTwoTets22));
  const Mesh b = read_gmsh(write_file("b.msh", kTwoTets41));
  expect_same_mesh(a, b);
  // Explicit dim = 3 is the same as auto.
  expect_same_mesh(a, read_gmsh(write_file("c.msh", kTwoTets41), 3));
}

TEST_F(IoGmsh, WindowsLineEndings)
{
  std::string crlf;
  for (char c : kTwoTets22)
    crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  expect_same_mesh(read_gmsh(write_file("a.msh", kTwoTets22)),
                   read_gmsh(write_file("crlf.msh", crlf)));
}

TEST_F(IoGmsh, Mixed2DOrientedCounterClockwise)
{
  const Mesh m = read_gmsh(write_file("m2.msh", kMixed2D22));
  EXPECT_EQ(m.dim, 2);
  ASSERT_EQ(m.num_nodes(), 6);
  ASSERT_EQ(m.num_elems(), 3);
  EXPECT_EQ(m.etype, (std::vector<ElemType>{ElemType::Quad4, ElemType::Tri3, ElemType::Tri3}));
  EXPECT_EQ(m.conn[0], (std::array<int, 4>{{0, 1, 4, 3}}));  // was 0 3 4 1 (clockwise)
  EXPECT_EQ(m.conn[1], (std::array<int, 4>{{1, 2, 4, -1}})); // was 1 4 2 (clockwise)
  EXPECT_EQ(m.conn[2], (std::array<int, 4>{{2, 5, 4, -1}})); // already counter-clockwise
  EXPECT_DOUBLE_EQ(signed_area(m, 0), 1.0);
  EXPECT_DOUBLE_EQ(signed_area(m, 1), 0.5);
  EXPECT_DOUBLE_EQ(signed_area(m, 2), 0.5);
  EXPECT_EQ(m.region, (std::vector<int>{2, 2, 2}));
  const std::map<std::string, std::vector<int>> nodes = {
      {"physical_11", {0, 3}}, {"physical_2", {0, 1, 2, 3, 4, 5}}, {"physical_12", {5}}};
  EXPECT_EQ(m.node_sets, nodes);
  const std::map<std::string, std::vector<int>> elems = {{"physical_2", {0, 1, 2}}};
  EXPECT_EQ(m.elem_sets, elems);
  // Same geometry from 4.1 with parametric nodes; explicit dim = 2.
  expect_same_mesh(m, read_gmsh(write_file("m2_41.msh", kMixed2D41), 2));
}

TEST_F(IoGmsh, RoundTripWriteGmsh22Box)
{
  Mesh m = make_box_tet_mesh(2, 1, 1, 2.0, 1.0, 0.7, {0.1, -0.2, 0.3});
  ASSERT_EQ(m.num_elems(), 12);
  for (int e = 0; e < 12; ++e)
    m.region[e] = e < 6 ? 1 : 2;
  m.elem_sets["left"] = {0, 1, 2, 3, 4, 5};
  m.elem_sets["right"] = {6, 7, 8, 9, 10, 11};
  m.elem_sets["mixed"] = {0, 7}; // not a region: written as repeated elements
  const std::string path = (dir_ / "box.msh").string();
  write_gmsh22(m, path);
  const Mesh r = read_gmsh(path);
  EXPECT_EQ(r.dim, 3);
  EXPECT_EQ(r.X, m.X); // %.17g round-trips doubles exactly
  EXPECT_EQ(r.etype, m.etype);
  EXPECT_EQ(r.conn, m.conn);
  EXPECT_EQ(r.region, m.region);
  EXPECT_EQ(r.elem_sets, m.elem_sets);
  for (const auto& kv : m.node_sets) {
    ASSERT_TRUE(r.node_sets.count(kv.first)) << kv.first;
    EXPECT_EQ(r.node_sets.at(kv.first), kv.second) << kv.first;
  }
  std::set<int> mixed_nodes;
  for (int e : m.elem_sets.at("mixed"))
    for (int k = 0; k < 4; ++k)
      mixed_nodes.insert(m.conn[e][k]);
  EXPECT_EQ(r.node_sets.at("mixed"), std::vector<int>(mixed_nodes.begin(), mixed_nodes.end()));
}

TEST_F(IoGmsh, RoundTripWriteGmsh22Rect)
{
  for (ElemType t : {ElemType::Tri3, ElemType::Quad4}) {
    const Mesh m = make_rect_mesh(3, 2, 1.5, 1.0, {-1.0, 2.0}, t);
    const std::string path = (dir_ / "rect.msh").string();
    write_gmsh22(m, path);
    const Mesh r = read_gmsh(path);
    EXPECT_EQ(r.dim, 2);
    EXPECT_EQ(r.X, m.X);
    EXPECT_EQ(r.conn, m.conn);
    EXPECT_EQ(r.etype, m.etype);
    EXPECT_EQ(r.node_sets, m.node_sets);
    EXPECT_TRUE(r.elem_sets.empty());
  }
}

TEST_F(IoGmsh, WriteToMissingDirectoryThrowsWithPath)
{
  const std::string path = (dir_ / "no_such_dir" / "x.msh").string();
  try {
    write_gmsh22(make_rect_mesh(1, 1, 1, 1), path);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

// ---- errors ---------------------------------------------------------------

TEST_F(IoGmsh, ErrorWrongNodeCount22)
{
  const std::string text = replace_once(kTwoTets22, "7 4 2 8 2 20 30 40 50", "7 4 2 8 2 20 30 40");
  const std::string path = write_file("bad.msh", text);
  EXPECT_EQ(read_error(path), path + ":" + std::to_string(line_of(text, "7 4 2 8 2 20 30 40")) +
                                  ": expected 4 node tags for element type 4 (tet4), got 3");
}

TEST_F(IoGmsh, ErrorWrongNodeCount41)
{
  const std::string text = replace_once(kTwoTets41, "3 10 20 30\n", "3 10 20 30 40\n");
  const std::string path = write_file("bad.msh", text);
  EXPECT_EQ(read_error(path), path + ":" + std::to_string(line_of(text, "3 10 20 30 40")) +
                                  ": expected 3 node tags for element type 2 (tri3), got 4");
}

TEST_F(IoGmsh, ErrorDuplicateNodeTag)
{
  const std::string text = replace_once(kTwoTets22, "35 5 5 5", "20 5 5 5");
  const std::string path = write_file("bad.msh", text);
  const std::string msg = read_error(path);
  EXPECT_NE(
      msg.find(path + ":" + std::to_string(line_of(text, "20 1 0 0")) + ": duplicate node tag 20"),
      std::string::npos)
      << msg;
  EXPECT_NE(msg.find("first defined on line " + std::to_string(line_of(text, "20 5 5 5"))),
            std::string::npos)
      << msg;
}

TEST_F(IoGmsh, ErrorUnknownNode)
{
  for (const auto& [base, from, to] :
       {std::tuple{kTwoTets22, std::string("7 4 2 8 2 20 30 40 50"),
                   std::string("7 4 2 8 2 20 30 40 99")},
        std::tuple{kTwoTets41, std::string("7 20 30 40 50"), std::string("7 20 30 40 99")}}) {
    const std::string text = replace_once(base, from, to);
    const std::string path = write_file("bad.msh", text);
    const std::string msg = read_error(path);
    EXPECT_NE(msg.find(path + ":" + std::to_string(line_of(text, to)) +
                       ": element references unknown node tag 99"),
              std::string::npos)
        << msg;
  }
}

TEST_F(IoGmsh, ErrorTruncatedSection)
{
  const std::string text = kTwoTets22.substr(0, kTwoTets22.find("20 1 0 0"));
  const std::string path = write_file("bad.msh", text);
  const std::string msg = read_error(path);
  EXPECT_NE(msg.find(path + ":" + std::to_string(line_of(text, "30 0 1 0")) +
                     ": unexpected end of file in $Nodes: expected 6 nodes, got 4"),
            std::string::npos)
      << msg;
  // 4.1: file ends inside an element block.
  const std::string t41 = kTwoTets41.substr(0, kTwoTets41.find("7 20 30 40 50"));
  const std::string msg41 = read_error(write_file("bad41.msh", t41));
  EXPECT_NE(
      msg41.find("unexpected end of file in $Elements: expected 1 elements in this block, got 0"),
      std::string::npos)
      << msg41;
}

TEST_F(IoGmsh, ErrorMissingEnd)
{
  const std::string text = replace_once(kTwoTets22, "$EndNodes\n", "");
  const std::string path = write_file("bad.msh", text);
  EXPECT_EQ(read_error(path), path + ":" + std::to_string(line_of(text, "$Elements")) +
                                  ": expected $EndNodes, got '$Elements'");
  const std::string t2 = replace_once(kTwoTets41, "$EndElements\n", "");
  const std::string msg = read_error(write_file("bad2.msh", t2));
  EXPECT_NE(msg.find("unexpected end of file: expected $EndElements"), std::string::npos) << msg;
  const std::string t3 = replace_once(kTwoTets41, "$EndComments\n", "");
  const std::string msg3 = read_error(write_file("bad3.msh", t3));
  EXPECT_NE(msg3.find("expected $EndComments closing the section opened on line " +
                      std::to_string(line_of(t3, "$Comments"))),
            std::string::npos)
      << msg3;
}

TEST_F(IoGmsh, ErrorNonNumericField)
{
  const std::string text = replace_once(kTwoTets22, "30 0 1 0", "30 0 1x 0");
  const std::string path = write_file("bad.msh", text);
  EXPECT_EQ(read_error(path), path + ":" + std::to_string(line_of(text, "30 0 1x 0")) +
                                  ": expected a number for y, got '1x'");
  const std::string t2 = replace_once(kTwoTets22, "5 4 2 7 1 10 20 30 40", "5 4 2 7 1 10 2O 30 40");
  const std::string p2 = write_file("bad2.msh", t2);
  EXPECT_EQ(read_error(p2), p2 + ":" + std::to_string(line_of(t2, "2O")) +
                                ": expected an integer for node tag, got '2O'");
}

TEST_F(IoGmsh, ErrorUnsupportedBodyElementTypes)
{
  struct Case {
    std::string line;
    std::string expect;
  };
  for (const Case& c :
       {Case{"5 11 2 7 1 10 20 30 40 10 20 30 40 50 35",
             "element type 11 (tet10) is not supported for a 3D body; supported: 4 (tet4)"},
        Case{"5 5 2 7 1 10 20 30 40 50 35 10 20",
             "element type 5 (hex8) is not supported for a 3D body; supported: 4 (tet4)"},
        Case{"5 6 2 7 1 10 20 30 40 50 35", "element type 6 (prism6)"}}) {
    const std::string text = replace_once(kTwoTets22, "5 4 2 7 1 10 20 30 40", c.line);
    const std::string path = write_file("bad.msh", text);
    const std::string msg = read_error(path);
    EXPECT_EQ(msg.find(path + ":" + std::to_string(line_of(text, c.line)) + ": " + c.expect), 0u)
        << msg;
  }
  const std::string text = replace_once(kMixed2D22, "3 2 2 2 1 2 5 3", "3 9 2 2 1 2 5 3 1 4 6");
  const std::string msg = read_error(write_file("bad2d.msh", text));
  EXPECT_NE(
      msg.find(
          "element type 9 (tri6) is not supported for a 2D body; supported: 2 (tri3), 3 (quad4)"),
      std::string::npos)
      << msg;
  const std::string t3 =
      replace_once(kTwoTets22, "5 4 2 7 1 10 20 30 40", "5 77 2 7 1 10 20 30 40");
  const std::string msg3 = read_error(write_file("bad3.msh", t3));
  EXPECT_NE(msg3.find("unknown element type 77"), std::string::npos) << msg3;
}

TEST_F(IoGmsh, ErrorBinaryAndOtherVersions)
{
  const std::string bin = replace_once(kTwoTets41, "4.1 0 8", "4.1 1 8");
  const std::string p1 = write_file("bin.msh", bin);
  const std::string m1 = read_error(p1);
  EXPECT_EQ(m1.find(p1 + ":2: binary Gmsh files are not supported (format 4.1, binary)"), 0u) << m1;
  EXPECT_NE(m1.find("-save -format msh22"), std::string::npos) << m1;
  const std::string v4 = replace_once(kTwoTets41, "4.1 0 8", "4 0 8");
  const std::string p2 = write_file("v4.msh", v4);
  const std::string m2 = read_error(p2);
  EXPECT_EQ(m2.find(p2 + ":2: unsupported Gmsh format version 4;"), 0u) << m2;
  EXPECT_NE(m2.find("msh41"), std::string::npos) << m2;
  const std::string m3 = read_error(write_file("v1.msh", "$NOD\n1\n1 0 0 0\n$ENDNOD\n"));
  EXPECT_NE(m3.find("version 1 is not supported"), std::string::npos) << m3;
  const std::string p4 = write_file("junk.msh", "hello\n");
  EXPECT_EQ(read_error(p4), p4 + ":1: not a Gmsh mesh: expected $MeshFormat, got 'hello'");
}

TEST_F(IoGmsh, ErrorEmptyBodyAndWrongDim)
{
  const std::string path = write_file("m2.msh", kMixed2D22);
  const std::string msg = read_error(path, 3);
  EXPECT_EQ(msg, path + ": no body elements: looked for dimension 3 (tet4), found 0D (1 elements), "
                        "1D (1 elements), 2D (3 elements)");
  const std::string p2 = write_file("two.msh", kTwoTets41);
  const std::string m2 = read_error(p2, 2);
  EXPECT_NE(m2.find("dim = 2 was requested but the file has 2 elements of dimension 3"),
            std::string::npos)
      << m2;
  // Only lines and points: auto finds no body.
  const std::string lines = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
2
1 0 0 0
2 1 0 0
$EndNodes
$Elements
1
1 1 2 1 1 1 2
$EndElements
)";
  const std::string m3 = read_error(write_file("lines.msh", lines));
  EXPECT_NE(m3.find("looked for dimension 3 or 2 (auto), found 1D (1 elements)"), std::string::npos)
      << m3;
  EXPECT_NE(read_error(p2, 1).find("dim must be 0 (auto), 2 or 3"), std::string::npos);
}

TEST_F(IoGmsh, Error2DOutOfPlane)
{
  const std::string text = replace_once(kMixed2D22, "5 1 1 0", "5 1 1 0.001");
  const std::string path = write_file("bad.msh", text);
  const std::string msg = read_error(path);
  EXPECT_EQ(msg.find(path + ":" + std::to_string(line_of(text, "5 1 1 0.001")) +
                     ": node 5 has z = 0.001"),
            0u)
      << msg;
  // Round-off far below 1e-12 * size is accepted and cleaned to exactly 0.
  const std::string ok = replace_once(kMixed2D22, "5 1 1 0", "5 1 1 1e-15");
  const Mesh m = read_gmsh(write_file("ok.msh", ok));
  EXPECT_EQ(m.X[3 * 4 + 2], 0.0);
}

TEST_F(IoGmsh, ErrorMissingFileAndSections)
{
  const std::string path = (dir_ / "nope.msh").string();
  EXPECT_EQ(read_error(path), path + ": cannot open file for reading");
  const std::string no_elems = kTwoTets22.substr(0, kTwoTets22.find("$Elements"));
  const std::string p2 = write_file("noelem.msh", no_elems);
  EXPECT_EQ(read_error(p2), p2 + ": no $Elements section");
  const std::string p3 =
      write_file("part.msh", replace_once(kTwoTets41, "$Entities", "$PartitionedEntities"));
  EXPECT_NE(read_error(p3).find("partitioned Gmsh meshes are not supported"), std::string::npos);
}

// ---- damaged files (cases from tests/integration/test_fuzz_inputs.py) -----

TEST_F(IoGmsh, HugeHeaderCountIsAnErrorNotAnAllocation)
{
  // The count is not trusted for reserve(): 10^12 nodes must not end in std::bad_alloc (which
  // read_error would not catch, failing this test) but where the records run out.
  const std::string text = replace_once(kTwoTets22, "$Nodes\n6\n", "$Nodes\n1000000000000\n");
  const std::string path = write_file("bad.msh", text);
  EXPECT_EQ(read_error(path), path + ":" + std::to_string(line_of(text, "$EndNodes")) +
                                  ": expected 1000000000000 nodes in $Nodes, got 6 before "
                                  "'$EndNodes' (wrong count in the section header?)");
  const std::string t41 = replace_once(kTwoTets41, "3 6 10 50", "3 4611686018427387904 10 50");
  const std::string msg41 = read_error(write_file("bad41.msh", t41));
  EXPECT_NE(msg41.find("$Nodes header announces 4611686018427387904 nodes, blocks hold 6"),
            std::string::npos)
      << msg41;
}

TEST_F(IoGmsh, ErrorSectionEndsBeforeItsCount)
{
  const std::string text = replace_once(kTwoTets22, "$Elements\n8\n", "$Elements\n9\n");
  const std::string path = write_file("bad.msh", text);
  EXPECT_EQ(read_error(path), path + ":" + std::to_string(line_of(text, "$EndElements")) +
                                  ": expected 9 elements in $Elements, got 8 before "
                                  "'$EndElements' (wrong count in the section header?)");
  const std::string t2 = replace_once(kTwoTets22, "$PhysicalNames\n6\n", "$PhysicalNames\n7\n");
  const std::string msg2 = read_error(write_file("bad2.msh", t2));
  EXPECT_NE(msg2.find("expected 7 names in $PhysicalNames, got 6 before '$EndPhysicalNames'"),
            std::string::npos)
      << msg2;
}

TEST_F(IoGmsh, ErrorPhysicalTagOutOfRange)
{
  // A 64-bit tag was truncated to int (4294967297 -> 1, i.e. silently another group).
  const std::string text =
      replace_once(kTwoTets22, "5 4 2 7 1 10 20 30 40", "5 4 2 4294967297 1 10 20 30 40");
  const std::string path = write_file("bad.msh", text);
  EXPECT_EQ(read_error(path), path + ":" + std::to_string(line_of(text, "4294967297")) +
                                  ": physical tag 4294967297 is out of range (at most "
                                  "2147483647 in magnitude)");
  // std::abs(INT_MIN) is undefined; the tag is refused before.
  const std::string t2 = replace_once(kTwoTets22, "3 7 \"left\"", "3 -2147483648 \"left\"");
  EXPECT_NE(read_error(write_file("bad2.msh", t2)).find("physical tag -2147483648 is out of range"),
            std::string::npos);
  const std::string t3 =
      replace_once(kTwoTets41, "1 0 0 0 1 1 1 2 7 10 0", "1 0 0 0 1 1 1 2 99999999999 10 0");
  EXPECT_NE(read_error(write_file("bad3.msh", t3)).find("physical tag 99999999999 is out of range"),
            std::string::npos);
}

TEST_F(IoGmsh, ErrorBodyElementWithRepeatedNode)
{
  const std::string text =
      replace_once(kTwoTets22, "5 4 2 7 1 10 20 30 40", "5 4 2 7 1 10 20 30 20");
  const std::string path = write_file("bad.msh", text);
  EXPECT_EQ(read_error(path), path + ":" + std::to_string(line_of(text, "5 4 2 7 1 10 20 30 20")) +
                                  ": element of type 4 (tet4) lists node tag 20 more than once; "
                                  "body elements need distinct nodes");
  // 2D: a quad with a node twice would pass the FE checks as a triangle with a zero-length edge.
  const std::string t2 = replace_once(kMixed2D22, "2 3 2 2 1 1 4 5 2", "2 3 2 2 1 1 4 4 2");
  const std::string msg2 = read_error(write_file("bad2.msh", t2));
  EXPECT_NE(msg2.find("element of type 3 (quad4) lists node tag 4 more than once"),
            std::string::npos)
      << msg2;
  // Boundary elements may repeat nodes: meshgen writes single-node sets as [a, b, b] triangles.
  const std::string ok = replace_once(kTwoTets22, "3 2 2 5 1 10 20 30", "3 2 2 5 1 10 20 20");
  const Mesh m = read_gmsh(write_file("ok.msh", ok));
  EXPECT_EQ(m.node_sets.at("bottom"), (std::vector<int>{0, 1}));
}

TEST_F(IoGmsh, ErrorOverflowingElementGeometry)
{
  // Each coordinate is finite, but the tet's volume and diameter overflow to inf / NaN.
  const std::string text = replace_once(kTwoTets22, "50 1 1 1", "50 1e308 1 1");
  const std::string path = write_file("bad.msh", text);
  EXPECT_EQ(read_error(path), path + ":" + std::to_string(line_of(text, "7 4 2 8 2 20 30 40 50")) +
                                  ": element size overflows double precision (node coordinates "
                                  "up to 1e+308); rescale the mesh, e.g. to metres");
  const std::string t2 = replace_once(kMixed2D22, "3 2 0 0", "3 2e200 0 0");
  const std::string msg2 = read_error(write_file("bad2.msh", t2));
  EXPECT_NE(msg2.find("element size overflows double precision"), std::string::npos) << msg2;

  Mesh m;
  m.X = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  m.etype = {ElemType::Tet4};
  m.conn = {{0, 1, 2, 3}};
  m.active = {1};
  EXPECT_TRUE(element_geometry_finite(m, 0));
  for (double& x : m.X)
    x *= 1e160; // volume ~1e480
  EXPECT_FALSE(element_geometry_finite(m, 0));
  m.X.assign(12, 0.0);
  m.X[3] = std::nan("");
  EXPECT_FALSE(element_geometry_finite(m, 0));
}

TEST_F(IoGmsh, DamagedTextInMessagesIsShortAndEscaped)
{
  // Binary bytes (and terminal escape codes) are shown as \xNN, long text is cut at 60 characters.
  const std::string garbage = std::string("\x01\x02garb\x1b[31m") + std::string(1000, 'x');
  const std::string path = write_file("bin.msh", replace_once(kTwoTets22, "$MeshFormat", garbage));
  const std::string msg = read_error(path);
  EXPECT_EQ(msg.find(path + ":1: not a Gmsh mesh: expected $MeshFormat, got "
                            "'\\x01\\x02garb\\x1B[31mxxx"),
            0u)
      << msg;
  EXPECT_NE(msg.find("' (951 more characters)"), std::string::npos) << msg;
  EXPECT_LT(msg.size(), path.size() + 200);
  const std::string text =
      replace_once(kTwoTets22, "30 0 1 0", "30 0 " + std::string(100000, '1') + " 0");
  const std::string msg2 = read_error(write_file("long.msh", text));
  EXPECT_NE(msg2.find("expected a number for y, got '" + std::string(60, '1') +
                      "' (99940 more characters)"),
            std::string::npos)
      << msg2.substr(0, 300);
  EXPECT_LT(msg2.size(), path.size() + 200);
}

TEST_F(IoGmsh, ByteOrderMarkAndBareCarriageReturns)
{
  expect_same_mesh(read_gmsh(write_file("a.msh", kTwoTets22)),
                   read_gmsh(write_file("bom.msh", "\xEF\xBB\xBF" + kTwoTets22)));
  std::string cr = kTwoTets22;
  std::replace(cr.begin(), cr.end(), '\n', '\r');
  const std::string path = write_file("cr.msh", cr);
  EXPECT_EQ(read_error(path).find(path + ":1: lines end in a bare CR (classic Mac line endings)"),
            0u)
      << read_error(path).substr(0, 300);
}

TEST_F(IoGmsh, ErrorDirectoryAndSecondMeshFormat)
{
  EXPECT_EQ(read_error(dir_.string()), dir_.string() + ": is a directory, not a mesh file");
  const std::string text = kTwoTets22 + "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  const std::string path = write_file("two_formats.msh", text);
  EXPECT_EQ(read_error(path), path + ":" + std::to_string(line_of(text, "$MeshFormat", 2)) +
                                  ": second $MeshFormat section");
}
