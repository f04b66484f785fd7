// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/gmsh.hpp"

#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "io/io_test_support.hpp"

namespace palpa {
namespace {

TEST(Gmsh, RoundTripIsBitExactAndKeepsTheElementOrder) {
  test::ScratchDir dir;
  auto rng = test::make_rng(71);
  const TetMesh m = test::cube_tet_mesh(rng);  // regions interleave: 1 2 1 2 1 2
  write_gmsh(dir / "cube.msh", m);
  const TetMesh r = read_gmsh(dir / "cube.msh");
  EXPECT_TRUE(test::same_bits(r.V, m.V));
  EXPECT_TRUE(test::same_ints(r.T, m.T));
  EXPECT_TRUE(test::same_ints(r.region, m.region));
  EXPECT_TRUE(test::same_ints(r.boundary, m.boundary));
  EXPECT_TRUE(test::same_ints(r.boundary_marker, m.boundary_marker));
  EXPECT_EQ(dir.entry_count(), 1u);
  const std::string text = test::read_bytes(dir / "cube.msh");
  EXPECT_EQ(text.rfind("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n", 0), 0u);
  EXPECT_NE(text.find("$Entities\n0 0 6 2\n"), std::string::npos);
}

TEST(Gmsh, MeshWithoutLabelsReadsBackWithoutLabels) {
  test::ScratchDir dir;
  auto rng = test::make_rng(72);
  TetMesh m = test::cube_tet_mesh(rng);
  m.region.resize(0);
  m.boundary_marker.resize(0);
  write_gmsh(dir / "plain.msh", m);
  const TetMesh r = read_gmsh(dir / "plain.msh");
  EXPECT_EQ(r.region.size(), 0);
  EXPECT_EQ(r.boundary_marker.size(), 0);
  EXPECT_TRUE(test::same_ints(r.boundary, m.boundary));
}

// A file as Gmsh writes it: physical names, entities with bounding entities,
// node blocks on points/curves/volume with sparse tags, parametric nodes,
// point and line elements, elements out of tag order, an unknown section.
constexpr const char* kHandWritten = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
2 5 "skin"
3 9 "fat"
$EndPhysicalNames
$Comments
anything at all
$EndComments
$Entities
1 1 1 2
1 0 0 0 0
1 0 0 0 1 0 0 0 2 1 -1
3 0 0 0 1 1 0 1 5 0
7 0 0 0 1 1 1 1 9 1 3
8 0 0 0 1 1 1 0 1 3
$EndEntities
$Nodes
3 5 10 50
0 1 0 1
10
0 0 0
1 1 1 2
20
30
1 0 0 0.5 0
0 1 0 0.75 0
3 7 0 2
40
50
0 0 1
1.5 1.5 1.5
$EndNodes
$Elements
4 5 1 9
0 1 15 1
1 10
1 1 1 1
2 10 20
2 3 2 1
9 10 20 30
3 7 4 2
5 10 20 30 40
4 20 30 40 50
$EndElements
)";

TEST(Gmsh, ReadsEntitiesSparseTagsAndSkipsOtherCells) {
  test::ScratchDir dir;
  const auto p = dir.write("hand.msh", kHandWritten);
  MeshReadOptions mm;
  mm.unit_to_si = 1e-3;
  const TetMesh m = read_gmsh(p, mm);
  ASSERT_EQ(m.V.rows(), 5);
  EXPECT_DOUBLE_EQ(m.V(4, 0), 1.5e-3);
  Eigen::MatrixX4i t(2, 4);
  t << 1, 2, 3, 4, 0, 1, 2, 3;  // sorted by element tag: 4 before 5
  EXPECT_TRUE(test::same_ints(m.T, t));
  ASSERT_EQ(m.region.size(), 2);
  EXPECT_EQ(m.region[0], 9);
  EXPECT_EQ(m.region[1], 9);
  ASSERT_EQ(m.boundary.rows(), 1);
  EXPECT_EQ(m.boundary(0, 2), 2);
  EXPECT_EQ(m.boundary_marker[0], 5);
}

TEST(Gmsh, OtherVersionsAndBinaryAreRefusedWithAHint) {
  test::ScratchDir dir;
  const auto v2 = dir.write("v2.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(v2); }, ErrorKind::Input,
                                 {"v2.msh:2", "version 2.2 is not supported", "4.1 ASCII"}));
  const auto bin = dir.write("bin.msh", "$MeshFormat\n4.1 1 8\n\x01\x00\x00\x00\n$EndMeshFormat\n");
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(bin); }, ErrorKind::Input,
                                 {"bin.msh:2", "binary .msh files are not supported", "ASCII"}));
  const auto other = dir.write("other.msh", "solid x\n");
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(other); }, ErrorKind::Input,
                                 {"other.msh:1", "not a Gmsh .msh file"}));
}

TEST(Gmsh, ErrorsNameTheLine) {
  test::ScratchDir dir;
  std::string text = kHandWritten;
  text.replace(text.find("4 20 30 40 50"), 13, "4 20 30 40 60");
  const auto a = dir.write("node.msh", text);
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(a); }, ErrorKind::Input,
                                 {"node.msh:46", "element 4", "node 60 is not in $Nodes"}));
  text = kHandWritten;
  text.replace(text.find("3 7 4 2"), 7, "3 7 11 2");
  const auto b = dir.write("order2.msh", text);
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(b); }, ErrorKind::Input,
                                 {"order2.msh:44", "element type 11 is not supported"}));
  text = kHandWritten;
  text.replace(text.find("1.5 1.5 1.5"), 11, "1.5 x 1.5");
  const auto c = dir.write("coord.msh", text);
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(c); }, ErrorKind::Input,
                                 {"coord.msh:34", "node 50 y", "'x' is not a number"}));
  text = kHandWritten;
  text.replace(text.find("$EndElements"), 12, "");
  const auto d = dir.write("open.msh", text);
  EXPECT_TRUE(
      test::throws_error([&] { read_gmsh(d); }, ErrorKind::Input, {"open.msh", "$EndElements"}));
}

TEST(Gmsh, MeshWithoutTetrahedraIsAnError) {
  test::ScratchDir dir;
  std::string text = kHandWritten;
  const std::size_t from = text.find("3 7 4 2");
  text.replace(from, text.find("$EndElements") - from, "");
  text.replace(text.find("4 5 1 9"), 7, "3 3 1 9");
  const auto p = dir.write("tris.msh", text);
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(p); }, ErrorKind::Input,
                                 {"tris.msh", "no tetrahedra (only 1 triangles)"}));
}

}  // namespace
}  // namespace palpa
