// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// STL surfaces (triangle soups).
//
// Read: binary or ASCII, told apart robustly: a file whose size is exactly
// 84 + 50·n bytes (n = the triangle count at byte 80) and whose first bytes do
// not look like ASCII STL text is binary, even if its header starts with
// "solid". Exactly coincident corners are welded into shared vertices (in order
// of first appearance), so the result is an indexed mesh.
// Write: binary, little endian, float32 coordinates, facet normals computed
// from the corners.

#include <filesystem>

#include "palpa/io/mesh.hpp"

namespace palpa {

// Reads an STL surface; positions scaled by options.unit_to_si [m]. Throws
// palpa::Error (Input) naming the file and the line (ASCII) or the triangle
// (binary, "triangle[4]", counted from 0): missing or empty file, a binary file
// shorter than its triangle count promises, NaN/Inf or non-numeric coordinates,
// malformed ASCII facets, no triangles.
SurfaceMesh read_stl(const std::filesystem::path& path, const MeshReadOptions& options = {});

// Writes binary STL atomically. Coordinates are stored as float32: values that
// are exactly representable as float read back bit for bit, others are rounded
// to the nearest float (relative error <= 6e-8).
void write_stl(const std::filesystem::path& path, const SurfaceMesh& mesh);

}  // namespace palpa
