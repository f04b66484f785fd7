// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Gmsh .msh tet meshes, format version 4.1, ASCII.
//
// Read: $MeshFormat (4.1, ASCII), $Entities (the first physical tag of each
// entity), $Nodes (entity blocks, sparse tags, parametric nodes), $Elements:
// 4-node tetrahedra (type 4) become T with region = the physical tag of their
// volume entity, 3-node triangles (type 2) become boundary triangles with
// marker = the physical tag of their surface entity; points, lines and other
// linear cells are skipped; second-order cells are refused. Elements are
// ordered by their tags. Other sections are skipped.
// Write: $MeshFormat 4.1, $Entities (one volume per region id, one surface per
// boundary marker, physical tag = id), one node block, element blocks per
// entity with element tags in mesh order (so reading restores the order).

#include <filesystem>

#include "palpa/io/mesh.hpp"

namespace palpa {

// Reads a Gmsh 4.1 ASCII mesh; positions scaled by options.unit_to_si [m].
// region (boundary_marker) is filled when any volume (surface) entity has a
// physical tag, with 0 for cells whose entity has none. Throws palpa::Error
// (Input) naming the file and line: missing or empty file, another format
// version (2.2, 4.0) or a binary file (saying how to export 4.1 ASCII), a
// malformed section, non-numeric or NaN/Inf values, an element naming a node
// that is not in $Nodes, second-order elements, no tetrahedra.
TetMesh read_gmsh(const std::filesystem::path& path, const MeshReadOptions& options = {});

// Writes a Gmsh 4.1 ASCII mesh atomically; coordinates in shortest round-trip
// form. Region ids and markers <= 0 are written without a physical tag (and
// read back as 0).
void write_gmsh(const std::filesystem::path& path, const TetMesh& mesh);

}  // namespace palpa
