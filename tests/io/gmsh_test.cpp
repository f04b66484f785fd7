// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/gmsh.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <utility>

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

TEST(Gmsh, OtherVersionsAndFormatsAreRefusedWithAHint) {
  test::ScratchDir dir;
  const auto v40 = dir.write("v40.msh", "$MeshFormat\n4.0 0 8\n$EndMeshFormat\n");
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(v40); }, ErrorKind::Input,
                                 {"v40.msh:2", "version 4.0 is not supported", "4.1 or 2.2"}));
  const auto type = dir.write("type.msh", "$MeshFormat\n4.1 2 8\n$EndMeshFormat\n");
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(type); }, ErrorKind::Input,
                                 {"type.msh:2", "file-type 2 is neither 0 (ASCII) nor 1"}));
  const auto size4 = dir.write("size4.msh", "$MeshFormat\n4.1 1 4\n\x01\n$EndMeshFormat\n");
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(size4); }, ErrorKind::Input,
                                 {"size4.msh:2", "binary data-size 4 is not supported"}));
  const auto one = dir.write(
      "one.msh", std::string("$MeshFormat\n2.2 1 8\n\x07\0\0\0\n$End", 29) + "MeshFormat\n");
  EXPECT_TRUE(
      test::throws_error([&] { read_gmsh(one); }, ErrorKind::Input,
                         {"one.msh: $MeshFormat at byte 20", "is 7, not 1 in either byte order"}));
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
  text.replace(text.find("4 5 1 9"), 7, "4 6 1 9");
  const auto count = dir.write("count.msh", text);
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(count); }, ErrorKind::Input,
                                 {"count.msh:46", "the element blocks hold 5 elements, the $Elements header says 6"}));
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

// ---- binary 4.1 and version 2.2: the mesh of kHandWritten in each variant ----

// Bytes of a binary .msh file: values appended in the chosen byte order,
// int = 4 bytes, size_t = 8, double = 8 (IEEE 754).
class MshBytes {
 public:
  explicit MshBytes(bool big_endian) : big_(big_endian) {}
  MshBytes& text(std::string_view s) {
    out_ += s;
    return *this;
  }
  MshBytes& i32(std::int32_t v) { return put(static_cast<std::uint32_t>(v), 4); }
  MshBytes& size(std::uint64_t v) { return put(v, 8); }
  MshBytes& f64(double v) { return put(std::bit_cast<std::uint64_t>(v), 8); }
  MshBytes& xyz(double x, double y, double z) { return f64(x).f64(y).f64(z); }
  const std::string& str() const { return out_; }

 private:
  MshBytes& put(std::uint64_t bits, int n) {
    for (int i = 0; i < n; ++i) {
      const int shift = 8 * (big_ ? n - 1 - i : i);
      out_ += static_cast<char>((bits >> shift) & 0xFFu);
    }
    return *this;
  }
  bool big_;
  std::string out_;
};

// What the variants below can change, to make a broken file.
struct MshTweaks {
  bool big_endian = false;
  std::int32_t tet_type = 4;         // element type of the tet block
  std::uint64_t tets_in_block = 2;   // its element count
  std::uint64_t total_nodes = 5;     // 4.1: numNodes of the $Nodes header
  std::uint64_t element_blocks = 4;  // 4.1: numEntityBlocks of $Elements
  double node50_y = 1.5;
  std::int64_t last_node = 50;  // last node of element 4
};

constexpr const char* kNamesAndComments =
    "$PhysicalNames\n2\n2 5 \"skin\"\n3 9 \"fat\"\n$EndPhysicalNames\n"
    "$Comments\nanything at all\n$EndComments\n";

// kHandWritten as Gmsh writes it in binary 4.1 ("4.1 1 8").
std::string msh41_binary(const MshTweaks& tw = {}) {
  MshBytes b(tw.big_endian);
  b.text("$MeshFormat\n4.1 1 8\n").i32(1).text("\n$EndMeshFormat\n").text(kNamesAndComments);
  // numPoints numCurves numSurfaces numVolumes; per entity: tag, point or
  // bounding box, physical tags, bounding entities (not for points).
  b.text("$Entities\n").size(1).size(1).size(1).size(2);
  b.i32(1).xyz(0, 0, 0).size(0);
  b.i32(1).xyz(0, 0, 0).xyz(1, 0, 0).size(0).size(2).i32(1).i32(-1);
  b.i32(3).xyz(0, 0, 0).xyz(1, 1, 0).size(1).i32(5).size(0);
  b.i32(7).xyz(0, 0, 0).xyz(1, 1, 1).size(1).i32(9).size(1).i32(3);
  b.i32(8).xyz(0, 0, 0).xyz(1, 1, 1).size(0).size(1).i32(3);
  b.text("\n$EndEntities\n");
  // numEntityBlocks numNodes minNodeTag maxNodeTag; per block entityDim
  // entityTag parametric numNodesInBlock, the tags, then x y z [u].
  b.text("$Nodes\n").size(3).size(tw.total_nodes).size(10).size(50);
  b.i32(0).i32(1).i32(0).size(1).size(10).xyz(0, 0, 0);
  b.i32(1).i32(1).i32(1).size(2).size(20).size(30).xyz(1, 0, 0).f64(0.5).xyz(0, 1, 0).f64(0.75);
  b.i32(3).i32(7).i32(0).size(2).size(40).size(50).xyz(0, 0, 1).xyz(1.5, tw.node50_y, 1.5);
  b.text("\n$EndNodes\n");
  // numEntityBlocks numElements minElementTag maxElementTag; per block
  // entityDim entityTag elementType numElementsInBlock, then tag and nodes.
  b.text("$Elements\n").size(tw.element_blocks).size(5).size(1).size(9);
  b.i32(0).i32(1).i32(15).size(1).size(1).size(10);
  b.i32(1).i32(1).i32(1).size(1).size(2).size(10).size(20);
  b.i32(2).i32(3).i32(2).size(1).size(9).size(10).size(20).size(30);
  b.i32(3).i32(7).i32(tw.tet_type).size(tw.tets_in_block);
  b.size(5).size(10).size(20).size(30).size(40);
  b.size(4).size(20).size(30).size(40).size(static_cast<std::uint64_t>(tw.last_node));
  b.text("\n$EndElements\n");
  return b.str();
}

// kHandWritten in format 2.2 ASCII: the first tag of an element is its
// physical group (the point has no tags, the line a third, partition tag).
constexpr const char* kHandWritten22 = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
2
2 5 "skin"
3 9 "fat"
$EndPhysicalNames
$Nodes
5
10 0 0 0
20 1 0 0
30 0 1 0
40 0 0 1
50 1.5 1.5 1.5
$EndNodes
$Elements
5
1 15 0 10
2 1 3 0 1 1 10 20
9 2 2 5 3 10 20 30
5 4 2 9 7 10 20 30 40
4 4 2 9 7 20 30 40 50
$EndElements
)";

// The same in format 2.2 binary ("2.2 1 8"): nodes as int number and three
// doubles; elements in blocks of one type and tag count: elm-type,
// number-of-elements, number-of-tags, then per element number, tags, nodes.
std::string msh22_binary(const MshTweaks& tw = {}) {
  MshBytes b(tw.big_endian);
  b.text("$MeshFormat\n2.2 1 8\n").i32(1).text("\n$EndMeshFormat\n").text(kNamesAndComments);
  b.text("$Nodes\n5\n");
  b.i32(10).xyz(0, 0, 0).i32(20).xyz(1, 0, 0).i32(30).xyz(0, 1, 0);
  b.i32(40).xyz(0, 0, 1).i32(50).xyz(1.5, tw.node50_y, 1.5);
  b.text("\n$EndNodes\n$Elements\n5\n");
  b.i32(15).i32(1).i32(0).i32(1).i32(10);
  b.i32(1).i32(1).i32(3).i32(2).i32(0).i32(1).i32(1).i32(10).i32(20);
  b.i32(2).i32(1).i32(2).i32(9).i32(5).i32(3).i32(10).i32(20).i32(30);
  b.i32(tw.tet_type).i32(static_cast<std::int32_t>(tw.tets_in_block)).i32(2);
  b.i32(5).i32(9).i32(7).i32(10).i32(20).i32(30).i32(40);
  b.i32(4).i32(9).i32(7).i32(20).i32(30).i32(40).i32(static_cast<std::int32_t>(tw.last_node));
  b.text("\n$EndElements\n");
  return b.str();
}

::testing::AssertionResult same_msh_mesh(const TetMesh& a, const TetMesh& b) {
  for (const auto& r :
       {test::same_bits(a.V, b.V), test::same_ints(a.T, b.T), test::same_ints(a.region, b.region),
        test::same_ints(a.boundary, b.boundary),
        test::same_ints(a.boundary_marker, b.boundary_marker)}) {
    if (!r) return r;
  }
  return ::testing::AssertionSuccess();
}

TEST(Gmsh, Binary41ReadsLikeAscii41InEitherByteOrder) {
  test::ScratchDir dir;
  const TetMesh ascii = read_gmsh(dir.write("a41.msh", kHandWritten));
  ASSERT_EQ(ascii.T.rows(), 2);
  const std::string le = msh41_binary();
  // Layout check: the int 1 right after the format line, then the line end.
  EXPECT_EQ(le.substr(0, 25), std::string("$MeshFormat\n4.1 1 8\n\x01\0\0\0\n", 25));
  const TetMesh little = read_gmsh(dir.write("b41.msh", le));
  EXPECT_TRUE(same_msh_mesh(little, ascii));
  MshTweaks big;
  big.big_endian = true;
  const std::string be = msh41_binary(big);
  EXPECT_EQ(be.substr(20, 4), std::string("\0\0\0\x01", 4));
  EXPECT_TRUE(same_msh_mesh(read_gmsh(dir.write("b41be.msh", be)), ascii));
  MeshReadOptions mm;
  mm.unit_to_si = 1e-3;
  EXPECT_DOUBLE_EQ(read_gmsh(dir / "b41.msh", mm).V(4, 0), 1.5e-3);
}

TEST(Gmsh, Version22AsciiAndBinaryReadLikeAscii41) {
  test::ScratchDir dir;
  const TetMesh ascii = read_gmsh(dir.write("a41.msh", kHandWritten));
  EXPECT_TRUE(same_msh_mesh(read_gmsh(dir.write("a22.msh", kHandWritten22)), ascii));
  EXPECT_TRUE(same_msh_mesh(read_gmsh(dir.write("b22.msh", msh22_binary())), ascii));
  MshTweaks big;
  big.big_endian = true;
  EXPECT_TRUE(same_msh_mesh(read_gmsh(dir.write("b22be.msh", msh22_binary(big))), ascii));
  // Without physical tags, region and boundary_marker stay empty as for 4.1.
  std::string plain = kHandWritten22;
  for (const auto& [from, to] :
       {std::pair{"9 2 2 5 3", "9 2 2 0 3"}, std::pair{"5 4 2 9 7", "5 4 2 0 7"},
        std::pair{"4 4 2 9 7", "4 4 2 0 7"}}) {
    plain.replace(plain.find(from), 9, to);
  }
  const TetMesh p = read_gmsh(dir.write("plain22.msh", plain));
  EXPECT_EQ(p.region.size(), 0);
  EXPECT_EQ(p.boundary_marker.size(), 0);
  EXPECT_EQ(p.boundary.rows(), 1);
}

TEST(Gmsh, TruncatedBinaryFilesAreRefusedAtEveryLength) {
  test::ScratchDir dir;
  for (const auto& [name, full] :
       {std::pair{"cut41.msh", msh41_binary()}, std::pair{"cut22.msh", msh22_binary()}}) {
    // Every prefix that loses at least the last two bytes ("s\n" of
    // $EndElements) is refused with an Input error, never read past its end.
    for (std::size_t n = 1; n + 2 <= full.size(); ++n) {
      const auto p = dir.write(name, full.substr(0, n));
      ASSERT_TRUE(test::throws_error([&] { read_gmsh(p); }, ErrorKind::Input, {name}))
          << n << " of " << full.size() << " bytes";
    }
  }
  const std::string full = msh41_binary();
  // Inside a fixed-size header, and inside a node block whose count is then
  // larger than what is left.
  const std::size_t nodes = full.find("$Nodes\n") + 7;
  const auto p = dir.write("cut.msh", full.substr(0, nodes + 12));
  EXPECT_TRUE(test::throws_error(
      [&] { read_gmsh(p); }, ErrorKind::Input,
      {"cut.msh: $Nodes at byte " + std::to_string(nodes + 8), "truncated: the file ends",
       "before numNodes", "(expected 8 more bytes for numNodes)"}));
  const auto q = dir.write("cut2.msh", full.substr(0, full.find("\n$EndNodes") - 3));
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(q); }, ErrorKind::Input,
                                 {"cut2.msh: $Nodes at byte", "2 nodes of 32 bytes each do not fit",
                                  "the file is truncated or a count is wrong"}));
}

TEST(Gmsh, CountsLargerThanTheFileAreRefusedBeforeReserving) {
  test::ScratchDir dir;
  MshTweaks tw;
  tw.tets_in_block = std::uint64_t{1} << 40;
  const auto a = dir.write("elements.msh", msh41_binary(tw));
  EXPECT_TRUE(test::throws_error(
      [&] { read_gmsh(a); }, ErrorKind::Input,
      {"elements.msh: $Elements at byte", "1099511627776 elements of 40 bytes each do not fit"}));
  tw = {};
  tw.total_nodes = 1'000'000'000'000;
  const auto b = dir.write("nodes.msh", msh41_binary(tw));
  EXPECT_TRUE(test::throws_error(
      [&] { read_gmsh(b); }, ErrorKind::Input,
      {"nodes.msh: $Nodes at byte", "1000000000000 nodes of 32 bytes each do not fit", "at most"}));
  std::string text = msh22_binary();
  text.replace(text.find("$Nodes\n5\n"), 9, "$Nodes\n2000000000\n");
  const auto c = dir.write("nodes22.msh", text);
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(c); }, ErrorKind::Input,
                                 {"nodes22.msh: $Nodes at byte", "2000000000 nodes of 28 bytes"}));
  tw = {};
  tw.tets_in_block = 3;  // more than the 2 left of the header's 5
  const auto d = dir.write("block22.msh", msh22_binary(tw));
  EXPECT_TRUE(test::throws_error(
      [&] { read_gmsh(d); }, ErrorKind::Input,
      {"block22.msh: $Elements at byte", "3 elements in the block, but 2 of the header's 5"}));
  text = msh22_binary();
  text.replace(text.find("$Elements\n5\n"), 12, "$Elements\n7\n");
  const auto e = dir.write("total22.msh", text);
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(e); }, ErrorKind::Input,
                                 {"total22.msh: $Elements at byte",
                                  "header counts 7 elements, but the section ends after 5"}));
  tw = {};
  tw.element_blocks = 5;
  const auto g = dir.write("blocks.msh", msh41_binary(tw));
  EXPECT_TRUE(test::throws_error(
      [&] { read_gmsh(g); }, ErrorKind::Input,
      {"blocks.msh: $Elements at byte", "counts 5 element blocks, but the section ends after 4"}));
  text = kHandWritten22;
  text.replace(text.find("$Nodes\n5\n"), 9, "$Nodes\n2000000000\n");
  const auto f = dir.write("nodes22a.msh", text);
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(f); }, ErrorKind::Input,
                                 {"nodes22a.msh:16", "node-number x y z"}));
}

TEST(Gmsh, UnknownElementTypesAreRefusedInEveryVariant) {
  test::ScratchDir dir;
  MshTweaks tw;
  tw.tet_type = 11;  // 10-node tetrahedron
  const auto a = dir.write("order2.msh", msh41_binary(tw));
  EXPECT_TRUE(test::throws_error(
      [&] { read_gmsh(a); }, ErrorKind::Input,
      {"order2.msh: $Elements at byte", "element type 11 is not supported", "4-node tetrahedra"}));
  tw.tet_type = 99;
  const auto b = dir.write("unknown22.msh", msh22_binary(tw));
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(b); }, ErrorKind::Input,
                                 {"unknown22.msh: $Elements at byte", "element type 99"}));
  std::string text = kHandWritten22;
  text.replace(text.find("5 4 2 9 7"), 9, "5 11 2 9 7");
  const auto c = dir.write("order2a.msh", text);
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(c); }, ErrorKind::Input,
                                 {"order2a.msh:22", "element type 11 is not supported"}));
}

TEST(Gmsh, Version22WithoutEndElementsIsRefused) {
  test::ScratchDir dir;
  std::string text = kHandWritten22;
  text.replace(text.find("$EndElements"), 12, "");
  const auto a = dir.write("open22.msh", text);
  EXPECT_TRUE(
      test::throws_error([&] { read_gmsh(a); }, ErrorKind::Input,
                         {"open22.msh:", "section $Elements is not closed", "$EndElements"}));
  text = msh22_binary();
  text.replace(text.find("$EndElements"), 12, "");
  const auto b = dir.write("open22b.msh", text);
  EXPECT_TRUE(test::throws_error(
      [&] { read_gmsh(b); }, ErrorKind::Input,
      {"open22b.msh: $Elements at byte", "is not closed", "(expected $EndElements)"}));
  // A count smaller than the data: the section does not end where it says.
  text = kHandWritten22;
  text.replace(text.find("$Elements\n5\n"), 12, "$Elements\n4\n");
  const auto c = dir.write("short22.msh", text);
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(c); }, ErrorKind::Input,
                                 {"short22.msh:23", "$EndElements"}));
}

TEST(Gmsh, BinaryValuesAreChecked) {
  test::ScratchDir dir;
  MshTweaks tw;
  tw.node50_y = std::numeric_limits<double>::quiet_NaN();
  const auto a = dir.write("nan.msh", msh41_binary(tw));
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(a); }, ErrorKind::Input,
                                 {"nan.msh: $Nodes at byte", "node 50 y", "not a finite number"}));
  const auto b = dir.write("nan22.msh", msh22_binary(tw));
  EXPECT_TRUE(
      test::throws_error([&] { read_gmsh(b); }, ErrorKind::Input,
                         {"nan22.msh: $Nodes at byte", "node 50 y", "not a finite number"}));
  tw = {};
  tw.last_node = 60;
  const auto c = dir.write("node.msh", msh41_binary(tw));
  EXPECT_TRUE(
      test::throws_error([&] { read_gmsh(c); }, ErrorKind::Input,
                         {"node.msh: $Elements at byte", "element 4", "node 60 is not in"}));
  const auto d = dir.write("node22.msh", msh22_binary(tw));
  EXPECT_TRUE(test::throws_error([&] { read_gmsh(d); }, ErrorKind::Input,
                                 {"node22.msh: $Elements at byte", "node 60 is not in $Nodes"}));
  tw = {};
  tw.total_nodes = 4;  // the blocks hold 5
  const auto e = dir.write("total.msh", msh41_binary(tw));
  EXPECT_TRUE(
      test::throws_error([&] { read_gmsh(e); }, ErrorKind::Input,
                         {"total.msh: $Nodes at byte", "hold 5 nodes, the $Nodes header says 4"}));
}

TEST(Gmsh, DamagedBinaryBytesAreReadOrRefusedNeverMisread) {
  // Each byte of the binary files replaced in turn: the reader either reads a
  // mesh or throws an Input error; it never reads out of bounds (the
  // sanitizer build checks) nor throws anything else.
  test::ScratchDir dir;
  for (const auto& [name, full] :
       {std::pair{"flip41.msh", msh41_binary()}, std::pair{"flip22.msh", msh22_binary()}}) {
    for (std::size_t i = 0; i < full.size(); ++i) {
      for (const char value : {'\xFF', '\x7F', '\x00'}) {
        std::string bytes = full;
        bytes[i] = value;
        const auto p = dir.write(name, bytes);
        try {
          read_gmsh(p);
        } catch (const Error& e) {
          ASSERT_EQ(e.kind(), ErrorKind::Input) << i << ": " << e.what();
        } catch (const std::exception& e) {
          FAIL() << name << " byte " << i << ": not a palpa::Error: " << e.what();
        }
      }
    }
  }
}

}  // namespace
}  // namespace palpa
