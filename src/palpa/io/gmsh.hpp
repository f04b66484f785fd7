// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Gmsh .msh tet meshes: read format versions 4.1 and 2.2, ASCII or binary;
// write 4.1 ASCII.
//
// Read: $MeshFormat (4.1 or 2.2; file-type 0 = ASCII, 1 = binary with
// data-size 8, either byte order, told by the binary int 1 that follows),
// 4.1: $Entities (the first physical tag of each entity), $Nodes (entity
// blocks, sparse tags, parametric nodes), $Elements: 4-node tetrahedra (type 4)
// become T with region = the physical tag of their volume entity, 3-node
// triangles (type 2) become boundary triangles with marker = the physical tag
// of their surface entity.
// 2.2: $Nodes (sparse node numbers), $Elements (in binary: blocks of one type
// and tag count): tetrahedra and triangles as for 4.1, labelled with their
// first tag (the physical group).
// Both: points, lines and other linear cells are skipped; second-order and
// unknown cells are refused. Elements are ordered by their tags. Other sections
// are skipped.
// Write: $MeshFormat 4.1, $Entities (one volume per region id, one surface per
// boundary marker, physical tag = id), one node block, element blocks per
// entity with element tags in mesh order (so reading restores the order).

#include <filesystem>

#include "palpa/io/mesh.hpp"

namespace palpa {

// Reads a Gmsh 4.1 or 2.2 mesh, ASCII or binary; positions scaled by
// options.unit_to_si [m]. region (boundary_marker) is filled when any tet
// (triangle) has a physical tag, with 0 for cells without one. Throws
// palpa::Error (Input) naming the file and line (for binary data: the section
// and byte offset): missing or empty file, another format version (e.g. 4.0) or
// data-size (saying how to export 4.1), a malformed section, a truncated
// binary section or a count that does not fit in the rest of the file,
// non-numeric or NaN/Inf values, an element naming a node that is not in
// $Nodes, second-order or unknown elements, no tetrahedra.
TetMesh read_gmsh(const std::filesystem::path& path, const MeshReadOptions& options = {});

// Writes a Gmsh 4.1 ASCII mesh atomically; coordinates in shortest round-trip
// form. Region ids and markers <= 0 are written without a physical tag (and
// read back as 0).
void write_gmsh(const std::filesystem::path& path, const TetMesh& mesh);

}  // namespace palpa
