// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// OFF surfaces (Geomview Object File Format).
//
// Read: an `OFF` header line (also COFF, NOFF, CNOFF, STOFF variants, whose
// extra per-vertex values are ignored), the counts `#V #F #E` (on the header
// line or the next), #V lines `x y z ...`, #F lines `n i1 ... in [colour]` with
// 0-based indices; polygons are fan-triangulated; `#` starts a comment.
// Write: `OFF`, counts, coordinates in shortest round-trip form, `3 a b c`.

#include <filesystem>

#include "palpa/io/mesh.hpp"

namespace palpa {

// Reads an OFF surface; positions scaled by options.unit_to_si [m]. Throws
// palpa::Error (Input) naming the file and line: missing or empty file, a bad
// header or counts, non-numeric or NaN/Inf coordinates, an index outside
// 0..#V-1, fewer lines than the counts promise, no faces.
SurfaceMesh read_off(const std::filesystem::path& path, const MeshReadOptions& options = {});

// Writes atomically; read_off returns the same doubles.
void write_off(const std::filesystem::path& path, const SurfaceMesh& mesh);

}  // namespace palpa
