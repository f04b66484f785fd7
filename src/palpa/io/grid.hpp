// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A grid of numbers stored as CSV without a header: each line one row of
// comma-separated numbers (a sensor mat's frame, an image of pressures).

#include <Eigen/Core>
#include <filesystem>

namespace palpa {

// The grid, row r of the matrix from the r-th line that is not blank or a
// '#' comment. Throws palpa::Error (Input) naming the file, and the line and
// field where there is one: a missing, unreadable or empty file, a field that
// is not a finite number, rows of unequal length.
Eigen::MatrixXd read_number_grid(const std::filesystem::path& path);

}  // namespace palpa
