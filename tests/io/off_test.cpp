// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/off.hpp"

#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "io/io_test_support.hpp"

namespace palpa {
namespace {

TEST(Off, RoundTripIsBitExact) {
  test::ScratchDir dir;
  auto rng = test::make_rng(51);
  const SurfaceMesh m = test::random_surface(rng, 120, 200);
  write_off(dir / "m.off", m);
  const SurfaceMesh r = read_off(dir / "m.off");
  EXPECT_TRUE(test::same_bits(r.V, m.V));
  EXPECT_TRUE(test::same_ints(r.F, m.F));
}

TEST(Off, ReadsPolygonsCommentsColoursAndCountsOnTheHeaderLine) {
  test::ScratchDir dir;
  const auto p = dir.write("q.off",
                           "COFF 4 1 0  # counts on the header line\n"
                           "# a comment\n"
                           "0 0 0 255 0 0 255\n1 0 0 255 0 0 255\n\n1 1 0 0 0 0 255\n"
                           "0 1 0.25 0 0 0 255\n"
                           "4 0 1 2 3 0.5 0.5 0.5\n");
  const SurfaceMesh m = read_off(p);
  ASSERT_EQ(m.V.rows(), 4);
  EXPECT_EQ(m.V(3, 2), 0.25);
  Eigen::MatrixX3i expected(2, 3);
  expected << 0, 1, 2, 0, 2, 3;
  EXPECT_TRUE(test::same_ints(m.F, expected));
}

TEST(Off, ErrorsNameTheLine) {
  test::ScratchDir dir;
  const auto a = dir.write("idx.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
  EXPECT_TRUE(test::throws_error([&] { read_off(a); }, ErrorKind::Input,
                                 {"idx.off:6", "face 0", "vertex index 3 is out of range"}));
  const auto b = dir.write("short.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n");
  EXPECT_TRUE(test::throws_error([&] { read_off(b); }, ErrorKind::Input,
                                 {"short.off", "ends after 2 of 3 vertices"}));
  const auto c = dir.write("nan.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 inf 0\n3 0 1 2\n");
  EXPECT_TRUE(test::throws_error([&] { read_off(c); }, ErrorKind::Input,
                                 {"nan.off:5", "vertex 2 y", "not a finite number"}));
  const auto d = dir.write("head.off", "PLY\n");
  EXPECT_TRUE(test::throws_error([&] { read_off(d); }, ErrorKind::Input,
                                 {"head.off:1", "not an OFF file"}));
  const auto e = dir.write("none.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
  EXPECT_TRUE(test::throws_error([&] { read_off(e); }, ErrorKind::Input, {"none.off", "no faces"}));
}

}  // namespace
}  // namespace palpa
