// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/vtu.hpp"

#include <zlib.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "common/test_support.hpp"
#include "io/io_test_support.hpp"

namespace palpa {
namespace {

// Every cell type in one grid: 2 tets, 3 triangles, 1 quad, 2 vertices, with
// point data (scalar and vector) and cell data.
UnstructuredGrid mixed_grid(std::mt19937_64& rng) {
  UnstructuredGrid g;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  g.points = Eigen::MatrixX3d::NullaryExpr(7, 3, [&] { return u(rng) * 1e-2; });
  Eigen::MatrixXi tets(2, 4);
  tets << 0, 1, 2, 3, 1, 2, 3, 4;
  Eigen::MatrixXi tris(3, 3);
  tris << 0, 1, 2, 2, 3, 4, 4, 5, 6;
  Eigen::MatrixXi quad(1, 4);
  quad << 3, 4, 5, 6;
  Eigen::MatrixXi verts(2, 1);
  verts << 6, 0;
  g.cells = {{VtkCellType::Tetra, tets},
             {VtkCellType::Triangle, tris},
             {VtkCellType::Quad, quad},
             {VtkCellType::Vertex, verts},
             {VtkCellType::Triangle, tris.topRows(1)}};
  g.point_data.push_back(
      {"pressure", Eigen::MatrixXd::NullaryExpr(7, 1, [&] { return u(rng) * 1e4; })});
  g.point_data.push_back(
      {"displacement", Eigen::MatrixXd::NullaryExpr(7, 3, [&] { return u(rng); })});
  g.cell_data.push_back({"region", Eigen::MatrixXd::NullaryExpr(9, 1, [&] { return u(rng); })});
  g.cell_data.push_back(
      {"stress <xx> & \"yy\"", Eigen::MatrixXd::NullaryExpr(9, 3, [&] { return u(rng); })});
  return g;
}

void expect_same_grid(const UnstructuredGrid& r, const UnstructuredGrid& g) {
  EXPECT_TRUE(test::same_bits(r.points, g.points));
  ASSERT_EQ(r.cells.size(), g.cells.size());
  for (std::size_t b = 0; b < g.cells.size(); ++b) {
    EXPECT_EQ(r.cells[b].type, g.cells[b].type) << b;
    EXPECT_TRUE(test::same_ints(r.cells[b].nodes, g.cells[b].nodes)) << b;
  }
  ASSERT_EQ(r.point_data.size(), g.point_data.size());
  for (std::size_t a = 0; a < g.point_data.size(); ++a) {
    EXPECT_EQ(r.point_data[a].name, g.point_data[a].name);
    EXPECT_TRUE(test::same_bits(r.point_data[a].values, g.point_data[a].values));
  }
  ASSERT_EQ(r.cell_data.size(), g.cell_data.size());
  for (std::size_t a = 0; a < g.cell_data.size(); ++a) {
    EXPECT_EQ(r.cell_data[a].name, g.cell_data[a].name);
    EXPECT_TRUE(test::same_bits(r.cell_data[a].values, g.cell_data[a].values));
  }
}

TEST(Vtu, RoundTripIsBitExactForEveryCellTypeAndArray) {
  test::ScratchDir dir;
  auto rng = test::make_rng(81);
  const UnstructuredGrid g = mixed_grid(rng);
  write_vtu(dir / "g.vtu", g);
  EXPECT_EQ(dir.entry_count(), 1u);
  const UnstructuredGrid r = read_vtu(dir / "g.vtu");
  expect_same_grid(r, g);
  EXPECT_EQ(r.cell_count(), 9);
  ASSERT_NE(r.find_point_data("pressure"), nullptr);
  EXPECT_EQ(r.find_cell_data("nothing"), nullptr);
  const std::string text = test::read_bytes(dir / "g.vtu");
  EXPECT_NE(text.find(R"(header_type="UInt64")"), std::string::npos);
  EXPECT_NE(text.find(R"(<AppendedData encoding="raw">)"), std::string::npos);
}

TEST(Vtu, PlanarQuadsAreWrittenWithZeroThirdCoordinate) {
  test::ScratchDir dir;
  Eigen::MatrixX2d rz(4, 2);
  rz << 0, 0, 1e-3, 0, 1e-3, 2e-3, 0, 2e-3;
  UnstructuredGrid g;
  g.points = embed_planar(rz);
  Eigen::MatrixXi quad(1, 4);
  quad << 0, 1, 2, 3;
  g.cells = {{VtkCellType::Quad, quad}};
  g.cell_data.push_back({"pressure", Eigen::MatrixXd::Constant(1, 1, 1234.5)});
  write_vtu(dir / "axi.vtu", g);
  const UnstructuredGrid r = read_vtu(dir / "axi.vtu");
  EXPECT_EQ(r.points(2, 0), 1e-3);
  EXPECT_EQ(r.points(2, 1), 2e-3);
  EXPECT_EQ(r.points.col(2).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(r.cells.at(0).type, VtkCellType::Quad);
  EXPECT_EQ(r.cell_data.at(0).values(0, 0), 1234.5);
}

TEST(Vtu, GridsOfMeshesCarryTheirCellsAndRegions) {
  auto rng = test::make_rng(82);
  const TetMesh t = test::cube_tet_mesh(rng);
  const UnstructuredGrid g = grid_of(t);
  ASSERT_EQ(g.cells.size(), 1u);
  EXPECT_EQ(g.cells[0].type, VtkCellType::Tetra);
  ASSERT_NE(g.find_cell_data("region"), nullptr);
  EXPECT_EQ(g.find_cell_data("region")->values(1, 0), 2.0);
  const UnstructuredGrid s = grid_of(test::unit_cube_surface());
  EXPECT_EQ(s.cells[0].nodes.rows(), 12);
}

// A grid in ascii and inline base64 (UInt32 headers, header and data encoded
// separately, as VTK does), in big-endian byte order for the binary arrays.
TEST(Vtu, ReadsAsciiAndInlineBase64Arrays) {
  test::ScratchDir dir;
  // Points: 3 Float64 ascii. connectivity Int32 binary big endian: 0 1 2.
  // base64 of header 00 00 00 0C (12 bytes) = "AAAADA==", data 00000000 00000001
  // 00000002 = "AAAAAAAAAAEAAAAC".
  const auto p = dir.write("inline.vtu",
                           R"(<?xml version="1.0"?>
<!-- written by hand -->
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="BigEndian">
  <UnstructuredGrid>
    <FieldData>
      <DataArray type="Float64" Name="TimeValue" NumberOfTuples="1" format="ascii">0.5</DataArray>
    </FieldData>
    <Piece NumberOfPoints="3" NumberOfCells="1">
      <PointData>
        <DataArray type="Float32" Name="T" format="ascii">1.5 2.5 3.5</DataArray>
      </PointData>
      <Points>
        <DataArray type="Float64" NumberOfComponents="3" format="ascii">
          0 0 0  1 0 0
          0 1 0
        </DataArray>
      </Points>
      <Cells>
        <DataArray type="Int32" Name="connectivity" format="binary">AAAADA==AAAAAAAAAAEAAAAC</DataArray>
        <DataArray type="Int32" Name="offsets" format="ascii">3</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">5</DataArray>
      </Cells>
    </Piece>
  </UnstructuredGrid>
</VTKFile>
)");
  const UnstructuredGrid g = read_vtu(p);
  ASSERT_EQ(g.points.rows(), 3);
  EXPECT_EQ(g.points(2, 1), 1.0);
  ASSERT_EQ(g.cells.size(), 1u);
  Eigen::MatrixXi tri(1, 3);
  tri << 0, 1, 2;
  EXPECT_TRUE(test::same_ints(g.cells[0].nodes, tri));
  ASSERT_EQ(g.point_data.size(), 1u);
  EXPECT_EQ(g.point_data[0].values(2, 0), 3.5);
}

// zlib-compressed appended data in several blocks (UInt64 headers): the
// header [blocks, block size, last block size, compressed sizes...] and then
// the blocks, as VTK writes them.
std::string zlib_blocks(const std::string& raw, std::size_t block_size) {
  std::vector<std::string> packed;
  for (std::size_t at = 0; at < raw.size(); at += block_size) {
    const std::string part = raw.substr(at, block_size);
    uLongf n = compressBound(static_cast<uLong>(part.size()));
    std::string out(n, '\0');
    EXPECT_EQ(compress(reinterpret_cast<Bytef*>(out.data()), &n, reinterpret_cast<const Bytef*>(part.data()),
                       static_cast<uLong>(part.size())),
              Z_OK);
    packed.push_back(out.substr(0, n));
  }
  std::vector<std::uint64_t> header = {packed.size(), block_size, raw.size() % block_size};
  for (const auto& p : packed) header.push_back(p.size());
  std::string bytes(reinterpret_cast<const char*>(header.data()), header.size() * 8);
  for (const auto& p : packed) bytes += p;
  return bytes;
}

// A zlib-compressed VTU of `points` points (one triangle) whose appended data
// (the points' array: compression header and blocks) is `data`.
std::string compressed_points_file(std::uint64_t points, const std::string& data) {
  return fmt::format(R"(<VTKFile type="UnstructuredGrid" byte_order="LittleEndian" header_type="UInt64" )"
                     R"(compressor="vtkZLibDataCompressor">
<UnstructuredGrid><Piece NumberOfPoints="{}" NumberOfCells="1">
<Points><DataArray type="Float64" NumberOfComponents="3" format="appended" offset="0"/></Points>
<Cells>
<DataArray type="Int32" Name="connectivity" format="ascii">0 1 2</DataArray>
<DataArray type="Int32" Name="offsets" format="ascii">3</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">5</DataArray>
</Cells></Piece></UnstructuredGrid>
<AppendedData encoding="raw">_)",
                     points) +
         data + "\n</AppendedData>\n</VTKFile>\n";
}

TEST(Vtu, ReadsZlibCompressedBlocksAndRefusesDamagedOnes) {
  test::ScratchDir dir;
  const double xyz[9] = {0, 0, 0, 1.5, 0, 0, 0, 2.25, 0};
  const std::string points = zlib_blocks(std::string(reinterpret_cast<const char*>(xyz), sizeof xyz), 32);
  const auto file = [](const std::string& data) { return compressed_points_file(3, data); };
  test::write_bytes(dir / "z.vtu", file(points));
  const UnstructuredGrid g = read_vtu(dir / "z.vtu");
  ASSERT_EQ(g.points.rows(), 3);
  EXPECT_EQ(g.points(1, 0), 1.5);
  EXPECT_EQ(g.points(2, 1), 2.25);
  // A flipped byte inside the second block, and a header promising more than
  // the file holds, are refused by name.
  std::string bad = points;
  bad[bad.size() - 12] = static_cast<char>(bad[bad.size() - 12] ^ 0x5a);
  test::write_bytes(dir / "bad.vtu", file(bad));
  EXPECT_TRUE(test::throws_error([&] { read_vtu(dir / "bad.vtu"); }, ErrorKind::Input,
                                 {"bad.vtu", "DataArray ''", "does not inflate"}));
  const std::string whole = file(points);
  test::write_bytes(dir / "cut.vtu", whole.substr(0, whole.find("raw\">_") + 6 + 16));  // the file ends there
  EXPECT_TRUE(test::throws_error([&] { read_vtu(dir / "cut.vtu"); }, ErrorKind::Input,
                                 {"cut.vtu", "truncated: the compression header is incomplete"}));
  test::write_bytes(dir / "short.vtu", file(points.substr(0, points.size() - 20)));
  EXPECT_TRUE(test::throws_error([&] { read_vtu(dir / "short.vtu"); }, ErrorKind::Input, {"short.vtu", "block"}));
}

// A header's claim is checked against the bytes present before anything is
// allocated: 200 million points claimed by a few kB of compressed data (once
// 4.7 GB and 24 s before the refusal).
TEST(Vtu, ClaimsLargerThanTheFileAreRefusedBeforeAllocating) {
  test::ScratchDir dir;
  const std::uint64_t points = 200'000'000;
  const std::uint64_t total = points * 24;
  const std::string one_block = zlib_blocks(std::string(1 << 20, '\0'), 1 << 20);
  const std::string packed = one_block.substr(4 * 8);  // the compressed bytes of 1 MiB of zeros
  const auto file = [&](const std::vector<std::uint64_t>& header, const std::string& data) {
    return compressed_points_file(points, std::string(reinterpret_cast<const char*>(header.data()), header.size() * 8) +
                                              data);
  };
  // One block said to inflate to the whole 4.8 GB.
  test::write_bytes(dir / "ratio.vtu", file({1, total, 0, packed.size()}, packed));
  EXPECT_TRUE(test::throws_error([&] { read_vtu(dir / "ratio.vtu"); }, ErrorKind::Input,
                                 {"ratio.vtu", fmt::format("cannot inflate to the {} bytes the header claims", total)}));
  // 4578 blocks of 1 MiB, of which the file holds one.
  const std::uint64_t blocks = total / (1 << 20) + 1;
  std::vector<std::uint64_t> header = {blocks, 1 << 20, total % (1 << 20)};
  header.resize(3 + blocks, packed.size());
  test::write_bytes(dir / "blocks.vtu", file(header, packed));
  EXPECT_TRUE(test::throws_error([&] { read_vtu(dir / "blocks.vtu"); }, ErrorKind::Input,
                                 {"blocks.vtu", "truncated: block 2 promises"}));
}

TEST(Vtu, TruncatedAppendedDataNamesTheArray) {
  test::ScratchDir dir;
  auto rng = test::make_rng(83);
  write_vtu(dir / "cut.vtu", mixed_grid(rng));
  const std::string bytes = test::read_bytes(dir / "cut.vtu");
  // Cut inside the last array (types): keep its 8-byte count and 3 of 9 bytes.
  const std::size_t end = bytes.rfind("\n  </AppendedData>");
  test::write_bytes(dir / "cut.vtu", bytes.substr(0, end - 6));
  EXPECT_TRUE(test::throws_error([&] { read_vtu(dir / "cut.vtu"); }, ErrorKind::Input,
                                 {"cut.vtu", "DataArray 'types'", "truncated"}));
}

TEST(Vtu, BadFilesAreErrors) {
  test::ScratchDir dir;
  const auto a =
      dir.write("poly.vtu", "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\">\n</VTKFile>\n");
  EXPECT_TRUE(test::throws_error([&] { read_vtu(a); }, ErrorKind::Input,
                                 {"poly.vtu:2", "PolyData", "UnstructuredGrid"}));
  const auto b = dir.write(
      "z.vtu", "<VTKFile type=\"UnstructuredGrid\" compressor=\"vtkLZMADataCompressor\">\n");
  EXPECT_TRUE(test::throws_error([&] { read_vtu(b); }, ErrorKind::Input,
                                 {"z.vtu:1", "compressed data (vtkLZMADataCompressor)", "zlib"}));
  const auto c = dir.write("hex.vtu", R"(<VTKFile type="UnstructuredGrid">
<UnstructuredGrid><Piece NumberOfPoints="1" NumberOfCells="1">
<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0</DataArray></Points>
<Cells>
<DataArray type="Int32" Name="connectivity" format="ascii">0 0 0 0 0 0 0 0</DataArray>
<DataArray type="Int32" Name="offsets" format="ascii">8</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">12</DataArray>
</Cells></Piece></UnstructuredGrid></VTKFile>
)");
  EXPECT_TRUE(test::throws_error([&] { read_vtu(c); }, ErrorKind::Input,
                                 {"hex.vtu:7", "DataArray 'types'", "VTK type 12"}));
  const auto d = dir.write("idx.vtu", R"(<VTKFile type="UnstructuredGrid">
<UnstructuredGrid><Piece NumberOfPoints="1" NumberOfCells="1">
<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0</DataArray></Points>
<Cells>
<DataArray type="Int32" Name="connectivity" format="ascii">0</DataArray>
<DataArray type="Int32" Name="offsets" format="ascii">1</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">1</DataArray>
</Cells>
<PointData><DataArray type="Float64" Name="p" format="ascii">nan</DataArray></PointData>
</Piece></UnstructuredGrid></VTKFile>
)");
  EXPECT_TRUE(test::throws_error([&] { read_vtu(d); }, ErrorKind::Input,
                                 {"idx.vtu:9", "DataArray 'p'", "'nan' is not a finite number"}));
}

TEST(Vtu, WriterRejectsArraysThatDoNotFitTheGrid) {
  test::ScratchDir dir;
  auto rng = test::make_rng(84);
  UnstructuredGrid g = mixed_grid(rng);
  g.cell_data[0].values.conservativeResize(8, 1);
  EXPECT_TRUE(test::throws_error([&] { write_vtu(dir / "bad.vtu", g); }, ErrorKind::Internal,
                                 {"bad.vtu", "cell data array 'region' is 8×1", "9 rows"}));
  g = mixed_grid(rng);
  g.cells[0].nodes(0, 0) = 7;
  EXPECT_TRUE(test::throws_error([&] { write_vtu(dir / "bad.vtu", g); }, ErrorKind::Internal,
                                 {"bad.vtu", "outside 0..6"}));
  EXPECT_EQ(dir.entry_count(), 0u);
}

TEST(Pvd, SeriesWritesEachStepAndAValidCollection) {
  test::ScratchDir dir;
  auto rng = test::make_rng(85);
  const UnstructuredGrid g = mixed_grid(rng);
  PvdSeries series(dir / "run.pvd");
  const auto first = series.add(0.0, g);
  series.add(0.25, g);
  series.add(0.5, g);
  EXPECT_EQ(first.filename(), "run_0000.vtu");
  EXPECT_TRUE(std::filesystem::exists(dir / "run_0002.vtu"));
  const auto entries = read_pvd(dir / "run.pvd");
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[1].time, 0.25);
  EXPECT_EQ(entries[2].time, 0.5);
  EXPECT_EQ(entries[2].file, "run_0002.vtu");
  expect_same_grid(read_vtu(dir / entries[2].file), g);
  EXPECT_EQ(dir.entry_count(), 4u);
}

}  // namespace
}  // namespace palpa
