// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/mesh.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <limits>

#include "common/test_support.hpp"
#include "io/io_test_support.hpp"
#include "palpa/io/ply.hpp"
#include "palpa/io/vtu.hpp"

namespace palpa {
namespace {

// A UTF-8 byte-order mark before a text file (editors on Windows write one)
// changes nothing: every text format reads the same mesh with and without it
// (it once dropped an OBJ's first vertex and made an ASCII STL "binary").
TEST(MeshIo, TextFilesReadTheSameAfterAByteOrderMark) {
  test::ScratchDir dir;
  const std::string bom = "\xEF\xBB\xBF";
  const auto with_bom = [&](const std::filesystem::path& p) {
    const auto q = p.parent_path() / ("bom_" + p.filename().string());
    test::write_bytes(q, bom + test::read_bytes(p));
    return q;
  };
  const SurfaceMesh cube = test::unit_cube_surface();
  PlyWriteOptions ascii;
  ascii.encoding = PlyEncoding::Ascii;
  write_ply(dir / "c.ply", cube, ascii);
  write_surface_mesh(dir / "c.obj", cube);
  write_surface_mesh(dir / "c.off", cube);
  std::string stl = "solid cube\n";
  for (Eigen::Index f = 0; f < cube.F.rows(); ++f) {
    stl += "facet normal 0 0 0\nouter loop\n";
    for (int c = 0; c < 3; ++c) {
      const Eigen::RowVector3d v = cube.V.row(cube.F(f, c));
      stl += fmt::format("vertex {} {} {}\n", v.x(), v.y(), v.z());
    }
    stl += "endloop\nendfacet\n";
  }
  test::write_bytes(dir / "c.stl", stl + "endsolid cube\n");
  for (const char* name : {"c.obj", "c.off", "c.ply", "c.stl"}) {
    const SurfaceMesh plain = read_surface_mesh(dir / name);
    const SurfaceMesh marked = read_surface_mesh(with_bom(dir / name));
    EXPECT_EQ(plain.V.rows(), 8) << name;
    EXPECT_TRUE(test::same_bits(plain.V, marked.V)) << name;
    EXPECT_TRUE(test::same_ints(plain.F, marked.F)) << name;
  }
  std::mt19937_64 rng = test::make_rng(5);
  const TetMesh tets = test::cube_tet_mesh(rng);
  for (const char* name : {"t.msh", "t.vtu", "t.node"}) {
    write_tet_mesh(dir / name, tets);
    const TetMesh plain = read_tet_mesh(dir / name);
    std::filesystem::path marked_path = with_bom(dir / name);
    if (std::string(name) == "t.node") {  // its .ele goes along, marked too
      test::write_bytes(dir / "bom_t.ele", bom + test::read_bytes(dir / "t.ele"));
    }
    const TetMesh marked = read_tet_mesh(marked_path);
    EXPECT_TRUE(test::same_bits(plain.V, marked.V)) << name;
    EXPECT_TRUE(test::same_ints(plain.T, marked.T)) << name;
  }
}

// A NaN or an infinity never reaches a file: every writer refuses it (exit 3,
// a failed computation), naming the array, the row and the value, and writes
// nothing.
TEST(MeshIo, WritersRefuseNonFiniteValuesAndWriteNothing) {
  test::ScratchDir dir;
  SurfaceMesh bad = test::unit_cube_surface();
  bad.V(5, 1) = std::numeric_limits<double>::quiet_NaN();
  for (const char* ext : {".obj", ".ply", ".stl", ".off", ".vtu"}) {
    const auto path = dir / (std::string("s") + ext);
    EXPECT_TRUE(test::throws_error([&] { write_surface_mesh(path, bad); }, ErrorKind::Solver,
                                   {path.string(), "positions", " 5 is nan"}))
        << ext;
    EXPECT_FALSE(std::filesystem::exists(path)) << ext;
  }
  std::mt19937_64 rng = test::make_rng(3);
  TetMesh tets = test::cube_tet_mesh(rng);
  tets.V(2, 0) = std::numeric_limits<double>::infinity();
  for (const char* ext : {".node", ".msh", ".vtu"}) {
    const auto path = dir / (std::string("t") + ext);
    EXPECT_TRUE(test::throws_error([&] { write_tet_mesh(path, tets); }, ErrorKind::Solver, {" 2 is inf"})) << ext;
    EXPECT_FALSE(std::filesystem::exists(path)) << ext;
  }
  // Data arrays too.
  const SurfaceMesh cube = test::unit_cube_surface();
  PlyWriteOptions o;
  Eigen::VectorXd p = Eigen::VectorXd::Ones(cube.V.rows());
  p(7) = -std::numeric_limits<double>::infinity();
  o.vertex_scalars.push_back({"pressure_Pa", p});
  EXPECT_TRUE(test::throws_error([&] { write_ply(dir / "p.ply", cube, o); }, ErrorKind::Solver,
                                 {"vertex scalar 'pressure_Pa'", "vertex 7 is -inf"}));
  EXPECT_FALSE(std::filesystem::exists(dir / "p.ply"));
  UnstructuredGrid grid = grid_of(cube);
  grid.point_data.push_back(DataArray{"pressure_Pa", p});
  EXPECT_TRUE(test::throws_error([&] { write_vtu(dir / "p.vtu", grid); }, ErrorKind::Solver,
                                 {"point data 'pressure_Pa'", "point 7 is -inf"}));
  EXPECT_FALSE(std::filesystem::exists(dir / "p.vtu"));
  EXPECT_EQ(dir.entry_count(), 0u);
}

TEST(MeshIo, SurfaceRoundTripThroughEveryFormatByExtension) {
  test::ScratchDir dir;
  auto rng = test::make_rng(91);
  const SurfaceMesh m = test::random_surface(rng, 60, 90);
  for (const char* name : {"m.obj", "m.PLY", "m.off", "m.vtu"}) {
    write_surface_mesh(dir / name, m);
    const SurfaceMesh r = read_surface_mesh(dir / name);
    EXPECT_TRUE(test::same_bits(r.V, m.V)) << name;
    EXPECT_TRUE(test::same_ints(r.F, m.F)) << name;
  }
  write_surface_mesh(dir / "m.stl", m);
  EXPECT_EQ(read_surface_mesh(dir / "m.stl").F.rows(), 90);
}

TEST(MeshIo, TetRoundTripThroughEveryFormatByExtension) {
  test::ScratchDir dir;
  auto rng = test::make_rng(92);
  const TetMesh m = test::cube_tet_mesh(rng);
  for (const char* name : {"t.node", "t.msh", "t.vtu"}) {
    write_tet_mesh(dir / name, m);
    const TetMesh r = read_tet_mesh(dir / name);
    EXPECT_TRUE(test::same_bits(r.V, m.V)) << name;
    EXPECT_TRUE(test::same_ints(r.T, m.T)) << name;
    EXPECT_TRUE(test::same_ints(r.region, m.region)) << name;
  }
  EXPECT_EQ(mesh_kind_of(dir / "t.vtu"), MeshKind::Tet);
  EXPECT_EQ(mesh_kind_of(dir / "t.ele"), MeshKind::Tet);
  EXPECT_EQ(mesh_kind_of(dir / "x.stl"), MeshKind::Surface);
}

TEST(MeshIo, ConvertScalesToMetresAndKeepsTheKind) {
  test::ScratchDir dir;
  const auto in = dir.write("mm.off", "OFF\n3 1 0\n0 0 0\n10 0 0\n0 20 0\n3 0 1 2\n");
  MeshReadOptions opt;
  opt.unit_to_si = 1e-3;
  const MeshConversion c = convert_mesh(in, dir / "m.ply", opt);
  EXPECT_EQ(c.kind, MeshKind::Surface);
  EXPECT_EQ(c.vertices, 3);
  EXPECT_EQ(c.elements, 1);
  const SurfaceMesh r = read_surface_mesh(dir / "m.ply");
  EXPECT_DOUBLE_EQ(r.V(1, 0), 0.01);
  EXPECT_DOUBLE_EQ(r.V(2, 1), 0.02);

  auto rng = test::make_rng(93);
  write_tet_mesh(dir / "t.msh", test::cube_tet_mesh(rng));
  EXPECT_TRUE(test::throws_error([&] { convert_mesh(dir / "t.msh", dir / "t.obj"); },
                                 ErrorKind::Input,
                                 {"t.obj", "holds a tet mesh", "surface format"}));
  EXPECT_TRUE(test::throws_error([&] { convert_mesh(in, dir / "s.msh"); }, ErrorKind::Input,
                                 {"s.msh", "holds a surface", "tet mesh format"}));
  EXPECT_FALSE(std::filesystem::exists(dir / "t.obj"));
  EXPECT_FALSE(std::filesystem::exists(dir / "s.msh"));
}

TEST(MeshIo, UnknownExtensionIsAnError) {
  test::ScratchDir dir;
  const auto p = dir.write("m.xyz", "1 2 3\n");
  EXPECT_TRUE(test::throws_error([&] { read_surface_mesh(p); }, ErrorKind::Input,
                                 {"m.xyz", "unknown mesh extension '.xyz'", ".obj"}));
  EXPECT_TRUE(test::throws_error([&] { read_tet_mesh(p); }, ErrorKind::Input,
                                 {"m.xyz", "unknown mesh extension", ".msh"}));
  EXPECT_TRUE(
      test::throws_error([&] { write_surface_mesh(dir / "out", test::unit_cube_surface()); },
                         ErrorKind::Input, {"out", "no extension"}));
  EXPECT_TRUE(
      test::throws_error([&] { write_surface_mesh(dir / "o.msh", test::unit_cube_surface()); },
                         ErrorKind::Input, {"o.msh", "tet mesh format"}));
}

TEST(MeshIo, MissingAndEmptyFilesAreErrorsInEveryFormat) {
  test::ScratchDir dir;
  for (const char* name : {"a.obj", "a.ply", "a.stl", "a.off", "a.vtu"}) {
    EXPECT_TRUE(test::throws_error([&] { read_surface_mesh(dir / name); }, ErrorKind::Input,
                                   {name, "file not found"}));
    const auto p = dir.write(name, "");
    EXPECT_TRUE(test::throws_error([&] { read_surface_mesh(p); }, ErrorKind::Input,
                                   {name, "file is empty"}));
  }
  for (const char* name : {"b.node", "b.msh"}) {
    EXPECT_TRUE(test::throws_error([&] { read_tet_mesh(dir / name); }, ErrorKind::Input,
                                   {name, "file not found"}));
    const auto p = dir.write(name, "");
    EXPECT_TRUE(
        test::throws_error([&] { read_tet_mesh(p); }, ErrorKind::Input, {name, "file is empty"}));
  }
}

TEST(MeshIo, WritersIntoAMissingFolderLeaveNothing) {
  test::ScratchDir dir;
  auto rng = test::make_rng(94);
  const SurfaceMesh s = test::unit_cube_surface();
  const TetMesh t = test::cube_tet_mesh(rng);
  for (const char* name : {"m.obj", "m.ply", "m.stl", "m.off", "m.vtu"}) {
    EXPECT_TRUE(test::throws_error([&] { write_surface_mesh(dir / "no" / name, s); },
                                   ErrorKind::Input, {"does not exist"}));
  }
  for (const char* name : {"t.node", "t.msh", "t.vtu"}) {
    EXPECT_TRUE(test::throws_error([&] { write_tet_mesh(dir / "no" / name, t); }, ErrorKind::Input,
                                   {"does not exist"}));
  }
  EXPECT_EQ(dir.entry_count(), 0u);
}

TEST(MeshIo, ChecksNameTheBadElement) {
  SurfaceMesh s = test::unit_cube_surface();
  s.F(4, 1) = 8;
  EXPECT_TRUE(test::throws_error([&] { check_surface_mesh(s, "cube.obj"); }, ErrorKind::Input,
                                 {"cube.obj", "face 4", "refers to vertex 8"}));
  s = test::unit_cube_surface();
  s.V(2, 1) = std::nan("");
  EXPECT_TRUE(test::throws_error([&] { check_surface_mesh(s, "cube.obj"); }, ErrorKind::Input,
                                 {"cube.obj", "vertex 2", "nan"}));
  TetMesh t;
  t.V = s.V;
  EXPECT_TRUE(test::throws_error([&] { check_tet_mesh(t, "t.msh"); }, ErrorKind::Input,
                                 {"t.msh", "no tetrahedra"}));
}

TEST(MeshIo, VtuWithoutTrianglesIsNotASurface) {
  test::ScratchDir dir;
  auto rng = test::make_rng(95);
  write_tet_mesh(dir / "t.vtu", test::cube_tet_mesh(rng));
  EXPECT_TRUE(test::throws_error([&] { read_surface_mesh(dir / "t.vtu"); }, ErrorKind::Input,
                                 {"t.vtu", "no faces (no triangle cells)"}));
}

}  // namespace
}  // namespace palpa
