// SPDX-License-Identifier: AGPL-3.0-or-later
// Distances along a surface's edges: exact along the grid's lines, never
// shorter than the straight line and at most 8.3% longer on a grid with
// alternating diagonals, cut at the limit, the nearest of several sources,
// and infinite on a part no source is on.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "palpa/geometry/edge_distance.hpp"
#include "test_surfaces.hpp"

namespace palpa::geometry {
namespace {

// The vertex of a square_grid(n, size) at cell corner (i, j).
Eigen::Index grid_vertex(int n, int i, int j) { return static_cast<Eigen::Index>(j * (n + 1) + i); }

TEST(EdgePathDistance, FollowsTheGridAndStaysNearTheStraightLine) {
  const int n = 16;
  const SurfaceMesh grid = test::square_grid(n, 0.16);  // 1 cm cells
  const std::vector<Eigen::Index> centre{grid_vertex(n, 8, 8)};
  const Eigen::VectorXd d = edge_path_distance(grid, centre);
  double worst = 1.0;
  for (Eigen::Index v = 0; v < grid.V.rows(); ++v) {
    const double straight = grid.V.row(v).norm();
    EXPECT_GE(d(v), straight - 1e-12) << v;
    if (straight > 0.0) worst = std::max(worst, d(v) / straight);
  }
  // From this vertex every cell's diagonal points away from it, so a path
  // is one of straight and diagonal steps: at most 1/cos(22.5°) = 1.0824 of
  // the straight line, nearly reached at (5, 2) cells: (3 + 2√2)/√29.
  EXPECT_NEAR(worst, (3.0 + 2.0 * std::sqrt(2.0)) / std::sqrt(29.0), 1e-12);
  EXPECT_LT(worst, 1.0 / std::cos(std::acos(-1.0) / 8.0));
  for (int i = 0; i <= n; ++i) {
    EXPECT_NEAR(d(grid_vertex(n, i, 8)), 0.01 * std::abs(i - 8), 1e-12) << i;
    EXPECT_NEAR(d(grid_vertex(n, 8, i)), 0.01 * std::abs(i - 8), 1e-12) << i;
  }
}

TEST(EdgePathDistance, StopsAtTheLimitAndTakesTheNearestSource) {
  const int n = 16;
  const SurfaceMesh grid = test::square_grid(n, 0.16);
  const std::vector<Eigen::Index> corners{grid_vertex(n, 0, 0), grid_vertex(n, n, n)};
  const Eigen::VectorXd all = edge_path_distance(grid, corners);
  const Eigen::VectorXd near = edge_path_distance(grid, corners, 0.05);
  int cut = 0;
  for (Eigen::Index v = 0; v < grid.V.rows(); ++v) {
    const double to_first = (grid.V.row(v) - grid.V.row(corners[0])).norm();
    const double to_second = (grid.V.row(v) - grid.V.row(corners[1])).norm();
    EXPECT_GE(all(v), std::min(to_first, to_second) - 1e-12);
    if (all(v) <= 0.05) {
      EXPECT_EQ(near(v), all(v)) << v;
    } else {
      EXPECT_TRUE(std::isinf(near(v))) << v;
      ++cut;
    }
  }
  EXPECT_GT(cut, 200);
  EXPECT_NEAR(all(grid_vertex(n, 0, 5)), 0.05, 1e-12);
  EXPECT_NEAR(all(grid_vertex(n, n, n - 3)), 0.03, 1e-12);
}

TEST(EdgePathDistance, APartWithoutASourceIsUnreachedAndBadSourcesThrow) {
  SurfaceMesh two = test::square_grid(4, 0.04);
  const SurfaceMesh other = test::square_grid(4, 0.04);
  const Eigen::Index nv = two.V.rows();
  two.V.conservativeResize(2 * nv, 3);
  two.V.bottomRows(nv) = other.V;
  two.V.bottomRows(nv).col(2).array() -= 0.01;  // 1 cm below, not connected
  two.F.conservativeResize(2 * other.F.rows(), 3);
  two.F.bottomRows(other.F.rows()) = other.F.array() + static_cast<int>(nv);
  const std::vector<Eigen::Index> first{0};
  const Eigen::VectorXd d = edge_path_distance(two, first);
  for (Eigen::Index v = 0; v < nv; ++v) EXPECT_TRUE(std::isfinite(d(v)));
  for (Eigen::Index v = nv; v < 2 * nv; ++v) EXPECT_TRUE(std::isinf(d(v)));
  const std::vector<Eigen::Index> bad{2 * nv};
  EXPECT_THROW(edge_path_distance(two, bad), std::out_of_range);
}

}  // namespace
}  // namespace palpa::geometry
