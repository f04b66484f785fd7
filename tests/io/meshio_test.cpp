// SPDX-License-Identifier: AGPL-3.0-or-later
// Independent validation of the mesh formats: files palpa writes are read by
// meshio (a separate implementation of the same formats, run with the system
// Python), and files meshio writes are read by palpa. Each check compares point
// and cell counts and concrete values.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "common/test_support.hpp"
#include "io/io_test_support.hpp"
#include "palpa/io/gmsh.hpp"
#include "palpa/io/mesh.hpp"
#include "palpa/io/obj.hpp"
#include "palpa/io/off.hpp"
#include "palpa/io/ply.hpp"
#include "palpa/io/stl.hpp"
#include "palpa/io/tetgen.hpp"
#include "palpa/io/vtu.hpp"

namespace palpa {
namespace {

using Json = nlohmann::json;

// Reads `file` with meshio and returns, as JSON: the point count, the first and
// last point, the cell blocks (type, count, first cell) and the cell and point
// data arrays (first and last value of each).
constexpr const char* kDescribe = R"PY(
import json, sys
import numpy as np
import meshio
m = meshio.read(sys.argv[1])
def first_last(a):
    a = np.asarray(a, dtype=float).reshape(len(a), -1)
    return [a[0].tolist(), a[-1].tolist(), int(len(a))]
out = {
    "points": int(len(m.points)),
    "first_point": m.points[0].tolist(),
    "last_point": m.points[-1].tolist(),
    "cells": [{"type": c.type, "count": int(len(c.data)), "first": c.data[0].tolist()} for c in m.cells],
    "point_data": {k: first_last(v) for k, v in m.point_data.items()},
    "cell_data": {k: [first_last(b) for b in v] for k, v in m.cell_data.items()},
}
print(json.dumps(out))
)PY";

class Meshio : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!test::meshio_available()) GTEST_SKIP() << "/usr/bin/python3 with meshio is not installed";
  }

  // meshio's view of `file`.
  static Json describe(const std::filesystem::path& file) {
    std::string out;
    const std::string script =
        fmt::format("import sys\nsys.argv = ['x', r'''{}''']\n{}", file.string(), kDescribe);
    const int status = test::run_python(script, out);
    EXPECT_EQ(status, 0) << out;
    if (status != 0) return Json::object();
    return Json::parse(out.substr(out.rfind('{', out.find("\"points\""))));
  }

  // Runs a Python snippet with meshio and numpy imported and `d` the folder.
  static void python(const test::ScratchDir& dir, const std::string& body) {
    std::string out;
    const std::string script = fmt::format("import numpy as np\nimport meshio\nd = r'''{}'''\n{}",
                                           dir.path().string(), body);
    ASSERT_EQ(test::run_python(script, out), 0) << out;
  }

  static const Json& block(const Json& j, const std::string& type) {
    for (const Json& b : j.at("cells")) {
      if (b.at("type") == type) return b;
    }
    ADD_FAILURE() << "meshio found no " << type << " cells in " << j.dump();
    static const Json empty = Json::object();
    return empty;
  }
};

void expect_row(const Json& actual, const Eigen::RowVector3d& expected, double tol) {
  ASSERT_EQ(actual.size(), 3u) << actual.dump();
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(actual[c].get<double>(), expected[c], tol) << c;
}

// ---- palpa writes, meshio reads --------------------------------------------

TEST_F(Meshio, ReadsPalpaSurfaceFormats) {
  test::ScratchDir dir;
  auto rng = test::make_rng(101);
  const SurfaceMesh m = test::random_surface(rng, 40, 60);
  Eigen::VectorXd pressure(40);
  for (int i = 0; i < 40; ++i) pressure[i] = 100.0 + 0.5 * i;

  write_obj(dir / "m.obj", m);
  write_off(dir / "m.off", m);
  for (const auto& [name, encoding] : {std::pair{"m_le.ply", PlyEncoding::BinaryLittleEndian},
                                       std::pair{"m_be.ply", PlyEncoding::BinaryBigEndian},
                                       std::pair{"m_a.ply", PlyEncoding::Ascii}}) {
    PlyWriteOptions opt;
    opt.encoding = encoding;
    opt.vertex_scalars.push_back({"pressure", pressure});
    write_ply(dir / name, m, opt);
  }
  for (const char* name : {"m.obj", "m.off", "m_le.ply", "m_be.ply", "m_a.ply"}) {
    SCOPED_TRACE(name);
    const Json j = describe(dir / name);
    ASSERT_FALSE(j.empty());
    EXPECT_EQ(j.at("points"), 40);
    expect_row(j.at("first_point"), m.V.row(0), 0.0);  // exact doubles
    expect_row(j.at("last_point"), m.V.row(39), 0.0);
    const Json& tri = block(j, "triangle");
    EXPECT_EQ(tri.at("count"), 60);
    EXPECT_EQ(tri.at("first")[2].get<int>(), m.F(0, 2));
    if (std::string(name).ends_with(".ply")) {
      const Json& p = j.at("point_data").at("pressure");
      EXPECT_EQ(p[1][0].get<double>(), pressure[39]);
    }
  }
}

TEST_F(Meshio, ReadsPalpaBinaryStl) {
  test::ScratchDir dir;
  SurfaceMesh cube = test::unit_cube_surface();
  cube.V *= 0.25;
  write_stl(dir / "c.stl", cube);
  const Json j = describe(dir / "c.stl");
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(block(j, "triangle").at("count"), 12);
  // Whatever meshio's vertex numbering, the first triangle's corners are ours.
  const int first = block(j, "triangle").at("first")[0].get<int>();
  EXPECT_GE(first, 0);
  EXPECT_LE(j.at("points").get<int>(), 36);
  expect_row(j.at("first_point"), cube.V.row(cube.F(0, 0)), 0.0);
}

TEST_F(Meshio, ReadsPalpaTetFormats) {
  test::ScratchDir dir;
  auto rng = test::make_rng(102);
  const TetMesh m = test::cube_tet_mesh(rng);
  write_tetgen(dir / "t.node", m);
  write_gmsh(dir / "t.msh", m);
  UnstructuredGrid g = grid_of(m);
  Eigen::MatrixXd disp(8, 3);
  for (int i = 0; i < 8; ++i) disp.row(i) << i, -i, 0.125 * i;
  g.point_data.push_back({"displacement", disp});
  write_vtu(dir / "t.vtu", g);

  const Json node = describe(dir / "t.node");
  ASSERT_FALSE(node.empty());
  EXPECT_EQ(node.at("points"), 8);
  expect_row(node.at("last_point"), m.V.row(7), 0.0);
  EXPECT_EQ(block(node, "tetra").at("count"), 6);
  EXPECT_EQ(block(node, "tetra").at("first")[3], 7);
  EXPECT_EQ(node.at("cell_data").at("tetgen:ref")[0][1][0].get<double>(), 2.0);  // last tet

  const Json msh = describe(dir / "t.msh");
  ASSERT_FALSE(msh.empty());
  EXPECT_EQ(msh.at("points"), 8);
  expect_row(msh.at("first_point"), m.V.row(0), 0.0);
  int tets = 0;
  int triangles = 0;
  for (const Json& b : msh.at("cells")) {
    if (b.at("type") == "tetra") tets += b.at("count").get<int>();
    if (b.at("type") == "triangle") triangles += b.at("count").get<int>();
  }
  EXPECT_EQ(tets, 6);
  EXPECT_EQ(triangles, 12);
  // Physical tags: the first block is region 1, the last block is marker 6.
  const Json& phys = msh.at("cell_data").at("gmsh:physical");
  EXPECT_EQ(phys.front()[0][0].get<double>(), 1.0);
  EXPECT_EQ(phys.back()[1][0].get<double>(), 6.0);

  const Json vtu = describe(dir / "t.vtu");
  ASSERT_FALSE(vtu.empty());
  EXPECT_EQ(vtu.at("points"), 8);
  expect_row(vtu.at("last_point"), m.V.row(7), 0.0);
  EXPECT_EQ(block(vtu, "tetra").at("count"), 6);
  EXPECT_EQ(vtu.at("point_data").at("displacement")[1][2].get<double>(), 0.875);
  EXPECT_EQ(vtu.at("cell_data").at("region")[0][1][0].get<double>(), 2.0);
}

TEST_F(Meshio, ReadsPalpaMixedVtu) {
  test::ScratchDir dir;
  UnstructuredGrid g;
  Eigen::MatrixX2d rz(6, 2);
  rz << 0, 0, 1, 0, 2, 0, 0, 1, 1, 1, 2, 1;
  g.points = embed_planar(rz * 1e-3);
  Eigen::MatrixXi quads(2, 4);
  quads << 0, 1, 4, 3, 1, 2, 5, 4;
  Eigen::MatrixXi verts(1, 1);
  verts << 5;
  g.cells = {{VtkCellType::Quad, quads}, {VtkCellType::Vertex, verts}};
  g.cell_data.push_back({"pressure", Eigen::Vector3d(10.0, 20.0, 30.0)});
  write_vtu(dir / "axi.vtu", g);
  const Json j = describe(dir / "axi.vtu");
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j.at("points"), 6);
  expect_row(j.at("last_point"), Eigen::RowVector3d(2e-3, 1e-3, 0.0), 0.0);
  EXPECT_EQ(block(j, "quad").at("count"), 2);
  EXPECT_EQ(block(j, "vertex").at("count"), 1);
  const Json& p = j.at("cell_data").at("pressure");
  EXPECT_EQ(p[0][1][0].get<double>(), 20.0);  // last quad
  EXPECT_EQ(p[1][0][0].get<double>(), 30.0);  // the vertex cell
}

// ---- meshio writes, palpa reads --------------------------------------------

constexpr const char* kSurfaceScript = R"PY(
pts = np.array([[0.0, 0.0, 0.0], [1.5, 0.0, 0.0], [0.0, 2.25, 0.0], [0.125, 0.5, 3.0]])
tri = np.array([[0, 1, 2], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
m = meshio.Mesh(pts, [("triangle", tri)], point_data={"pressure": np.array([1.0, 2.0, 3.0, 4.5])})
meshio.write(d + "/s.obj", m)
meshio.write(d + "/s.off", m)
meshio.write(d + "/s_bin.ply", m, binary=True)
meshio.write(d + "/s_asc.ply", m, binary=False)
meshio.write(d + "/s_bin.stl", m, binary=True)
meshio.write(d + "/s_asc.stl", m, binary=False)
meshio.write(d + "/s_b64.vtu", m, binary=True, compression=None)
meshio.write(d + "/s_asc.vtu", m, binary=False)
meshio.write(d + "/s_zlib.vtu", m, binary=True, compression="zlib")
meshio.write(d + "/s_lzma.vtu", m, binary=True, compression="lzma")
)PY";

TEST_F(Meshio, PalpaReadsMeshioSurfaceFormats) {
  test::ScratchDir dir;
  python(dir, kSurfaceScript);
  Eigen::MatrixX3d V(4, 3);
  V << 0, 0, 0, 1.5, 0, 0, 0, 2.25, 0, 0.125, 0.5, 3.0;
  Eigen::MatrixX3i F(4, 3);
  F << 0, 1, 2, 0, 1, 3, 1, 2, 3, 0, 3, 2;
  for (const char* name : {"s.obj", "s.off", "s_bin.ply", "s_asc.ply", "s_bin.stl", "s_asc.stl",
                           "s_b64.vtu", "s_asc.vtu", "s_zlib.vtu"}) {
    SCOPED_TRACE(name);
    const SurfaceMesh m = read_surface_mesh(dir / name);
    ASSERT_EQ(m.V.rows(), 4);
    ASSERT_EQ(m.F.rows(), 4);
    // STL welding numbers vertices by first use, which here is file order too.
    EXPECT_TRUE(test::same_bits(m.V, V));
    EXPECT_TRUE(test::same_ints(m.F, F));
  }
  const PlyContents ply = read_ply_with_scalars(dir / "s_bin.ply");
  ASSERT_EQ(ply.vertex_scalars.size(), 1u);
  EXPECT_EQ(ply.vertex_scalars[0].values[3], 4.5);
  const UnstructuredGrid grid = read_vtu(dir / "s_b64.vtu");
  ASSERT_NE(grid.find_point_data("pressure"), nullptr);
  EXPECT_EQ(grid.find_point_data("pressure")->values(3, 0), 4.5);
  const UnstructuredGrid zipped = read_vtu(dir / "s_zlib.vtu");
  ASSERT_NE(zipped.find_point_data("pressure"), nullptr);
  EXPECT_EQ(zipped.find_point_data("pressure")->values(3, 0), 4.5);
  EXPECT_TRUE(test::throws_error([&] { read_surface_mesh(dir / "s_lzma.vtu"); }, ErrorKind::Input,
                                 {"s_lzma.vtu", "vtkLZMADataCompressor", "zlib"}));
}

constexpr const char* kTetScript = R"PY(
pts = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]]) * 0.01
tet = np.array([[0, 1, 2, 3], [1, 2, 3, 4]])
m = meshio.Mesh(pts, [("tetra", tet)], cell_data={"region": [np.array([3.0, 7.0])]})
meshio.write(d + "/t.node", m)
meshio.write(d + "/t.msh", m, file_format="gmsh", binary=False)
meshio.write(d + "/t.vtu", m, binary=True, compression=None)
)PY";

TEST_F(Meshio, PalpaReadsMeshioTetFormats) {
  test::ScratchDir dir;
  python(dir, kTetScript);
  Eigen::MatrixX4i T(2, 4);
  T << 0, 1, 2, 3, 1, 2, 3, 4;
  for (const char* name : {"t.node", "t.msh", "t.vtu"}) {
    SCOPED_TRACE(name);
    const TetMesh m = read_tet_mesh(dir / name);
    ASSERT_EQ(m.V.rows(), 5);
    EXPECT_EQ(m.V(4, 1), 0.01);
    EXPECT_EQ(m.V(1, 0), 0.01);
    EXPECT_TRUE(test::same_ints(m.T, T));
  }
  const TetMesh v = read_tet_mesh(dir / "t.vtu");
  ASSERT_EQ(v.region.size(), 2);
  EXPECT_EQ(v.region[1], 7);
}

// Gmsh files in the other variants palpa reads: 2.2 ASCII and binary (tets
// and a triangle with physical tags) and 4.1 binary (tets only: meshio writes
// one node block per cell type only with entity information).
constexpr const char* kGmshScript = R"PY(
pts = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]]) * 0.01
tet = np.array([[0, 1, 2, 3], [1, 2, 3, 4]])
tri = np.array([[0, 1, 2]])
m = meshio.Mesh(pts, [("tetra", tet), ("triangle", tri)],
                cell_data={"gmsh:physical": [np.array([3, 7]), np.array([5])],
                           "gmsh:geometrical": [np.array([1, 1]), np.array([2])]})
meshio.write(d + "/a22.msh", m, file_format="gmsh22", binary=False)
meshio.write(d + "/b22.msh", m, file_format="gmsh22", binary=True)
t = meshio.Mesh(pts, [("tetra", tet)])
meshio.write(d + "/a41.msh", t, file_format="gmsh", binary=False)
meshio.write(d + "/b41.msh", t, file_format="gmsh", binary=True)
)PY";

TEST_F(Meshio, PalpaReadsMeshioGmshBinaryAndVersion22) {
  test::ScratchDir dir;
  python(dir, kGmshScript);
  Eigen::MatrixX4i T(2, 4);
  T << 0, 1, 2, 3, 1, 2, 3, 4;
  const TetMesh a41 = read_gmsh(dir / "a41.msh");
  for (const char* name : {"a22.msh", "b22.msh", "b41.msh"}) {
    SCOPED_TRACE(name);
    const TetMesh m = read_gmsh(dir / name);
    EXPECT_TRUE(test::same_bits(m.V, a41.V));
    EXPECT_EQ(m.V(4, 1), 0.01);
    EXPECT_TRUE(test::same_ints(m.T, T));
    if (std::string(name).ends_with("22.msh")) {
      ASSERT_EQ(m.region.size(), 2);
      EXPECT_EQ(m.region[0], 3);
      EXPECT_EQ(m.region[1], 7);
      ASSERT_EQ(m.boundary.rows(), 1);
      EXPECT_EQ(m.boundary(0, 2), 2);
      ASSERT_EQ(m.boundary_marker.size(), 1);
      EXPECT_EQ(m.boundary_marker[0], 5);
    } else {
      EXPECT_EQ(m.region.size(), 0);  // no $Entities, so no physical tags
    }
  }
}

}  // namespace
}  // namespace palpa
