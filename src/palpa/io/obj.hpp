// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Wavefront OBJ surfaces.
//
// Read: `v x y z` (extra values such as w or colours ignored), `f` with
// `i`, `i/t`, `i//n` or `i/t/n` corners (only the vertex index i is used),
// polygons fan-triangulated, 1-based indices, negative indices relative to the
// vertices defined so far (-1 = the last one), `g`/`o` for groups and objects
// (see MeshReadOptions::obj_group; a face belongs to every group named on the
// last `g` line and to the current object; `o` starts outside any group). Texture coordinates,
// normals, materials, smoothing groups and lines are ignored.

#include <filesystem>

#include "palpa/io/mesh.hpp"

namespace palpa {

// Reads an OBJ surface; positions scaled by options.unit_to_si [m]. Throws
// palpa::Error (Input) naming the file and line: missing or empty file,
// non-numeric or NaN/Inf coordinates, an index of 0 or out of range (after
// resolving negative ones), a face with fewer than 3 corners, an unknown
// obj_group (listing the groups present), no faces.
SurfaceMesh read_obj(const std::filesystem::path& path, const MeshReadOptions& options = {});

// Writes `v` and `f` lines (1-based), coordinates in shortest round-trip form
// (read_obj returns the same doubles). Atomic.
void write_obj(const std::filesystem::path& path, const SurfaceMesh& mesh);

}  // namespace palpa
