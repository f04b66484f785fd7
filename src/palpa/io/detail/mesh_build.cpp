// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/detail/mesh_build.hpp"

#include "palpa/core/error.hpp"

#include <fmt/format.h>

#include <cmath>

namespace palpa::io_detail {

void fan_triangulate(const std::vector<int>& poly, std::vector<Triangle>& out) {
  for (std::size_t k = 1; k + 1 < poly.size(); ++k) out.push_back({poly[0], poly[k], poly[k + 1]});
}

Eigen::MatrixX3d positions_from(const std::vector<double>& xyz) {
  const auto n = static_cast<Eigen::Index>(xyz.size() / 3);
  Eigen::MatrixX3d V(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index c = 0; c < 3; ++c) V(i, c) = xyz[static_cast<std::size_t>(3 * i + c)];
  }
  return V;
}

Eigen::MatrixX3i triangles_from(const std::vector<Triangle>& tris) {
  Eigen::MatrixX3i F(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t i = 0; i < tris.size(); ++i) {
    for (int c = 0; c < 3; ++c)
      F(static_cast<Eigen::Index>(i), c) = tris[i][static_cast<std::size_t>(c)];
  }
  return F;
}

void apply_unit(Eigen::MatrixX3d& V, const MeshReadOptions& options, const std::string& file) {
  if (!std::isfinite(options.unit_to_si) || options.unit_to_si <= 0.0) {
    ErrorContext ctx;
    ctx.file = file;
    ctx.field = "unit";
    throw_input_error(fmt::format("unit scale {} is not a positive number", options.unit_to_si),
                      ctx, "a length unit such as mm or m");
  }
  if (options.unit_to_si != 1.0) V *= options.unit_to_si;
}

void require_finite(const Eigen::Ref<const Eigen::MatrixXd>& values, const std::string& file, const std::string& what,
                    const char* row) {
  for (Eigen::Index j = 0; j < values.cols(); ++j) {
    for (Eigen::Index i = 0; i < values.rows(); ++i) {
      const double v = values(i, j);
      if (std::isfinite(v)) continue;
      ErrorContext c;
      c.file = file;
      c.field = what;
      throw_solver_error(fmt::format("{} {} is {}{}: the computation that made it failed there, so nothing was "
                                     "written",
                                     row, i, v, values.cols() > 1 ? fmt::format(" (component {})", j) : ""),
                         c);
    }
  }
}

}  // namespace palpa::io_detail
