// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// What `palpa material show` prints and `palpa material curve` writes, for
// any caller: a material described in words and its homogeneous curves as a
// table with units.

#include <string>
#include <string_view>

#include "palpa/io/csv.hpp"
#include "palpa/material/homogeneous.hpp"
#include "palpa/material/material_file.hpp"

namespace palpa::material {

// The material of `file` (read from `path`): model, parameters with units and
// meaning, small-strain constants, stability checks and provenance, as lines.
std::string describe(const MaterialFile& file, std::string_view path);

// `points` homogeneous points from `lo` to `hi` (stretch, or shear strain for
// the shear test): load, lateral stretch, nominal and Cauchy stresses and the
// energy density, with units in the column names; `comment` heads the table.
CsvTable homogeneous_curve_table(const Material& m, LoadCase test, double lo, double hi, int points,
                                 std::string comment);

}  // namespace palpa::material
