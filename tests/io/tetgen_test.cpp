// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/tetgen.hpp"

#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "io/io_test_support.hpp"

namespace palpa {
namespace {

TEST(TetGen, RoundTripIsBitExactWithRegionsAndMarkers) {
  test::ScratchDir dir;
  auto rng = test::make_rng(61);
  const TetMesh m = test::cube_tet_mesh(rng);
  write_tetgen(dir / "cube.node", m);
  EXPECT_EQ(dir.entry_count(), 3u);  // .node .ele .face, no temporaries
  for (const char* name : {"cube.node", "cube.ele", "cube"}) {
    const TetMesh r = read_tetgen(dir / name);
    EXPECT_TRUE(test::same_bits(r.V, m.V)) << name;
    EXPECT_TRUE(test::same_ints(r.T, m.T)) << name;
    EXPECT_TRUE(test::same_ints(r.region, m.region)) << name;
    EXPECT_TRUE(test::same_ints(r.boundary, m.boundary)) << name;
    EXPECT_TRUE(test::same_ints(r.boundary_marker, m.boundary_marker)) << name;
  }
  const std::string ele = test::read_bytes(dir / "cube.ele");
  EXPECT_NE(ele.find("\n6 4 1\n1 1 2 4 8 1\n"), std::string::npos) << ele;  // 1-based, region
}

TEST(TetGen, WithoutRegionsOrBoundaryStaysWithout) {
  test::ScratchDir dir;
  auto rng = test::make_rng(62);
  TetMesh m = test::cube_tet_mesh(rng);
  m.region.resize(0);
  m.boundary.resize(0, 3);
  m.boundary_marker.resize(0);
  write_tetgen(dir / "bare.ele", m);
  const TetMesh r = read_tetgen(dir / "bare.node");
  EXPECT_EQ(r.region.size(), 0);
  EXPECT_EQ(r.boundary.rows(), 0);
  EXPECT_TRUE(test::same_ints(r.T, m.T));
}

TEST(TetGen, ReadsZeroBasedFilesWithAttributesMarkersAndComments) {
  test::ScratchDir dir;
  dir.write("z.node",
            "# nodes\n5 3 1 1\n0 0 0 0 7.5 1\n1 1 0 0 7.5 1\n2 0 1 0 7.5 0\n"
            "3 0 0 1 7.5 2   # marker 2\n4 1 1 1 0 0\n");
  dir.write("z.ele", "2 4 2\n0 0 1 2 3 3.0 9\n1 1 2 3 4 -2 9\n");
  dir.write("z.face", "1 1\n0 0 2 1 4\n");
  const TetMesh m = read_tetgen(dir / "z.ele");
  ASSERT_EQ(m.V.rows(), 5);
  EXPECT_EQ(m.V(3, 2), 1.0);
  Eigen::MatrixX4i t(2, 4);
  t << 0, 1, 2, 3, 1, 2, 3, 4;
  EXPECT_TRUE(test::same_ints(m.T, t));
  ASSERT_EQ(m.region.size(), 2);
  EXPECT_EQ(m.region[0], 3);
  EXPECT_EQ(m.region[1], -2);
  ASSERT_EQ(m.boundary.rows(), 1);
  EXPECT_EQ(m.boundary(0, 1), 2);
  EXPECT_EQ(m.boundary_marker[0], 4);
}

TEST(TetGen, ErrorsNameTheFileAndLine) {
  test::ScratchDir dir;
  dir.write("q.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
  dir.write("q.ele", "1 10 0\n1 1 2 3 4 1 1 1 1 1 1\n");
  EXPECT_TRUE(test::throws_error([&] { read_tetgen(dir / "q.node"); }, ErrorKind::Input,
                                 {"q.ele:1", "10 nodes per tetrahedron", "quadratic"}));
  dir.write("q.ele", "1 4 0\n1 1 2 3 5\n");
  EXPECT_TRUE(test::throws_error([&] { read_tetgen(dir / "q.node"); }, ErrorKind::Input,
                                 {"q.ele:2", "tetrahedron 1 corner 4", "point 5 does not exist"}));
  dir.write("q.ele", "1 4 1\n1 1 2 3 4 1.5\n");
  EXPECT_TRUE(test::throws_error([&] { read_tetgen(dir / "q.node"); }, ErrorKind::Input,
                                 {"q.ele:2", "region attribute 1.5 is not an integer"}));
  dir.write("q.ele", "0 4 0\n");
  EXPECT_TRUE(test::throws_error([&] { read_tetgen(dir / "q.node"); }, ErrorKind::Input,
                                 {"q.ele", "no tetrahedra"}));
  dir.write("q.ele", "2 4 0\n1 1 2 3 4\n");
  EXPECT_TRUE(test::throws_error([&] { read_tetgen(dir / "q.node"); }, ErrorKind::Input,
                                 {"q.ele", "ends after 1 of 2 tetrahedra"}));
  dir.write("g.node", "3 3 0 0\n1 0 0 0\n3 1 0 0\n4 0 1 0\n");
  EXPECT_TRUE(test::throws_error([&] { read_tetgen(dir / "g.node"); }, ErrorKind::Input,
                                 {"g.node:3", "point number 3 breaks the sequence"}));
  dir.write("n.node", "2 3 0 0\n1 0 0 0\n2 1 nan 0\n");
  EXPECT_TRUE(test::throws_error([&] { read_tetgen(dir / "n.node"); }, ErrorKind::Input,
                                 {"n.node:3", "point 2 y", "not a finite number"}));
  dir.write("d.node", "2 2 0 0\n1 0 0\n2 1 0\n");
  EXPECT_TRUE(test::throws_error([&] { read_tetgen(dir / "d.node"); }, ErrorKind::Input,
                                 {"d.node:1", "dimension"}));
  dir.write("alone.node", "1 3 0 0\n1 0 0 0\n");
  EXPECT_TRUE(test::throws_error([&] { read_tetgen(dir / "alone.node"); }, ErrorKind::Input,
                                 {"alone.ele", "file not found"}));
}

}  // namespace
}  // namespace palpa
