// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// TetGen tet meshes: `<stem>.node`, `<stem>.ele` and, optionally, `<stem>.face`.
//
//   .node  `#V 3 #attributes #markers`, then `index x y z [attributes] [marker]`
//   .ele   `#T 4 #attributes`,          then `index a b c d [attributes]`
//   .face  `#B #markers`,                then `index a b c [marker]`
//
// Node numbers start at 0 or 1 (the first node line decides) and must be
// consecutive; .ele and .face refer to them. The first tet attribute is the
// region id (an integer); the .face marker is the boundary marker. Node
// attributes and markers are not kept. `#` starts a comment.

#include <filesystem>

#include "palpa/io/mesh.hpp"

namespace palpa {

// Reads `<stem>.node` and `<stem>.ele` (and `<stem>.face` if it exists), where
// `path` is any of them or the stem itself. Positions scaled by
// options.unit_to_si [m]. Throws palpa::Error (Input) naming the file and line:
// a missing .node/.ele, a bad header, a dimension other than 3, quadratic
// (10-node) tets, non-consecutive node numbers, non-numeric or NaN/Inf values,
// an index that is not a node, a non-integer region attribute, no tets.
TetMesh read_tetgen(const std::filesystem::path& path, const MeshReadOptions& options = {});

// Writes `<stem>.node`, `<stem>.ele` and `<stem>.face` (1-based, as TetGen
// writes; the region as one tet attribute when mesh.region is set, markers in
// .face when mesh.boundary_marker is set; .face is written even with no
// boundary triangles so a stale one is never paired with the new mesh). All
// three appear together or not at all.
void write_tetgen(const std::filesystem::path& path, const TetMesh& mesh);

// `<stem>` of a TetGen path: "a/b.node" -> "a/b".
std::filesystem::path tetgen_stem(const std::filesystem::path& path);

}  // namespace palpa
