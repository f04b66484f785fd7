// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/ply.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>

#include "common/test_support.hpp"
#include "io/io_test_support.hpp"

namespace palpa {
namespace {

// Test-local packing, independent of the reader's own byte helpers.
template <class T>
void put(std::string& out, T value, bool big_endian) {
  using U = std::conditional_t<
      sizeof(T) == 1, std::uint8_t,
      std::conditional_t<sizeof(T) == 2, std::uint16_t,
                         std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
  const U bits = std::bit_cast<U>(value);
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    const std::size_t shift = 8 * (big_endian ? sizeof(T) - 1 - i : i);
    out.push_back(static_cast<char>((bits >> shift) & 0xFF));
  }
}

PlyWriteOptions with_pressure(const SurfaceMesh& m, PlyEncoding encoding) {
  PlyWriteOptions opt;
  opt.encoding = encoding;
  Eigen::VectorXd p(m.V.rows());
  for (Eigen::Index i = 0; i < p.size(); ++i) p[i] = 1000.0 / 3.0 * static_cast<double>(i) + 0.1;
  opt.vertex_scalars.push_back({"pressure", p});
  return opt;
}

void expect_round_trip(PlyEncoding encoding) {
  test::ScratchDir dir;
  auto rng = test::make_rng(31 + static_cast<int>(encoding));
  const SurfaceMesh m = test::random_surface(rng, 150, 260);
  const PlyWriteOptions opt = with_pressure(m, encoding);
  write_ply(dir / "m.ply", m, opt);
  const PlyContents r = read_ply_with_scalars(dir / "m.ply");
  EXPECT_TRUE(test::same_bits(r.mesh.V, m.V));
  EXPECT_TRUE(test::same_ints(r.mesh.F, m.F));
  ASSERT_EQ(r.vertex_scalars.size(), 1u);
  EXPECT_EQ(r.vertex_scalars[0].name, "pressure");
  EXPECT_TRUE(test::same_bits(r.vertex_scalars[0].values, opt.vertex_scalars[0].values));
  EXPECT_EQ(dir.entry_count(), 1u);
}

TEST(Ply, BinaryLittleEndianRoundTripIsBitExact) {
  expect_round_trip(PlyEncoding::BinaryLittleEndian);
}
TEST(Ply, BinaryBigEndianRoundTripIsBitExact) {
  expect_round_trip(PlyEncoding::BinaryBigEndian);
}
TEST(Ply, AsciiRoundTripIsBitExact) {
  expect_round_trip(PlyEncoding::Ascii);
}

TEST(Ply, DefaultIsBinaryLittleEndianWithDoubleCoordinates) {
  test::ScratchDir dir;
  write_ply(dir / "c.ply", test::unit_cube_surface());
  const std::string bytes = test::read_bytes(dir / "c.ply");
  EXPECT_NE(bytes.find("format binary_little_endian 1.0\n"), std::string::npos);
  EXPECT_NE(bytes.find("property double x\n"), std::string::npos);
  EXPECT_NE(bytes.find("property list uchar int vertex_indices\n"), std::string::npos);
  const std::size_t body = bytes.find("end_header\n") + 11;
  // 8 vertices × 3 doubles + 12 faces × (1 + 3×4) bytes.
  EXPECT_EQ(bytes.size() - body, 8u * 24u + 12u * 13u);
}

TEST(Ply, ReadsBigEndianMixedTypesAndSkipsUnknownElements) {
  test::ScratchDir dir;
  std::string b =
      "ply\r\nformat binary_big_endian 1.0\r\ncomment mixed types\r\n"
      "element vertex 4\r\nproperty uchar red\r\nproperty float x\r\nproperty short y\r\n"
      "property double z\r\nproperty list uchar float texture\r\n"
      "element edge 2\r\nproperty int a\r\nproperty list ushort int pair\r\n"
      "element face 2\r\nproperty list uint ushort vertex_index\r\nproperty int flags\r\n"
      "end_header\r\n";
  const float xs[4] = {0.5f, 1.25f, -2.0f, 3.0f};
  for (int i = 0; i < 4; ++i) {
    put<std::uint8_t>(b, static_cast<std::uint8_t>(200 + i), true);
    put<float>(b, xs[i], true);
    put<std::int16_t>(b, static_cast<std::int16_t>(-7 * i), true);
    put<double>(b, 0.1 * i, true);
    put<std::uint8_t>(b, static_cast<std::uint8_t>(i % 2 ? 2 : 0), true);  // list length
    for (int k = 0; k < (i % 2 ? 2 : 0); ++k) put<float>(b, 9.0f, true);
  }
  for (int e = 0; e < 2; ++e) {
    put<std::int32_t>(b, e, true);
    put<std::uint16_t>(b, 2, true);
    put<std::int32_t>(b, 0, true);
    put<std::int32_t>(b, 1, true);
  }
  // A quad (fan-triangulated) and a triangle.
  put<std::uint32_t>(b, 4, true);
  for (std::uint16_t v : {0, 1, 2, 3}) put<std::uint16_t>(b, v, true);
  put<std::int32_t>(b, -1, true);
  put<std::uint32_t>(b, 3, true);
  for (std::uint16_t v : {3, 2, 1}) put<std::uint16_t>(b, v, true);
  put<std::int32_t>(b, 5, true);
  const auto p = dir / "mixed.ply";
  test::write_bytes(p, b);

  const PlyContents r = read_ply_with_scalars(p);
  ASSERT_EQ(r.mesh.V.rows(), 4);
  EXPECT_EQ(r.mesh.V(1, 0), 1.25);
  EXPECT_EQ(r.mesh.V(3, 1), -21.0);
  EXPECT_EQ(r.mesh.V(2, 2), 0.2);
  Eigen::MatrixX3i expected(3, 3);
  expected << 0, 1, 2, 0, 2, 3, 3, 2, 1;
  EXPECT_TRUE(test::same_ints(r.mesh.F, expected));
  ASSERT_EQ(r.vertex_scalars.size(), 1u);
  EXPECT_EQ(r.vertex_scalars[0].name, "red");
  EXPECT_EQ(r.vertex_scalars[0].values[3], 203.0);
}

TEST(Ply, ReadsAsciiPolygons) {
  test::ScratchDir dir;
  const auto p = dir.write("a.ply",
                           "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n"
                           "property float y\nproperty float z\nproperty uchar alpha\n"
                           "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                           "0 0 0 1\n1 0 0 1\n1 1 0 1\n0.5 1.5 0 1\n0 1 0 1\n5 0 1 2 3 4\n");
  const SurfaceMesh m = read_ply(p);
  ASSERT_EQ(m.F.rows(), 3);
  EXPECT_EQ(m.F(2, 0), 0);
  EXPECT_EQ(m.F(2, 2), 4);
  EXPECT_EQ(m.V(3, 1), 1.5);
}

std::filesystem::path binary_cube(const test::ScratchDir& dir, const std::string& name) {
  const auto p = dir / name;
  write_ply(p, test::unit_cube_surface());
  return p;
}

TEST(Ply, TruncatedBinaryFaceBlockNamesTheFace) {
  test::ScratchDir dir;
  const auto p = binary_cube(dir, "cut.ply");
  const auto size = std::filesystem::file_size(p);
  std::filesystem::resize_file(p, size - 20);  // the last face and part of the one before
  EXPECT_TRUE(test::throws_error([&] { read_ply(p); }, ErrorKind::Input,
                                 {"cut.ply", "face[10]", "truncated", "8 vertex, 12 face"}));
}

TEST(Ply, TruncatedBinaryVertexBlockNamesTheVertex) {
  test::ScratchDir dir;
  const auto p = binary_cube(dir, "short.ply");
  const std::string bytes = test::read_bytes(p);
  const std::size_t body = bytes.find("end_header\n") + 11;
  std::filesystem::resize_file(p, body + 5 * 24 + 4);  // five vertices and a bit
  EXPECT_TRUE(test::throws_error([&] { read_ply(p); }, ErrorKind::Input,
                                 {"short.ply", "vertex[5]", "truncated"}));
}

TEST(Ply, TruncatedAsciiNamesTheLine) {
  test::ScratchDir dir;
  const auto p = dir.write("t.ply",
                           "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                           "property float y\nproperty float z\nelement face 1\n"
                           "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n");
  EXPECT_TRUE(test::throws_error([&] { read_ply(p); }, ErrorKind::Input,
                                 {"t.ply", "vertex[2]", "ends before"}));
}

TEST(Ply, IndexOutOfRangeNamesTheFace) {
  test::ScratchDir dir;
  const auto p = dir.write("idx.ply",
                           "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                           "property float y\nproperty float z\nelement face 2\n"
                           "property list uchar int vertex_indices\nend_header\n"
                           "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 3\n");
  EXPECT_TRUE(test::throws_error([&] { read_ply(p); }, ErrorKind::Input,
                                 {"idx.ply:14", "face[1]", "vertex index 3 is out of range"}));
}

TEST(Ply, NonFiniteCoordinatesAreErrors) {
  test::ScratchDir dir;
  const auto p = dir.write("nan.ply",
                           "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                           "property float y\nproperty float z\nelement face 1\n"
                           "property list uchar int vertex_indices\nend_header\n"
                           "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n");
  EXPECT_TRUE(test::throws_error([&] { read_ply(p); }, ErrorKind::Input,
                                 {"nan.ply:11", "vertex[1] y", "not a finite number"}));
  std::string b =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < 9; ++i) put<float>(b, i == 5 ? INFINITY : 1.0f, false);
  put<std::uint8_t>(b, 3, false);
  for (int v : {0, 1, 2}) put<std::int32_t>(b, v, false);
  test::write_bytes(dir / "inf.ply", b);
  EXPECT_TRUE(test::throws_error([&] { read_ply(dir / "inf.ply"); }, ErrorKind::Input,
                                 {"inf.ply", "vertex[1]", "coordinate z is inf"}));
}

TEST(Ply, MeshWithoutFacesIsAnError) {
  test::ScratchDir dir;
  const auto p = dir.write("pts.ply",
                           "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                           "property float y\nproperty float z\nend_header\n0 0 0\n");
  EXPECT_TRUE(test::throws_error([&] { read_ply(p); }, ErrorKind::Input, {"pts.ply", "no faces"}));
}

TEST(Ply, BadHeadersAreErrors) {
  test::ScratchDir dir;
  const auto a = dir.write("a.ply", "plyx\n");
  EXPECT_TRUE(test::throws_error([&] { read_ply(a); }, ErrorKind::Input, {"a.ply:1", "not a PLY"}));
  const auto b = dir.write("b.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty half x\n");
  EXPECT_TRUE(test::throws_error([&] { read_ply(b); }, ErrorKind::Input,
                                 {"b.ply:4", "unknown type 'half'"}));
  const auto c = dir.write("c.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n");
  EXPECT_TRUE(test::throws_error([&] { read_ply(c); }, ErrorKind::Input, {"c.ply", "end_header"}));
  const auto d = dir.write("d.ply",
                           "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                           "property float y\nend_header\n0 0\n");
  EXPECT_TRUE(test::throws_error([&] { read_ply(d); }, ErrorKind::Input,
                                 {"d.ply", "no scalar property 'z'"}));
  const auto e = dir.write("e.ply", "");
  EXPECT_TRUE(test::throws_error([&] { read_ply(e); }, ErrorKind::Input, {"e.ply", "empty"}));
}

TEST(Ply, WriterRejectsMismatchedScalars) {
  test::ScratchDir dir;
  PlyWriteOptions opt;
  opt.vertex_scalars.push_back({"pressure", Eigen::VectorXd::Zero(3)});
  EXPECT_TRUE(test::throws_error([&] { write_ply(dir / "x.ply", test::unit_cube_surface(), opt); },
                                 ErrorKind::Internal, {"x.ply", "pressure", "3 values for 8"}));
  EXPECT_EQ(dir.entry_count(), 0u);
}

}  // namespace
}  // namespace palpa
