// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/stl.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>

#include "common/test_support.hpp"
#include "io/io_test_support.hpp"

namespace palpa {
namespace {

// Corner positions of every face, row f = (x0 y0 z0 x1 ... z2): independent of
// how the vertices are numbered.
Eigen::MatrixXd face_corners(const SurfaceMesh& m) {
  Eigen::MatrixXd c(m.F.rows(), 9);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) c.block(f, 3 * k, 1, 3) = m.V.row(m.F(f, k));
  }
  return c;
}

TEST(Stl, BinaryRoundTripIsExactForFloatValuesAndWelds) {
  test::ScratchDir dir;
  SurfaceMesh cube = test::unit_cube_surface();
  cube.V *= 0.03125;  // exactly representable as float
  cube.V.col(0).array() -= 0.5;
  write_stl(dir / "cube.stl", cube);
  EXPECT_EQ(std::filesystem::file_size(dir / "cube.stl"), 84u + 50u * 12u);
  const SurfaceMesh r = read_stl(dir / "cube.stl");
  EXPECT_EQ(r.V.rows(), 8);  // 36 corners welded back into 8 vertices
  EXPECT_TRUE(test::same_bits(face_corners(r), face_corners(cube)));
}

TEST(Stl, BinaryRoundTripRoundsToFloat) {
  test::ScratchDir dir;
  auto rng = test::make_rng(41);
  const SurfaceMesh m = test::random_surface(rng, 100, 150);
  write_stl(dir / "r.stl", m);
  const SurfaceMesh r = read_stl(dir / "r.stl");
  const Eigen::MatrixXd a = face_corners(m);
  const Eigen::MatrixXd b = face_corners(r);
  ASSERT_EQ(a.rows(), b.rows());
  // float32 rounding: relative error at most 2^-24.
  const double rel = ((a - b).array().abs() / a.array().abs().max(1e-300)).maxCoeff();
  EXPECT_LE(rel, std::ldexp(1.0, -24));
  EXPECT_GT(rel, 0.0);  // the doubles did not survive unrounded: it is float32
  // Welding keeps exactly the vertices the faces use.
  std::vector<bool> used(100, false);
  for (Eigen::Index i = 0; i < m.F.size(); ++i)
    used[static_cast<std::size_t>(m.F.data()[i])] = true;
  EXPECT_EQ(r.V.rows(), std::count(used.begin(), used.end(), true));
}

TEST(Stl, BinaryWhoseHeaderStartsWithSolidIsReadAsBinary) {
  test::ScratchDir dir;
  write_stl(dir / "s.stl", test::unit_cube_surface());
  std::string bytes = test::read_bytes(dir / "s.stl");
  const std::string header = "solid cube exported by a CAD program";
  bytes.replace(0, header.size(), header);
  test::write_bytes(dir / "s.stl", bytes);
  const SurfaceMesh r = read_stl(dir / "s.stl");
  EXPECT_EQ(r.F.rows(), 12);
  EXPECT_EQ(r.V.rows(), 8);
}

TEST(Stl, ReadsAsciiAndWeldsSharedCorners) {
  test::ScratchDir dir;
  const auto p = dir.write("a.stl",
                           "solid square\n"
                           "  facet normal 0 0 1\n    outer loop\n"
                           "      vertex 0 0 0\n      vertex 1 0 0\n      vertex 1 1 0\n"
                           "    endloop\n  endfacet\n"
                           "  facet normal 0 0 1\n    outer loop\n"
                           "      vertex 0 0 0\n      vertex 1 1 0\n      vertex 0 1.5e-1 0\n"
                           "    endloop\n  endfacet\n"
                           "endsolid square\n");
  const SurfaceMesh m = read_stl(p);
  ASSERT_EQ(m.V.rows(), 4);
  Eigen::MatrixX3i expected(2, 3);
  expected << 0, 1, 2, 0, 2, 3;
  EXPECT_TRUE(test::same_ints(m.F, expected));
  EXPECT_EQ(m.V(3, 1), 0.15);
  MeshReadOptions mm;
  mm.unit_to_si = 1e-3;
  EXPECT_DOUBLE_EQ(read_stl(p, mm).V(2, 0), 1e-3);
}

TEST(Stl, TruncatedBinaryNamesTheTriangle) {
  test::ScratchDir dir;
  write_stl(dir / "cut.stl", test::unit_cube_surface());
  std::filesystem::resize_file(dir / "cut.stl", 84 + 50 * 7 + 10);
  EXPECT_TRUE(test::throws_error(
      [&] { read_stl(dir / "cut.stl"); }, ErrorKind::Input,
      {"cut.stl", "triangle[7]", "truncated", "promises 12 triangles", "684 bytes", "444 bytes"}));
  std::filesystem::resize_file(dir / "cut.stl", 40);
  EXPECT_TRUE(test::throws_error([&] { read_stl(dir / "cut.stl"); }, ErrorKind::Input,
                                 {"cut.stl", "truncated", "84-byte"}));
}

TEST(Stl, NonFiniteBinaryCoordinateNamesTheTriangle) {
  test::ScratchDir dir;
  write_stl(dir / "nan.stl", test::unit_cube_surface());
  std::string bytes = test::read_bytes(dir / "nan.stl");
  const std::size_t at = 84 + 50 * 3 + 12 + 4 * 4;  // triangle 3, corner 2, y
  bytes[at] = '\0';
  bytes[at + 1] = '\0';
  bytes[at + 2] = static_cast<char>(0xC0);
  bytes[at + 3] = static_cast<char>(0x7F);  // quiet NaN, little endian
  test::write_bytes(dir / "nan.stl", bytes);
  EXPECT_TRUE(test::throws_error([&] { read_stl(dir / "nan.stl"); }, ErrorKind::Input,
                                 {"nan.stl", "triangle[3]", "corner 2", "nan"}));
}

TEST(Stl, AsciiErrorsNameTheLine) {
  test::ScratchDir dir;
  const auto p = dir.write("bad.stl",
                           "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                           "vertex 1 abc 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid x\n");
  EXPECT_TRUE(test::throws_error([&] { read_stl(p); }, ErrorKind::Input,
                                 {"bad.stl:5", "facet 1 vertex 2", "'abc' is not a number"}));
  const auto q = dir.write("quad.stl",
                           "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                           "vertex 1 0 0\nendloop\nendfacet\nendsolid x\n");
  EXPECT_TRUE(test::throws_error([&] { read_stl(q); }, ErrorKind::Input,
                                 {"quad.stl:6", "a facet with 2 vertices"}));
  const auto r = dir.write("open.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n");
  EXPECT_TRUE(test::throws_error([&] { read_stl(r); }, ErrorKind::Input,
                                 {"open.stl:4", "ends inside a facet"}));
}

TEST(Stl, MeshWithoutFacesIsAnError) {
  test::ScratchDir dir;
  std::string bytes(80, ' ');
  bytes.append(4, '\0');  // zero triangles
  test::write_bytes(dir / "zero.stl", bytes);
  EXPECT_TRUE(test::throws_error([&] { read_stl(dir / "zero.stl"); }, ErrorKind::Input,
                                 {"zero.stl", "no faces"}));
  const auto p = dir.write("empty_solid.stl", "solid x\nendsolid x\n");
  EXPECT_TRUE(
      test::throws_error([&] { read_stl(p); }, ErrorKind::Input, {"empty_solid.stl", "no faces"}));
  const auto e = dir.write("empty.stl", "");
  EXPECT_TRUE(test::throws_error([&] { read_stl(e); }, ErrorKind::Input, {"empty.stl", "empty"}));
}

}  // namespace
}  // namespace palpa
