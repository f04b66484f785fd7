// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Internal helpers for mesh readers: growing index lists, fan triangulation,
// applying the unit, and the checks every reader ends with. Not public API.

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "palpa/io/mesh.hpp"

namespace palpa::io_detail {

using Triangle = std::array<int, 3>;

// Appends the fan triangulation (p0,p1,p2), (p0,p2,p3), ... of polygon `poly`
// (>= 3 corners, in order) to `out`.
void fan_triangulate(const std::vector<int>& poly, std::vector<Triangle>& out);

// Flat xyz triples -> #V×3.
Eigen::MatrixX3d positions_from(const std::vector<double>& xyz);
Eigen::MatrixX3i triangles_from(const std::vector<Triangle>& tris);

// Multiplies V by options.unit_to_si after checking it is finite and > 0
// (palpa::Error, Input, naming `file` otherwise).
void apply_unit(Eigen::MatrixX3d& V, const MeshReadOptions& options, const std::string& file);

// Writers call this on every array of numbers before a byte is written: a NaN
// or an infinity means the computation that made the array failed, and it must
// not reach a file. Throws palpa::Error (Solver: exit 3) naming `file`, the
// array (`what`, e.g. "point data 'pressure_Pa'"), the row (`row`, e.g.
// "vertex") and the value.
void require_finite(const Eigen::Ref<const Eigen::MatrixXd>& values, const std::string& file, const std::string& what,
                    const char* row);

// The largest vertex count a 32-bit index can address; readers refuse more.
inline constexpr long long kMaxIndex = 2147483647LL;

}  // namespace palpa::io_detail
