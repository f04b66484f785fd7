// SPDX-License-Identifier: AGPL-3.0-or-later
// Analytic test bodies: closed and clean, on their implicit surface, with the
// requested edge length and the analytic volume.
#include <gtest/gtest.h>

#include <numbers>

#include "common/test_support.hpp"
#include "palpa/mesh/bodies.hpp"
#include "palpa/mesh/surface_check.hpp"

namespace palpa::mesh {
namespace {

using test::throws_error;

struct BodyCase {
  BodyShape shape;
  double edge;
  double volume_tolerance;  // relative, inscribed polyhedron vs analytic
};

class EveryBody : public ::testing::TestWithParam<BodyCase> {};

TEST_P(EveryBody, IsClosedCleanOnItsSurfaceWithTheRequestedEdgeLength) {
  BodyOptions o;
  o.shape = GetParam().shape;
  o.edge_length = GetParam().edge;
  const SurfaceMesh m = make_body(o);
  EXPECT_NO_THROW(check_closed_surface(m, std::string(body_shape_name(o.shape))));
  // Vertices on the level set (Newton projection to 1e-12 of the level).
  EXPECT_LT(body_level(o, m.V).cwiseAbs().maxCoeff(), 1e-9);
  // Isotropic remeshing: mean edge within 25 % of the target.
  EXPECT_NEAR(mean_edge_length(m), o.edge_length, 0.25 * o.edge_length);
  const double exact = body_volume(o);
  if (std::isfinite(exact)) {
    EXPECT_NEAR(enclosed_volume(m), exact, GetParam().volume_tolerance * exact);
  } else {
    EXPECT_GT(enclosed_volume(m), 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Bodies, EveryBody,
    ::testing::Values(BodyCase{BodyShape::Sphere, 8e-3, 0.02},
                      BodyCase{BodyShape::RoundedBlock, 6e-3, 0.02},
                      BodyCase{BodyShape::Thigh, 15e-3, 0.02},
                      BodyCase{BodyShape::Foot, 7e-3, 0.0}));

TEST(Bodies, NamesRoundTripAndBadOptionsAreRefused) {
  for (BodyShape s :
       {BodyShape::Sphere, BodyShape::RoundedBlock, BodyShape::Thigh, BodyShape::Foot}) {
    EXPECT_EQ(parse_body_shape(body_shape_name(s)), s);
  }
  EXPECT_TRUE(throws_error([] { parse_body_shape("hand"); }, ErrorKind::Input,
                           {"'hand'", "rounded-block"}));
  BodyOptions o;
  o.edge_length = 0.05;  // larger than a quarter of the 40 mm block height
  EXPECT_TRUE(throws_error([&] { make_body(o); }, ErrorKind::Input, {"edge length"}));
  o.edge_length = 5e-3;
  o.size = Eigen::Vector3d(0.1, -0.02, 0.04);
  EXPECT_TRUE(throws_error([&] { make_body(o); }, ErrorKind::Input, {"not positive"}));
  o.size = Eigen::Vector3d(0.1, 0.06, 0.04);
  o.radius = 0.03;
  EXPECT_TRUE(throws_error([&] { make_body(o); }, ErrorKind::Input, {"rounding radius"}));
}

}  // namespace
}  // namespace palpa::mesh
