// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Positions in messages.

#include <Eigen/Core>
#include <string>

namespace palpa::geometry {

// "(12.5 mm, -3 mm, 40 mm)": each coordinate [m] in a unit suited to it.
std::string format_point(const Eigen::Vector3d& p);

}  // namespace palpa::geometry
