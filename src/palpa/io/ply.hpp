// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Stanford PLY surfaces.
//
// Read: ascii, binary_little_endian and binary_big_endian; x/y/z of any scalar
// type; the face list `vertex_indices` (or `vertex_index`) with any count and
// index types, polygons fan-triangulated; other properties and elements are
// skipped (their bytes are accounted for). Further per-vertex scalar properties
// can be returned (read_ply_with_scalars).
// Write: binary little endian (default) or ascii, x/y/z as double, faces as
// `list uchar int vertex_indices`, plus optional per-vertex double properties
// (e.g. `pressure`) for viewers that read custom PLY properties, such as
// MeshLab (which shows them as per-vertex attributes). For ParaView, .vtu
// point data is the more reliable carrier.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "palpa/io/mesh.hpp"

namespace palpa {

enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

// One value per vertex.
struct VertexScalarField {
  std::string name;        // PLY property name: no white space; not x, y or z
  Eigen::VectorXd values;  // #V values, in whatever unit the caller states
};

struct PlyWriteOptions {
  PlyEncoding encoding = PlyEncoding::BinaryLittleEndian;
  // Extra vertex properties, each with #V values, written as `property double`.
  std::vector<VertexScalarField> vertex_scalars;
};

struct PlyContents {
  SurfaceMesh mesh;
  // Every scalar vertex property other than x, y, z (e.g. nx, red, pressure), as
  // doubles in file order. Not scaled by unit_to_si.
  std::vector<VertexScalarField> vertex_scalars;
};

// Reads a PLY surface; positions scaled by options.unit_to_si [m]. Throws
// palpa::Error (Input) naming the file and the line (ascii header/data) or the
// element ("vertex 57", "face 3", with the byte offset) for: missing or empty
// file, a bad header, a binary body shorter than the header promises,
// non-numeric or NaN/Inf coordinates, an index outside 0..#V-1, a face with
// fewer than 3 corners, no faces.
SurfaceMesh read_ply(const std::filesystem::path& path, const MeshReadOptions& options = {});
PlyContents read_ply_with_scalars(const std::filesystem::path& path,
                                  const MeshReadOptions& options = {});

// Writes atomically. Binary output holds the exact doubles; ascii output uses
// shortest round-trip text, so both read back bit for bit. Each vertex scalar
// must have #V values and a valid, distinct name (programmer errors: palpa::Error
// of kind Internal).
void write_ply(const std::filesystem::path& path, const SurfaceMesh& mesh,
               const PlyWriteOptions& options = {});

}  // namespace palpa
