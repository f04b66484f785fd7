// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Reading and writing palpa's mesh types (geometry/mesh.hpp) by file
// extension. The per-format functions live in obj.hpp, ply.hpp, stl.hpp,
// off.hpp, tetgen.hpp, gmsh.hpp and vtu.hpp.
//
// Units: files hold coordinates in whatever unit they were made in (body scans
// are often in mm, MakeHuman in decimetres); readers multiply by
// MeshReadOptions::unit_to_si so that the returned positions are in metres.
// Writers write the positions as given (palpa writes metres).

#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "palpa/core/error.hpp"
#include "palpa/geometry/mesh.hpp"

namespace palpa {

struct MeshReadOptions {
  // Metres per file unit: positions are multiplied by it (1e-3 for a file in
  // mm). Must be finite and > 0.
  double unit_to_si = 1.0;
  // OBJ only: keep only the faces of this group (`g`) or object (`o`), and only
  // the vertices those faces use (renumbered in their file order). Empty: all
  // faces and all vertices.
  std::string obj_group;
};

enum class MeshKind { Surface, Tet };

// Reads a triangle surface by extension (case-insensitive): .obj, .ply, .stl,
// .off, .vtu (its triangle cells). Polygons are fan-triangulated. Throws
// palpa::Error (Input) naming the file and place for any bad input, including a
// mesh without faces, and for an unknown extension.
SurfaceMesh read_surface_mesh(const std::filesystem::path& path,
                              const MeshReadOptions& options = {});
// Writes by extension: .obj, .ply (binary little endian), .stl (binary), .off,
// .vtu. Atomic. Throws palpa::Error (Input) for an unknown extension or an
// unwritable folder.
void write_surface_mesh(const std::filesystem::path& path, const SurfaceMesh& mesh);

// Reads a tet mesh by extension: .node or .ele (TetGen: the pair, plus .face if
// present), .msh (Gmsh 4.1 or 2.2, ASCII or binary), .vtu (its tetra cells,
// cell data "region").
TetMesh read_tet_mesh(const std::filesystem::path& path, const MeshReadOptions& options = {});
// Writes by extension: .node or .ele (TetGen .node/.ele and .face when there are
// boundary triangles), .msh (Gmsh 4.1 ASCII), .vtu (tets with cell data
// "region"; boundary triangles are not written). Atomic (all files or none).
void write_tet_mesh(const std::filesystem::path& path, const TetMesh& mesh);

// The kind of mesh a file holds: by extension, and for .vtu by its cells (any
// tetra: Tet, else Surface). Throws palpa::Error (Input) for an unknown
// extension.
MeshKind mesh_kind_of(const std::filesystem::path& path);

// What convert_mesh() did, for a one-line report.
struct MeshConversion {
  MeshKind kind = MeshKind::Surface;
  Eigen::Index vertices = 0;
  Eigen::Index elements = 0;  // triangles or tets
};
// Reads `in` (scaled by options.unit_to_si) and writes it to `out` in the format
// of out's extension. A tet mesh cannot be written to a surface format and vice
// versa (palpa::Error, Input). Nothing is written if reading fails.
MeshConversion convert_mesh(const std::filesystem::path& in, const std::filesystem::path& out,
                            const MeshReadOptions& options = {});

// Checks a mesh read from `file`: at least one face (tet), every index a row of
// V, every coordinate finite. Throws palpa::Error (Input) naming `file` and the
// first bad face or vertex.
void check_surface_mesh(const SurfaceMesh& mesh, const std::string& file);
void check_tet_mesh(const TetMesh& mesh, const std::string& file);

}  // namespace palpa
