// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/geometry/format.hpp"

#include <fmt/format.h>

#include "palpa/core/units.hpp"

namespace palpa::geometry {

std::string format_point(const Eigen::Vector3d& p) {
  return fmt::format("({}, {}, {})", format_quantity(p.x(), Dimension::Length),
                     format_quantity(p.y(), Dimension::Length),
                     format_quantity(p.z(), Dimension::Length));
}

}  // namespace palpa::geometry
