// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/obj.hpp"

#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "io/io_test_support.hpp"

namespace palpa {
namespace {

TEST(Obj, RoundTripIsBitExact) {
  test::ScratchDir dir;
  auto rng = test::make_rng(21);
  const SurfaceMesh m = test::random_surface(rng, 200, 300);
  write_obj(dir / "m.obj", m);
  const SurfaceMesh r = read_obj(dir / "m.obj");
  EXPECT_TRUE(test::same_bits(r.V, m.V));
  EXPECT_TRUE(test::same_ints(r.F, m.F));
  EXPECT_EQ(dir.entry_count(), 1u);
}

TEST(Obj, ReadsCornerFormsPolygonsAndNegativeIndices) {
  test::ScratchDir dir;
  const auto p = dir.write("forms.obj",
                           "# corner forms\n"
                           "mtllib x.mtl\n"
                           "v 0 0 0\nv 1 0 0\nv 1 1 0 1.0\nv 0 1 0 0.5 0.5 0.5\n"
                           "vt 0 0\nvn 0 0 1\n"
                           "usemtl skin\ns 1\n"
                           "f 1/1/1 2/1/1 3/1/1 4/1/1\n"  // quad: fan (1,2,3) (1,3,4)
                           "v 2 0 0\n"
                           "f -4//1 -1//1 -3//1\n"  // 2, 5, 3 (1-based)
                           "f 5/1 3/1 2/1  # trailing comment\n"
                           "l 1 2\n");
  const SurfaceMesh m = read_obj(p);
  ASSERT_EQ(m.V.rows(), 5);
  EXPECT_EQ(m.V(4, 0), 2.0);
  Eigen::MatrixX3i expected(4, 3);
  expected << 0, 1, 2, 0, 2, 3, 1, 4, 2, 4, 2, 1;
  EXPECT_TRUE(test::same_ints(m.F, expected));
}

TEST(Obj, GroupFilterKeepsOnlyThatGroupAndItsVertices) {
  test::ScratchDir dir;
  const auto p = dir.write("groups.obj",
                           "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\nv 6 5 5\nv 5 6 5\n"
                           "g body\nf 1 2 3\n"
                           "g helper-tights\nf 4 5 6\n"
                           "g skin body\nf 3 2 1\n"
                           "o eyes\nf 6 5 4\n");
  MeshReadOptions opt;
  opt.obj_group = "body";
  const SurfaceMesh m = read_obj(p, opt);
  ASSERT_EQ(m.V.rows(), 3);
  ASSERT_EQ(m.F.rows(), 2);  // the second face's line names body among its groups
  EXPECT_EQ(m.V(1, 0), 1.0);
  EXPECT_EQ(m.F(1, 0), 2);
  opt.obj_group = "eyes";  // an object name works too
  const SurfaceMesh e = read_obj(p, opt);
  ASSERT_EQ(e.F.rows(), 1);
  EXPECT_EQ(e.V(0, 0), 5.0);
  EXPECT_EQ(read_obj(p).F.rows(), 4);  // no filter: every face
}

TEST(Obj, UnknownGroupListsTheGroupsPresent) {
  test::ScratchDir dir;
  const auto p = dir.write("g.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\ng body\nf 1 2 3\ng hair\n");
  MeshReadOptions opt;
  opt.obj_group = "torso";
  EXPECT_TRUE(test::throws_error([&] { read_obj(p, opt); }, ErrorKind::Input,
                                 {"g.obj", "no group or object named 'torso'", "body, hair"}));
  opt.obj_group = "hair";
  EXPECT_TRUE(test::throws_error([&] { read_obj(p, opt); }, ErrorKind::Input,
                                 {"g.obj", "group 'hair' has no faces"}));
}

TEST(Obj, UnitScalesToMetres) {
  test::ScratchDir dir;
  const auto p = dir.write("mm.obj", "v 10 20 30\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  MeshReadOptions opt;
  opt.unit_to_si = 1e-3;
  const SurfaceMesh m = read_obj(p, opt);
  EXPECT_DOUBLE_EQ(m.V(0, 0), 0.01);
  EXPECT_DOUBLE_EQ(m.V(0, 2), 0.03);
  opt.unit_to_si = -1.0;
  EXPECT_TRUE(test::throws_error([&] { read_obj(p, opt); }, ErrorKind::Input,
                                 {"mm.obj", "not a positive number"}));
}

TEST(Obj, ReportsLineOfIndexZero) {
  test::ScratchDir dir;
  const auto p = dir.write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  EXPECT_TRUE(test::throws_error([&] { read_obj(p); }, ErrorKind::Input,
                                 {"zero.obj:4", "face corner 1 '0'", "vertex index 0"}));
}

TEST(Obj, ReportsLineOfOutOfRangeIndex) {
  test::ScratchDir dir;
  const auto p = dir.write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n");
  EXPECT_TRUE(test::throws_error([&] { read_obj(p); }, ErrorKind::Input,
                                 {"range.obj:5", "vertex index 9 is out of range", "3 vertices"}));
}

TEST(Obj, ReportsLineOfNegativeIndexBeforeTheFirstVertex) {
  test::ScratchDir dir;
  const auto p = dir.write("neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\nv 1 1 1\n");
  EXPECT_TRUE(test::throws_error(
      [&] { read_obj(p); }, ErrorKind::Input,
      {"neg.obj:4", "face corner 3 '-4'", "relative vertex index -4", "only 3 vertices"}));
}

TEST(Obj, ReportsNonNumericAndNonFiniteCoordinates) {
  test::ScratchDir dir;
  const auto p = dir.write("text.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_TRUE(test::throws_error([&] { read_obj(p); }, ErrorKind::Input,
                                 {"text.obj:2", "vertex 2 y", "'zero' is not a number"}));
  const auto q = dir.write("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n");
  EXPECT_TRUE(test::throws_error([&] { read_obj(q); }, ErrorKind::Input,
                                 {"nan.obj:3", "vertex 3 z", "'nan' is not a finite number"}));
  const auto r = dir.write("short.obj", "v 0 0\n");
  EXPECT_TRUE(test::throws_error([&] { read_obj(r); }, ErrorKind::Input,
                                 {"short.obj:1", "vertex 1", "2 coordinates"}));
}

TEST(Obj, FaceWithTwoCornersIsAnError) {
  test::ScratchDir dir;
  const auto p = dir.write("two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n");
  EXPECT_TRUE(test::throws_error([&] { read_obj(p); }, ErrorKind::Input,
                                 {"two.obj:3", "face with 2 corners"}));
}

TEST(Obj, MeshWithoutFacesIsAnError) {
  test::ScratchDir dir;
  const auto p = dir.write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  EXPECT_TRUE(test::throws_error([&] { read_obj(p); }, ErrorKind::Input,
                                 {"points.obj", "no faces", "a mesh needs faces"}));
}

TEST(Obj, EmptyFileIsAnError) {
  test::ScratchDir dir;
  const auto p = dir.write("empty.obj", "");
  EXPECT_TRUE(
      test::throws_error([&] { read_obj(p); }, ErrorKind::Input, {"empty.obj", "file is empty"}));
  const auto q = dir.write("blank.obj", "  \n\n");
  EXPECT_TRUE(test::throws_error([&] { read_obj(q); }, ErrorKind::Input,
                                 {"blank.obj", "only white space"}));
}

}  // namespace
}  // namespace palpa
