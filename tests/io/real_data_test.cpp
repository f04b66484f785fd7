// SPDX-License-Identifier: AGPL-3.0-or-later
// Real meshes from the shared data folder beside the repository (not copied
// into it): the MakeHuman base body and a FIND foot model.

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <utility>

#include "common/test_support.hpp"
#include "palpa/io/mesh.hpp"
#include "palpa/io/obj.hpp"

namespace palpa {
namespace {

// Number of faces around each undirected edge.
std::map<std::pair<int, int>, int> edge_use(const SurfaceMesh& m) {
  std::map<std::pair<int, int>, int> use;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = m.F(f, k);
      const int b = m.F(f, (k + 1) % 3);
      ++use[{std::min(a, b), std::max(a, b)}];
    }
  }
  return use;
}

TEST(RealData, MakeHumanBodyGroupIsTheSkinInMetres) {
  const auto path = test::source_path("../shared/data/makehuman/base.obj");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data folder not present: " << path;
  MeshReadOptions opt;
  opt.obj_group = "body";
  opt.unit_to_si = 0.1;  // MakeHuman works in decimetres
  const SurfaceMesh m = read_obj(path, opt);
  // The body group: 13378 quads over 13380 vertices; the helper geometry
  // (tights, joints, eyes) in the other groups is left out.
  EXPECT_EQ(m.V.rows(), 13380);
  EXPECT_EQ(m.F.rows(), 2 * 13378);
  check_surface_mesh(m, path.string());
  const Eigen::RowVector3d extent = m.V.colwise().maxCoeff() - m.V.colwise().minCoeff();
  EXPECT_NEAR(extent[1], 1.666, 0.005);  // height [m], y up
  EXPECT_NEAR(extent[0], 0.993, 0.005);  // arm span in the A pose [m]
  // Without the group filter the helpers come along.
  MeshReadOptions all;
  all.unit_to_si = 0.1;
  EXPECT_EQ(read_obj(path, all).V.rows(), 19158);
}

TEST(RealData, FindFootIsAClosedSurface) {
  const auto path = test::source_path("../shared/data/find_foot/foot_mean.obj");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data folder not present: " << path;
  const SurfaceMesh m = read_surface_mesh(path);
  EXPECT_EQ(m.V.rows(), 1002);
  EXPECT_EQ(m.F.rows(), 2000);
  // Closed and manifold: every edge is shared by exactly two triangles, and
  // V - E + F = 2 (a sphere-like surface).
  const auto use = edge_use(m);
  for (const auto& [edge, count] : use) {
    ASSERT_EQ(count, 2) << "edge " << edge.first << "-" << edge.second;
  }
  EXPECT_EQ(m.V.rows() - static_cast<Eigen::Index>(use.size()) + m.F.rows(), 2);
  const Eigen::RowVector3d extent = m.V.colwise().maxCoeff() - m.V.colwise().minCoeff();
  EXPECT_NEAR(extent[0], 0.2617, 0.001);  // foot length [m]
}

}  // namespace
}  // namespace palpa
