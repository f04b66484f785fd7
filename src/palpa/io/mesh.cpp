// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/mesh.hpp"

#include <fmt/format.h>

#include <spdlog/spdlog.h>

#include <cmath>

#include "palpa/core/text.hpp"
#include "palpa/io/detail/mesh_build.hpp"
#include "palpa/io/gmsh.hpp"
#include "palpa/io/obj.hpp"
#include "palpa/io/off.hpp"
#include "palpa/io/ply.hpp"
#include "palpa/io/stl.hpp"
#include "palpa/io/tetgen.hpp"
#include "palpa/io/vtu.hpp"

namespace palpa {

namespace {

constexpr const char* kSurfaceFormats = ".obj, .ply, .stl, .off or .vtu";
constexpr const char* kTetFormats = ".node/.ele (TetGen), .msh (Gmsh 4.1) or .vtu";

std::string extension_of(const std::filesystem::path& path) {
  return to_lower(path.extension().string());
}

bool is_tetgen(const std::string& ext) {
  return ext == ".node" || ext == ".ele";
}
bool is_surface(const std::string& ext) {
  return ext == ".obj" || ext == ".ply" || ext == ".stl" || ext == ".off" || ext == ".vtu";
}
bool is_tet(const std::string& ext) {
  return is_tetgen(ext) || ext == ".msh" || ext == ".vtu";
}

[[noreturn]] void unknown_extension(const std::filesystem::path& path, const char* formats) {
  ErrorContext ctx;
  ctx.file = path.string();
  const std::string ext = path.extension().string();
  throw_input_error(ext.empty() ? std::string("the file name has no extension")
                                : fmt::format("unknown mesh extension '{}'", ext),
                    ctx, formats);
}

void check_vertices(const Eigen::MatrixX3d& V, const std::string& file) {
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(V(i, c))) {
        ErrorContext ctx;
        ctx.file = file;
        ctx.field = fmt::format("vertex {}", i);
        throw_input_error(fmt::format("coordinate {} is {}", c, V(i, c)), ctx,
                          "finite coordinates");
      }
    }
  }
}

template <class Cells>
void check_cells(const Cells& cells, Eigen::Index vertex_count, const std::string& file,
                 const char* what) {
  for (Eigen::Index i = 0; i < cells.rows(); ++i) {
    for (Eigen::Index k = 0; k < cells.cols(); ++k) {
      const int v = cells(i, k);
      if (v < 0 || v >= vertex_count) {
        ErrorContext ctx;
        ctx.file = file;
        ctx.field = fmt::format("{} {}", what, i);
        throw_input_error(
            fmt::format("refers to vertex {}, the mesh has {} vertices", v, vertex_count), ctx,
            fmt::format("indices from 0 to {}", vertex_count - 1));
      }
    }
  }
}

}  // namespace

void check_surface_mesh(const SurfaceMesh& mesh, const std::string& file) {
  if (mesh.F.rows() == 0) {
    throw_input_error("the mesh has no faces", ErrorContext{file, 0, 0, {}}, "a mesh needs faces");
  }
  check_vertices(mesh.V, file);
  check_cells(mesh.F, mesh.V.rows(), file, "face");
}

void check_tet_mesh(const TetMesh& mesh, const std::string& file) {
  if (mesh.T.rows() == 0) {
    throw_input_error("the mesh has no tetrahedra", ErrorContext{file, 0, 0, {}},
                      "a tet mesh needs tetrahedra");
  }
  check_vertices(mesh.V, file);
  check_cells(mesh.T, mesh.V.rows(), file, "tetrahedron");
  check_cells(mesh.boundary, mesh.V.rows(), file, "boundary triangle");
}

namespace {

// A body or support is between a millimetre and ten metres across; outside
// that, the coordinates were most likely read in the wrong unit.
void warn_if_unlikely_size(const Eigen::MatrixX3d& V, const std::filesystem::path& path) {
  if (V.rows() == 0) return;
  const double size = (V.colwise().maxCoeff() - V.colwise().minCoeff()).maxCoeff();
  if (!std::isfinite(size)) return;
  if (size > 10.0) {
    spdlog::warn("{}: the mesh is {:.4g} m across: if its coordinates are in millimetres, give the unit "
                 "(--unit mm, or \"unit\": \"mm\" in a scene)",
                 path.string(), size);
  } else if (size < 1e-3) {
    spdlog::warn("{}: the mesh is {:.4g} mm across: if its coordinates are already in metres, drop the unit "
                 "(or give --unit m)",
                 path.string(), size * 1e3);
  }
}

}  // namespace

SurfaceMesh read_surface_mesh(const std::filesystem::path& path, const MeshReadOptions& options) {
  const std::string ext = extension_of(path);
  SurfaceMesh mesh;
  if (ext == ".obj") {
    mesh = read_obj(path, options);
  } else if (ext == ".ply") {
    mesh = read_ply(path, options);
  } else if (ext == ".stl") {
    mesh = read_stl(path, options);
  } else if (ext == ".off") {
    mesh = read_off(path, options);
  } else if (ext == ".vtu") {
    const UnstructuredGrid grid = read_vtu(path);
    mesh.V = grid.points;
    io_detail::apply_unit(mesh.V, options, path.string());
    Eigen::Index n = 0;
    for (const CellBlock& b : grid.cells) n += b.type == VtkCellType::Triangle ? b.nodes.rows() : 0;
    mesh.F.resize(n, 3);
    n = 0;
    for (const CellBlock& b : grid.cells) {
      if (b.type != VtkCellType::Triangle) continue;
      mesh.F.middleRows(n, b.nodes.rows()) = b.nodes;
      n += b.nodes.rows();
    }
    if (n == 0) {
      throw_input_error("the mesh has no faces (no triangle cells)",
                        ErrorContext{path.string(), 0, 0, {}}, "a mesh needs faces");
    }
  } else {
    unknown_extension(path, kSurfaceFormats);
  }
  check_surface_mesh(mesh, path.string());
  warn_if_unlikely_size(mesh.V, path);
  return mesh;
}

void write_surface_mesh(const std::filesystem::path& path, const SurfaceMesh& mesh) {
  const std::string ext = extension_of(path);
  if (ext == ".obj") {
    write_obj(path, mesh);
  } else if (ext == ".ply") {
    write_ply(path, mesh);
  } else if (ext == ".stl") {
    write_stl(path, mesh);
  } else if (ext == ".off") {
    write_off(path, mesh);
  } else if (ext == ".vtu") {
    write_vtu(path, grid_of(mesh));
  } else if (is_tet(ext)) {
    ErrorContext ctx;
    ctx.file = path.string();
    throw_input_error(fmt::format("'{}' is a tet mesh format; a surface cannot be written to it",
                                  path.extension().string()),
                      ctx, kSurfaceFormats);
  } else {
    unknown_extension(path, kSurfaceFormats);
  }
}

TetMesh read_tet_mesh(const std::filesystem::path& path, const MeshReadOptions& options) {
  const std::string ext = extension_of(path);
  TetMesh mesh;
  if (is_tetgen(ext)) {
    mesh = read_tetgen(path, options);
  } else if (ext == ".msh") {
    mesh = read_gmsh(path, options);
  } else if (ext == ".vtu") {
    const UnstructuredGrid grid = read_vtu(path);
    mesh.V = grid.points;
    io_detail::apply_unit(mesh.V, options, path.string());
    const DataArray* region = grid.find_cell_data("region");
    Eigen::Index n = 0;
    for (const CellBlock& b : grid.cells) n += b.type == VtkCellType::Tetra ? b.nodes.rows() : 0;
    mesh.T.resize(n, 4);
    if (region != nullptr) mesh.region.resize(n);
    Eigen::Index row = 0;
    Eigen::Index cell = 0;
    for (const CellBlock& b : grid.cells) {
      if (b.type == VtkCellType::Tetra) {
        mesh.T.middleRows(row, b.nodes.rows()) = b.nodes;
        if (region != nullptr) {
          for (Eigen::Index i = 0; i < b.nodes.rows(); ++i) {
            mesh.region[row + i] = static_cast<int>(std::lround(region->values(cell + i, 0)));
          }
        }
        row += b.nodes.rows();
      }
      cell += b.nodes.rows();
    }
  } else {
    unknown_extension(path, kTetFormats);
  }
  check_tet_mesh(mesh, path.string());
  warn_if_unlikely_size(mesh.V, path);
  return mesh;
}

void write_tet_mesh(const std::filesystem::path& path, const TetMesh& mesh) {
  const std::string ext = extension_of(path);
  if (is_tetgen(ext)) {
    write_tetgen(path, mesh);
  } else if (ext == ".msh") {
    write_gmsh(path, mesh);
  } else if (ext == ".vtu") {
    write_vtu(path, grid_of(mesh));
  } else if (is_surface(ext)) {
    ErrorContext ctx;
    ctx.file = path.string();
    throw_input_error(fmt::format("'{}' is a surface format; a tet mesh cannot be written to it",
                                  path.extension().string()),
                      ctx, kTetFormats);
  } else {
    unknown_extension(path, kTetFormats);
  }
}

MeshKind mesh_kind_of(const std::filesystem::path& path) {
  const std::string ext = extension_of(path);
  if (ext == ".vtu") {
    const UnstructuredGrid grid = read_vtu(path);
    for (const CellBlock& b : grid.cells) {
      if (b.type == VtkCellType::Tetra) return MeshKind::Tet;
    }
    return MeshKind::Surface;
  }
  if (is_tet(ext)) return MeshKind::Tet;
  if (is_surface(ext)) return MeshKind::Surface;
  unknown_extension(path, "a mesh: .obj, .ply, .stl, .off, .vtu, .node/.ele or .msh");
}

MeshConversion convert_mesh(const std::filesystem::path& in, const std::filesystem::path& out,
                            const MeshReadOptions& options) {
  MeshConversion result;
  result.kind = mesh_kind_of(in);
  const std::string out_ext = extension_of(out);
  const bool out_ok = result.kind == MeshKind::Tet ? is_tet(out_ext) : is_surface(out_ext);
  if (!out_ok) {
    ErrorContext ctx;
    ctx.file = out.string();
    const bool known = is_tet(out_ext) || is_surface(out_ext);
    if (!known) unknown_extension(out, "a mesh: .obj, .ply, .stl, .off, .vtu, .node/.ele or .msh");
    throw_input_error(result.kind == MeshKind::Tet
                          ? fmt::format("'{}' holds a tet mesh; '{}' is a surface format",
                                        in.string(), out.extension().string())
                          : fmt::format("'{}' holds a surface; '{}' is a tet mesh format",
                                        in.string(), out.extension().string()),
                      ctx, result.kind == MeshKind::Tet ? kTetFormats : kSurfaceFormats);
  }
  if (result.kind == MeshKind::Tet) {
    const TetMesh mesh = read_tet_mesh(in, options);
    write_tet_mesh(out, mesh);
    result.vertices = mesh.V.rows();
    result.elements = mesh.T.rows();
  } else {
    const SurfaceMesh mesh = read_surface_mesh(in, options);
    write_surface_mesh(out, mesh);
    result.vertices = mesh.V.rows();
    result.elements = mesh.F.rows();
  }
  return result;
}

}  // namespace palpa
