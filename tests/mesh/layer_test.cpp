// SPDX-License-Identifier: AGPL-3.0-or-later
// Soft layers around a rigid core: a uniform offset of a sphere is a sphere of
// the expected radius, the layer volume is the analytic shell's, depth samples
// are reproduced and respected, the core is closed and clean, every attached
// vertex lies on it, and bad scans and depths are refused.
#include <gtest/gtest.h>

#include <numbers>

#include "common/test_support.hpp"
#include "palpa/geometry/surface_interpolation.hpp"
#include "palpa/mesh/bodies.hpp"
#include "palpa/mesh/layer.hpp"
#include "palpa/mesh/surface_check.hpp"

namespace palpa::mesh {
namespace {

using test::throws_error;
constexpr double kPi = std::numbers::pi;
constexpr double kDegree = kPi / 180.0;
constexpr double kRadius = 0.05;  // m
constexpr double kEdge = 5e-3;    // m

SurfaceMesh sphere(double edge = kEdge) {
  BodyOptions o;
  o.shape = BodyShape::Sphere;
  o.size = Eigen::Vector3d::Constant(2 * kRadius);
  o.edge_length = edge;
  return make_body(o);
}

LayerOptions options() {
  LayerOptions o;
  o.edge_length = kEdge;
  o.source = "sphere.obj";
  return o;
}

void expect_sound(const LayerMesh& layer, const TetQuality& bounds) {
  const LayerSummary s = summarize_layer(layer, bounds);
  EXPECT_EQ(s.quality.inverted, 0);
  EXPECT_GT(s.quality.min_volume, 0.0);
  // TetGen's bounds are targets; tets pinned to both kept surfaces may miss
  // them slightly: no slivers below 5°, radius-edge beyond the bound on under
  // 1 % of the tets.
  EXPECT_GT(s.quality.min_dihedral, 5.0 * kDegree);
  EXPECT_LT(double(s.quality.above_max_radius_edge), 0.01 * double(s.quality.tets));
  EXPECT_NO_THROW(check_closed_surface(layer.core, "core"));
  // The tets fill exactly the space between the two kept surfaces.
  EXPECT_NEAR(s.layer_volume, s.outer_volume - s.core_volume, 1e-9 * s.outer_volume);
  EXPECT_EQ(s.dropped_in_core, 0);
  // Every attached vertex lies on the core surface.
  Eigen::MatrixX3d attached(layer.attached.size(), 3);
  for (std::size_t i = 0; i < layer.attached.size(); ++i) {
    attached.row(Eigen::Index(i)) = layer.tets.V.row(layer.attached[i]);
  }
  ASSERT_GT(attached.rows(), 0);
  EXPECT_LT(distance_to_surface(layer.core, attached).maxCoeff(), 1e-12);
  // And every core vertex is attached (the core is kept as given).
  EXPECT_EQ(attached.rows(), layer.core.V.rows());
}

TEST(Layer, UniformOffsetOfASphereIsTheConcentricSphereAndTheShellVolume) {
  const double depth = 0.01;
  const LayerMesh layer = make_layer(sphere(), DepthSpec{depth, std::nullopt}, std::nullopt,
                                     options());
  const Eigen::VectorXd r = layer.core.V.rowwise().norm();
  // Within the edge length (issue) — in fact within a tenth of it.
  EXPECT_LT((r.array() - (kRadius - depth)).abs().maxCoeff(), 0.1 * kEdge);
  const double shell = 4.0 / 3.0 * kPi * (std::pow(kRadius, 3) - std::pow(kRadius - depth, 3));
  const LayerSummary s = summarize_layer(layer, options().quality);
  // Inscribed polyhedra of edge h lose O(h²/R) of the volume: 2 %.
  EXPECT_NEAR(s.layer_volume, shell, 0.02 * shell);
  EXPECT_NEAR(s.thickness_mean, depth, 0.05 * depth);
  expect_sound(layer, options().quality);
}

TEST(Layer, TheDistanceOffsetIsTheConcentricSphereAndFitsWhereNormalsFold) {
  LayerOptions o = options();
  o.core_offset = CoreOffset::Distance;
  const double depth = 0.01;
  const LayerMesh layer = make_layer(sphere(), DepthSpec{depth, std::nullopt}, std::nullopt, o);
  const Eigen::VectorXd r = layer.core.V.rowwise().norm();
  // The level set is meshed within a tenth of the edge, then remeshed.
  EXPECT_LT((r.array() - (kRadius - depth)).abs().maxCoeff(), 0.15 * kEdge);
  expect_sound(layer, o.quality);

  // An 18 mm layer in the 100 × 60 × 40 mm block folds the pushed-in surface
  // at the 10 mm rounded edges; the distance offset simply rounds the core's
  // edges less: every core point is at least its depth from the skin.
  BodyOptions b;
  b.edge_length = 5e-3;
  const SurfaceMesh block = make_body(b);
  const LayerMesh deep = make_layer(block, DepthSpec{0.018, std::nullopt}, std::nullopt, o);
  EXPECT_GT(distance_to_surface(deep.outer, deep.core.V).minCoeff(), 0.018 - 0.15 * kEdge);
  expect_sound(deep, o.quality);
  // Clamping belongs to the normals offset only.
  LayerOptions clamped = o;
  clamped.clamp_depth = true;
  EXPECT_TRUE(throws_error([&] { make_layer(block, DepthSpec{0.018, std::nullopt}, std::nullopt, clamped); },
                           ErrorKind::Input, {"sphere.obj", "clamping", "distance offset"}));
  // No core is left when the body is nowhere thicker than twice the depth.
  EXPECT_TRUE(throws_error([&] { make_layer(block, DepthSpec{0.021, std::nullopt}, std::nullopt, o); },
                           ErrorKind::Input, {"sphere.obj", "no core is left"}));
}

TEST(Layer, DepthSamplesAreReproducedAndBounded) {
  const SurfaceMesh outer = sphere();
  Samples samples;
  samples.source = "depths.csv";
  samples.field = "depth_mm";
  const int n = 8;
  samples.positions.resize(n, 3);
  samples.values.resize(n);
  for (int i = 0; i < n; ++i) {
    const double phi = 2 * kPi * i / n;
    const double z = (i % 2 ? 0.4 : -0.4);
    samples.positions.row(i) =
        kRadius * Eigen::RowVector3d(std::sqrt(1 - z * z) * std::cos(phi),
                                     std::sqrt(1 - z * z) * std::sin(phi), z);
    samples.values(i) = (6.0 + 1.5 * i) * 1e-3;
    samples.labels.push_back("line " + std::to_string(i + 2));
  }
  const LayerMesh layer = make_layer(outer, DepthSpec{0.0, samples}, std::nullopt, options());
  EXPECT_GE(layer.depth.minCoeff(), samples.values.minCoeff());
  EXPECT_LE(layer.depth.maxCoeff(), samples.values.maxCoeff());
  // At each sample's vertex the requested depth is the sample; the core lies
  // at that depth under it up to the smoothing and remeshing of the inner
  // surface (a fifth of the edge length).
  geometry::InterpolationOptions io;
  const geometry::SurfaceInterpolator locate(layer.outer, samples.positions, io);
  for (int i = 0; i < n; ++i) {
    const Eigen::Index v = locate.sample_vertices()[i];
    EXPECT_EQ(layer.depth(v), samples.values(i));
    const Eigen::MatrixX3d p = layer.outer.V.row(v);
    EXPECT_NEAR(distance_to_surface(layer.core, p)(0), samples.values(i), 0.2 * kEdge);
  }
  expect_sound(layer, options().quality);
}

TEST(Layer, StiffnessSamplesGiveEveryTetAModulusInTheirRange) {
  Samples E;
  E.source = "stiffness.csv";
  E.positions.resize(3, 3);
  E.positions << kRadius, 0, 0, 0, kRadius, 0, 0, 0, kRadius;
  E.values = Eigen::Vector3d(5e3, 10e3, 15e3);
  E.labels = {"a", "b", "c"};
  const LayerMesh layer =
      make_layer(sphere(8e-3), DepthSpec{0.01, std::nullopt}, E, [] {
        LayerOptions o = options();
        o.edge_length = 8e-3;
        return o;
      }());
  ASSERT_EQ(layer.youngs_modulus.size(), layer.tets.T.rows());
  // Barycentric sums of clamped vertex values: within rounding of the range.
  EXPECT_GE(layer.youngs_modulus.minCoeff(), 5e3 * (1 - 1e-12));
  EXPECT_LE(layer.youngs_modulus.maxCoeff(), 15e3 * (1 + 1e-12));
  EXPECT_GT(layer.youngs_modulus.maxCoeff() - layer.youngs_modulus.minCoeff(), 5e3);
}

TEST(Layer, AThighAndAFootGiveSoundLayers) {
  for (BodyShape shape : {BodyShape::Thigh, BodyShape::Foot}) {
    BodyOptions b;
    b.shape = shape;
    b.edge_length = 7e-3;
    LayerOptions o = options();
    o.edge_length = 7e-3;
    const LayerMesh layer = make_layer(make_body(b), DepthSpec{0.012, std::nullopt},
                                       std::nullopt, o);
    SCOPED_TRACE(std::string(body_shape_name(shape)));
    expect_sound(layer, o.quality);
  }
}

TEST(Layer, ADepthLargerThanTheLocalThicknessOrCurvatureRadiusIsRefused) {
  BodyOptions b;  // 100 × 60 × 40 mm block, edges rounded with 10 mm
  b.edge_length = 5e-3;
  const SurfaceMesh block = make_body(b);
  // 36 mm + two edges do not fit in 40 mm.
  EXPECT_TRUE(throws_error(
      [&] { make_layer(block, DepthSpec{0.036, std::nullopt}, std::nullopt, options()); },
      ErrorKind::Input, {"sphere.obj", "does not fit", "thick there"}));
  // 18 mm from each side and a 5 mm core do not fit in 40 mm either: the
  // far side's layer counts.
  EXPECT_TRUE(throws_error(
      [&] { make_layer(block, DepthSpec{0.018, std::nullopt}, std::nullopt, options()); },
      ErrorKind::Input, {"sphere.obj", "does not fit", "far side takes 18"}));
  // 13 mm from each side (+ 5 mm) fits, but an inward offset beyond the 10 mm
  // rounding radius folds the inner surface at the edges.
  EXPECT_TRUE(throws_error(
      [&] { make_layer(block, DepthSpec{0.013, std::nullopt}, std::nullopt, options()); },
      ErrorKind::Input, {"sphere.obj", "curvature"}));
  // 8 mm is fine.
  EXPECT_NO_THROW(make_layer(block, DepthSpec{0.008, std::nullopt}, std::nullopt, options()));
  // On the 50 mm sphere (5 mm edges) a depth past 47.5 mm leaves no core of
  // one edge (it once made a core of negative volume).
  for (const double d : {0.048, 0.050, 0.060}) {
    SCOPED_TRACE(d);
    EXPECT_TRUE(throws_error([&] { make_layer(sphere(), DepthSpec{d, std::nullopt}, std::nullopt, options()); },
                             ErrorKind::Input, {"sphere.obj", "does not fit", "far side"}));
  }
}

TEST(Layer, OpenOrSelfIntersectingScansAndSamplesOffTheSurfaceAreRefused) {
  SurfaceMesh open = sphere(10e-3);
  open.F.conservativeResize(open.F.rows() - 1, 3);
  EXPECT_TRUE(throws_error(
      [&] { make_layer(open, DepthSpec{0.01, std::nullopt}, std::nullopt, options()); },
      ErrorKind::Input, {"sphere.obj", "open"}));

  const SurfaceMesh s = sphere(10e-3);
  SurfaceMesh two;
  two.V.resize(2 * s.V.rows(), 3);
  two.V << s.V, (s.V.rowwise() + Eigen::RowVector3d(0.03, 0, 0));
  two.F.resize(2 * s.F.rows(), 3);
  two.F << s.F, (s.F.array() + int(s.V.rows())).matrix();
  EXPECT_TRUE(throws_error(
      [&] { make_layer(two, DepthSpec{0.01, std::nullopt}, std::nullopt, options()); },
      ErrorKind::Input, {"sphere.obj", "intersects itself"}));

  Samples off;
  off.source = "depths.csv";
  off.positions.resize(2, 3);
  off.positions << kRadius, 0, 0, 0, 0, 2 * kRadius;
  off.values = Eigen::Vector2d(0.01, 0.01);
  off.labels = {"the sample on line 2", "the sample on line 3"};
  EXPECT_TRUE(throws_error(
      [&] { make_layer(sphere(10e-3), DepthSpec{0.0, off}, std::nullopt, options()); },
      ErrorKind::Input, {"depths.csv", "the sample on line 3", "from the surface"}));
  off.source = "moduli.csv";
  off.values = Eigen::Vector2d(5e3, -1e3);
  EXPECT_TRUE(throws_error(
      [&] { make_layer(sphere(10e-3), DepthSpec{0.01, std::nullopt}, off, options()); },
      ErrorKind::Input, {"moduli.csv", "the sample on line 3", "Young's modulus"}));
  // A modulus no tissue or support has: a unit gone wrong.
  for (const double wrong : {1e-297, 0.5, 3e9}) {
    off.values = Eigen::Vector2d(5e3, wrong);
    EXPECT_TRUE(throws_error(
        [&] { make_layer(sphere(10e-3), DepthSpec{0.01, std::nullopt}, off, options()); },
        ErrorKind::Input, {"moduli.csv", "the sample on line 3", "from 1 Pa to 1 GPa"}))
        << wrong;
  }
}

}  // namespace
}  // namespace palpa::mesh
