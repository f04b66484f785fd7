// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Values measured at points on a body (tissue depths, Young's moduli), read
// from CSV.
//
// Columns (units in the names, see io/csv.hpp): the position x_<unit>,
// y_<unit>, z_<unit> (a length unit, in the scan's frame) and one value
// column <base>_<unit>, e.g.
//
//   # Table 3.1, side A (bone distance), positions in the scan's frame
//   x_mm,y_mm,z_mm,depth_mm
//   12.5,-40.1,310.0,24.3
//
//   x_mm,y_mm,z_mm,youngs_modulus_kPa
//
// Other columns are ignored, so a file may carry several fields (fat_depth_mm
// and bone_distance_mm) and the caller picks one by its base name.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "palpa/core/units.hpp"

namespace palpa::mesh {

struct Samples {
  Eigen::MatrixX3d positions;       // #S×3 [m]
  Eigen::VectorXd values;           // #S, SI unit of the value's dimension
  std::vector<std::string> labels;  // #S, "line <n>" of the file, for messages
  std::string source;               // the file
  std::string field;                // the value column's name as in the file
};

// Reads the samples of column base `value_base` (e.g. "depth",
// "youngs_modulus") of dimension `dimension`. Throws palpa::Error (Input)
// naming the file, line and column: missing columns (listing those present),
// wrong units, non-finite numbers, no rows.
Samples read_samples(const std::filesystem::path& path, std::string_view value_base,
                     Dimension dimension);

}  // namespace palpa::mesh
