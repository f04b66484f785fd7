// SPDX-License-Identifier: AGPL-3.0-or-later
// The thesis's negative image of the bundled seated body (§7.5.1: pressed
// 5 cm into the seat, its edges smoothed) is a clean closed surface: the deep
// press brings the body's clipped faces below the block's top, whose creases
// the remesh once left as zero-area caps and folded triangles.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/test_support.hpp"
#include "palpa/core/json.hpp"
#include "palpa/mesh/surface_check.hpp"
#include "palpa/rest/scene.hpp"

namespace palpa::rest {
namespace {

TEST(NegativeImage, TheThesisFiveCentimetrePressOfTheSeatedBodyIsAClosedSurface) {
  const std::filesystem::path file = test::source_path("examples/design/chair/scene.json");
  const Json chair = Json::parse(test::read_text(file));
  Json scene = {{"palpa_rest", 1},
                {"body", chair["body"]},
                {"core", chair["core"]},
                {"contact", chair["contact"]}};
  scene["support"] = Json::parse(R"({"negative_image": {
      "box": {"size": ["500 mm", "500 mm", "200 mm"], "divisions": 50},
      "press": "50 mm", "edge": "10 mm", "smoothing": 10, "band": "20 mm"},
    "position": ["0 mm", "-80 mm", "0 mm"]})");
  const RestScene s = read_rest_scene(scene, file);
  EXPECT_NO_THROW(mesh::check_closed_surface(s.support, "the negative image"));
  // The block's top stays at z = 0 (Taubin's inflating step lifts the rim by
  // well under a millimetre); the hollow's floor lies the press and the
  // 2 mm clearance below the top (the body first touches the flat top at its
  // lowest point), to the remesh's sagitta.
  EXPECT_NEAR(s.support.V.col(2).maxCoeff(), 0.0, 1e-3);
  double deepest = 0.0;
  for (Eigen::Index i = 0; i < s.support.V.rows(); ++i) {
    // Inside the block's footprint (500 mm square about y = −80 mm): the
    // hollow and the top, not the sides and the bottom.
    const bool inside = std::abs(s.support.V(i, 0)) < 0.24 && std::abs(s.support.V(i, 1) + 0.08) < 0.24 &&
                        s.support.V(i, 2) > -0.19;
    if (inside) deepest = std::min(deepest, s.support.V(i, 2));
  }
  EXPECT_NEAR(deepest, -0.052, 2e-3);
}

}  // namespace
}  // namespace palpa::rest
