// SPDX-License-Identifier: AGPL-3.0-or-later
// Scattered-data interpolation over a surface: samples reproduced, the range
// respected, constants (harmonic) and linear functions of position
// (biharmonic) reproduced exactly, and bad samples refused by name.
#include <gtest/gtest.h>

#include <random>

#include "common/test_support.hpp"
#include "geometry/test_surfaces.hpp"
#include "palpa/geometry/surface_interpolation.hpp"

namespace palpa::geometry {
namespace {

using test::throws_error;

constexpr double kSphereRadius = 0.05;  // m

// #S points on the sphere of radius kSphereRadius·(1 + offset), seeded.
Eigen::MatrixX3d sphere_samples(int count, double offset, std::uint64_t salt) {
  auto rng = test::make_rng(salt);
  std::normal_distribution<double> normal;
  Eigen::MatrixX3d P(count, 3);
  for (int s = 0; s < count; ++s) {
    // Drawn z first, then y, then x, on every compiler: the order these seeds'
    // sample sets were checked in (samples farther apart than an edge).
    Eigen::RowVector3d d;
    for (int k = 2; k >= 0; --k) d[k] = normal(rng);
    P.row(s) = d.normalized() * kSphereRadius * (1.0 + offset);
  }
  return P;
}

InterpolationOptions options_for(SurfaceInterpolation method, bool clamp) {
  InterpolationOptions o;
  o.method = method;
  o.clamp_to_sample_range = clamp;
  o.max_distance = 2e-3;
  o.source = "depths.csv";
  return o;
}

class BothMethods : public ::testing::TestWithParam<SurfaceInterpolation> {};

TEST_P(BothMethods, ReproduceTheSamplesAtTheirPointsAndStayInRange) {
  const SurfaceMesh sphere = test::icosphere(3, kSphereRadius);
  const Eigen::MatrixX3d P = sphere_samples(32, 0.01, 1);
  auto rng = test::make_rng(2);
  std::uniform_real_distribution<double> depth(2e-3, 12e-3);
  Eigen::VectorXd values(P.rows());
  for (auto& v : values) v = depth(rng);
  const SurfaceInterpolator interpolator(sphere, P, options_for(GetParam(), true));
  const Eigen::VectorXd u = interpolator.interpolate(values);
  ASSERT_EQ(u.size(), sphere.V.rows());
  for (Eigen::Index s = 0; s < P.rows(); ++s) {
    // Exact at the sample's vertex (an assignment, not a solve).
    EXPECT_EQ(u(interpolator.sample_vertices()[s]), values(s)) << "sample " << s;
    // That vertex is a corner of the triangle the sample lands in, within one
    // edge length (~6 mm at this resolution) of the sample.
    const Eigen::Index v = interpolator.sample_vertices()[s];
    EXPECT_LT((sphere.V.row(v).transpose() - interpolator.sample_points()[s].position).norm(),
              6e-3);
  }
  EXPECT_GE(u.minCoeff(), values.minCoeff());
  EXPECT_LE(u.maxCoeff(), values.maxCoeff());
}

TEST_P(BothMethods, ReproduceConstants) {
  const SurfaceMesh sphere = test::icosphere(3, kSphereRadius);
  const Eigen::MatrixX3d P = sphere_samples(10, -0.01, 3);
  const Eigen::VectorXd u = interpolate_over_surface(sphere, P, Eigen::VectorXd::Constant(10, 7e3),
                                                     options_for(GetParam(), false));
  EXPECT_LT((u.array() - 7e3).abs().maxCoeff(), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Interpolation, BothMethods,
                         ::testing::Values(SurfaceInterpolation::Harmonic,
                                           SurfaceInterpolation::Biharmonic));

TEST(SurfaceInterpolation, HarmonicObeysTheMaximumPrincipleWithoutClamping) {
  const SurfaceMesh sphere = test::icosphere(3, kSphereRadius);
  const Eigen::MatrixX3d P = sphere_samples(20, 0.0, 4);
  Eigen::VectorXd values = Eigen::VectorXd::LinSpaced(20, 5e3, 15e3);
  const Eigen::VectorXd u = interpolate_over_surface(
      sphere, P, values, options_for(SurfaceInterpolation::Harmonic, false));
  // Icosphere triangles are acute: non-negative weights, so no overshoot.
  EXPECT_GE(u.minCoeff(), 5e3 - 1e-9);
  EXPECT_LE(u.maxCoeff(), 15e3 + 1e-9);
}

TEST(SurfaceInterpolation, BiharmonicOvershootsWithoutTheClampAndNotWithIt) {
  const SurfaceMesh sphere = test::icosphere(3, kSphereRadius);
  const Eigen::MatrixX3d P = sphere_samples(32, 0.01, 1);
  auto rng = test::make_rng(2);
  std::uniform_real_distribution<double> depth(2e-3, 12e-3);
  Eigen::VectorXd values(P.rows());
  for (auto& v : values) v = depth(rng);
  const Eigen::VectorXd free = interpolate_over_surface(
      sphere, P, values, options_for(SurfaceInterpolation::Biharmonic, false));
  const Eigen::VectorXd clamped = interpolate_over_surface(
      sphere, P, values, options_for(SurfaceInterpolation::Biharmonic, true));
  const double overshoot = std::max(free.maxCoeff() - values.maxCoeff(),
                                    values.minCoeff() - free.minCoeff());
  EXPECT_GT(overshoot, 1e-5);  // the smooth fit leaves the range somewhere ...
  EXPECT_GE(clamped.minCoeff(), values.minCoeff());  // ... and the clamp brings it back
  EXPECT_LE(clamped.maxCoeff(), values.maxCoeff());
  // Where the free fit is in range the clamp changes nothing.
  for (Eigen::Index i = 0; i < free.size(); ++i) {
    if (free(i) >= values.minCoeff() && free(i) <= values.maxCoeff()) {
      EXPECT_EQ(clamped(i), free(i));
    }
  }
}

TEST(SurfaceInterpolation, BiharmonicReproducesLinearFunctionsOfPositionExactly) {
  const SurfaceMesh sphere = test::icosphere(3, kSphereRadius);
  // Every 25th vertex, pushed 1 mm outward (so samples do not share vertices).
  Eigen::MatrixX3d P(sphere.V.rows() / 25, 3);
  for (Eigen::Index s = 0; s < P.rows(); ++s) P.row(s) = sphere.V.row(25 * s) * 1.02;
  const SurfaceInterpolator interpolator(sphere, P,
                                         options_for(SurfaceInterpolation::Biharmonic, false));
  const Eigen::Vector3d g(0.3, -0.2, 0.1);  // depth gradient (dimensionless)
  const auto linear = [&g](const Eigen::MatrixX3d& X) {
    return Eigen::VectorXd((8e-3 + (X * g).array()).matrix());
  };
  // Values at the sample vertices (the linear function on the surface).
  Eigen::MatrixX3d located(P.rows(), 3);
  for (Eigen::Index s = 0; s < P.rows(); ++s) {
    located.row(s) = sphere.V.row(interpolator.sample_vertices()[s]);
  }
  const Eigen::VectorXd u = interpolator.interpolate(linear(located));
  EXPECT_LT((u - linear(sphere.V)).cwiseAbs().maxCoeff(), 1e-14);
  // The harmonic method does not: that is the point of the linear part.
  const Eigen::VectorXd h = interpolate_over_surface(
      sphere, P, linear(located), options_for(SurfaceInterpolation::Harmonic, false));
  EXPECT_GT((h - linear(sphere.V)).cwiseAbs().maxCoeff(), 1e-4);
}

TEST(SurfaceInterpolation, BiharmonicIsMoreAccurateThanHarmonicForASmoothField) {
  const SurfaceMesh sphere = test::icosphere(4, kSphereRadius);
  const Eigen::MatrixX3d P = sphere_samples(60, 0.0, 6);
  const auto field = [](const Eigen::MatrixX3d& X) {
    return Eigen::VectorXd((X.col(2).array() / kSphereRadius).square() * 1e4 + 5e3);
  };
  const Eigen::VectorXd exact = field(sphere.V);
  const Eigen::VectorXd b = interpolate_over_surface(
      sphere, P, field(P), options_for(SurfaceInterpolation::Biharmonic, true));
  const Eigen::VectorXd h = interpolate_over_surface(
      sphere, P, field(P), options_for(SurfaceInterpolation::Harmonic, true));
  const double b_rms = std::sqrt((b - exact).squaredNorm() / double(exact.size()));
  const double h_rms = std::sqrt((h - exact).squaredNorm() / double(exact.size()));
  // 60 random samples of a quadratic spanning 1e4: biharmonic within 5 % RMS
  // and at least twice as accurate as harmonic.
  EXPECT_LT(b_rms, 500.0);
  EXPECT_LT(2.0 * b_rms, h_rms);
}

TEST(SurfaceInterpolation, SeveralColumnsAtOnceMatchOneAtATime) {
  const SurfaceMesh sphere = test::icosphere(2, kSphereRadius);
  const Eigen::MatrixX3d P = sphere_samples(8, 0.0, 7);
  const SurfaceInterpolator interpolator(sphere, P);
  Eigen::MatrixXd values(8, 2);
  values.col(0) = Eigen::VectorXd::LinSpaced(8, 1.0, 8.0);
  values.col(1) = Eigen::VectorXd::LinSpaced(8, -3.0, 5.0).array().square();
  const Eigen::MatrixXd both = interpolator.interpolate_columns(values);
  EXPECT_LT((both.col(0) - interpolator.interpolate(Eigen::VectorXd(values.col(0)))).norm(), 1e-12);
  EXPECT_LT((both.col(1) - interpolator.interpolate(Eigen::VectorXd(values.col(1)))).norm(), 1e-12);
}

TEST(SurfaceInterpolation, FewSamplesStillWork) {
  const SurfaceMesh sphere = test::icosphere(2, kSphereRadius);
  for (int count : {1, 2, 3}) {
    const Eigen::MatrixX3d P = sphere_samples(count, 0.0, 8);
    const Eigen::VectorXd values = Eigen::VectorXd::LinSpaced(count, 1.0, 2.0);
    const SurfaceInterpolator interpolator(sphere, P);
    const Eigen::VectorXd u = interpolator.interpolate(values);
    for (int s = 0; s < count; ++s) {
      EXPECT_EQ(u(interpolator.sample_vertices()[s]), values(s));
    }
  }
}

TEST(SurfaceInterpolation, ASampleOffTheSurfaceIsNamed) {
  const SurfaceMesh sphere = test::icosphere(2, kSphereRadius);
  Eigen::MatrixX3d P = sphere_samples(5, 0.0, 9);
  P.row(3) *= 1.5;  // 25 mm outside
  auto options = options_for(SurfaceInterpolation::Biharmonic, true);
  EXPECT_TRUE(throws_error([&] { SurfaceInterpolator(sphere, P, options); }, ErrorKind::Input,
                           {"depths.csv", "sample 3", "from the surface", "within 2 mm"}));
  options.sample_labels = {"A1", "A2", "A3", "A4", "A5"};
  EXPECT_TRUE(throws_error([&] { SurfaceInterpolator(sphere, P, options); }, ErrorKind::Input,
                           {"A4"}));
}

TEST(SurfaceInterpolation, APartWithoutSamplesIsRefused) {
  SurfaceMesh two = test::icosphere(1, kSphereRadius);
  const SurfaceMesh other = test::icosphere(1, kSphereRadius);
  const Eigen::Index nv = two.V.rows(), nf = two.F.rows();
  two.V.conservativeResize(2 * nv, 3);
  two.V.bottomRows(nv) = other.V.rowwise() + Eigen::RowVector3d(1.0, 0, 0);
  two.F.conservativeResize(2 * nf, 3);
  two.F.bottomRows(nf) = other.F.array() + int(nv);
  const Eigen::MatrixX3d P = sphere_samples(4, 0.0, 10);
  EXPECT_TRUE(throws_error([&] { SurfaceInterpolator(two, P); }, ErrorKind::Input,
                           {"connected part", "no sample"}));
}

TEST(SurfaceInterpolation, CoincidentSamplesAndBadValuesAreRefused) {
  const SurfaceMesh sphere = test::icosphere(2, kSphereRadius);
  Eigen::MatrixX3d P = sphere_samples(4, 0.0, 12);
  P.row(2) = P.row(0);
  EXPECT_TRUE(throws_error([&] { SurfaceInterpolator(sphere, P); }, ErrorKind::Input,
                           {"sample 0 and sample 2", "nearest to surface vertex"}));
  const SurfaceInterpolator ok(sphere, sphere_samples(4, 0.0, 13));
  EXPECT_TRUE(throws_error([&] { (void)ok.interpolate(Eigen::VectorXd::Ones(3)); },
                           ErrorKind::Input, {"3 sample values for 4 samples"}));
  Eigen::VectorXd bad = Eigen::VectorXd::Ones(4);
  bad(1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { (void)ok.interpolate(bad); }, ErrorKind::Input,
                           {"sample 1", "non-finite"}));
}

}  // namespace
}  // namespace palpa::geometry
