// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/mesh/graded_remesh.hpp"

#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <vector>

#include "palpa/core/error.hpp"
#include "palpa/mesh/detail/cgal_surface.hpp"

namespace palpa::mesh {

GradingLevels grading_levels(double far_edge, const Grading& grading) {
  if (!(grading.edge > 0.0) || !std::isfinite(grading.edge)) {
    throw_input_error("the grading's edge length is not positive", {}, "an edge length > 0 such as \"3 mm\"");
  }
  if (!(grading.within >= 0.0) || !std::isfinite(grading.within)) {
    throw_input_error("the grading's distance is negative", {}, "a distance ≥ 0 such as \"10 mm\"");
  }
  GradingLevels levels;
  levels.edge.push_back(far_edge);
  // As few levels as keep neighbours within kGradingGrowth, in equal ratios
  // down to the grading's own edge; the finest reaches `within`, each coarser
  // one two of its own edges further.
  if (grading.edge < far_edge) {
    const int n = static_cast<int>(std::ceil(std::log(far_edge / grading.edge) / std::log(kGradingGrowth) - 1e-9));
    const double ratio = std::pow(far_edge / grading.edge, 1.0 / n);
    for (int k = 1; k < n; ++k) levels.edge.push_back(levels.edge.back() / ratio);
    levels.edge.push_back(grading.edge);
  }
  levels.reach.assign(levels.edge.size(), std::numeric_limits<double>::infinity());
  double reach = grading.within;
  for (std::size_t k = levels.edge.size() - 1; k >= 1; --k) {
    levels.reach[k] = reach;
    reach += 2.0 * levels.edge[k - 1];
  }
  return levels;
}

SurfaceMesh remesh_graded(const SurfaceMesh& mesh, double far_edge, const Grading& grading,
                          const ContactDistance& distance, int iterations) {
  const GradingLevels levels = grading_levels(far_edge, grading);
  SurfaceMesh m = mesh;
  for (std::size_t k = 1; k < levels.edge.size(); ++k) {
    Eigen::MatrixX3d centroids(m.F.rows(), 3);
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      centroids.row(f) = (m.V.row(m.F(f, 0)) + m.V.row(m.F(f, 1)) + m.V.row(m.F(f, 2))) / 3.0;
    }
    const Eigen::VectorXd d = distance(centroids);
    std::vector<char> selected(static_cast<std::size_t>(m.F.rows()), 0);
    bool any = false;
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      if (d[f] < levels.reach[k]) selected[static_cast<std::size_t>(f)] = 1, any = true;
    }
    if (!any) break;  // nothing reaches this level, or any finer one
    m = detail::cgal_remesh_patch(m, selected, levels.edge[k], iterations);
  }
  return m;
}

}  // namespace palpa::mesh
