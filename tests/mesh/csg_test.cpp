// SPDX-License-Identifier: AGPL-3.0-or-later
// Solid modelling on closed surfaces: booleans obey the inclusion–exclusion
// identity exactly and match analytic volumes, clipping gives the spherical
// cap, self-intersections are repaired into a clean surface, and the negative
// image has the pressed body's shape, depth and a smoothed rim.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/test_support.hpp"
#include "palpa/mesh/bodies.hpp"
#include "palpa/mesh/csg.hpp"
#include "palpa/mesh/layer.hpp"
#include "palpa/mesh/surface_check.hpp"

namespace palpa::mesh {
namespace {

using test::throws_error;
constexpr double kBodyRadius = 0.05;  // m

SurfaceMesh sphere(const Eigen::Vector3d& centre, double edge = 4e-3) {
  BodyOptions o;
  o.shape = BodyShape::Sphere;
  o.size = Eigen::Vector3d::Constant(2 * kBodyRadius);
  o.edge_length = edge;
  SurfaceMesh s = make_body(o);
  s.V.rowwise() += centre.transpose();
  return s;
}

// An axis-aligned box [lo, hi] of 12 triangles, outward.
SurfaceMesh box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  SurfaceMesh b;
  b.V.resize(8, 3);
  for (int i = 0; i < 8; ++i) {
    b.V.row(i) << (i & 1 ? hi.x() : lo.x()), (i & 2 ? hi.y() : lo.y()), (i & 4 ? hi.z() : lo.z());
  }
  b.F.resize(12, 3);
  b.F << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6,
      1, 3, 5, 3, 7, 5;
  return b;
}

TEST(Csg, BooleansObeyInclusionExclusionAndTheLensVolume) {
  const double d = 0.06;  // centre distance < 2r: the spheres overlap in a lens
  const SurfaceMesh a = sphere(Eigen::Vector3d::Zero());
  const SurfaceMesh b = sphere(Eigen::Vector3d(d, 0, 0));
  const SurfaceMesh u = boolean(a, b, BooleanOp::Union, "spheres");
  const SurfaceMesh i = boolean(a, b, BooleanOp::Intersection, "spheres");
  const SurfaceMesh ab = boolean(a, b, BooleanOp::Difference, "spheres");
  EXPECT_NO_THROW(check_closed_surface(u, "union"));
  EXPECT_NO_THROW(check_closed_surface(i, "intersection"));
  EXPECT_NO_THROW(check_closed_surface(ab, "difference"));
  const double va = enclosed_volume(a), vb = enclosed_volume(b);
  // Corefinement cuts the same polyhedra: the identities hold to rounding.
  EXPECT_NEAR(enclosed_volume(u) + enclosed_volume(i), va + vb, 1e-9 * va);
  EXPECT_NEAR(enclosed_volume(ab) + enclosed_volume(i), va, 1e-9 * va);
  // And the lens is the analytic one within the polyhedral error (1 %).
  const double lens = std::numbers::pi * (4 * kBodyRadius + d) * std::pow(2 * kBodyRadius - d, 2) / 12.0;
  EXPECT_NEAR(enclosed_volume(i), lens, 0.01 * lens);
  // Apart spheres stay two shells; the union is their sum.
  const SurfaceMesh far = sphere(Eigen::Vector3d(0.3, 0, 0));
  EXPECT_NEAR(enclosed_volume(boolean(a, far, BooleanOp::Union, "spheres")), 2 * va, 1e-9 * va);
  EXPECT_TRUE(throws_error([&] { boolean(a, far, BooleanOp::Intersection, "apart.obj"); },
                           ErrorKind::Input, {"apart.obj", "intersection", "empty"}));
}

TEST(Csg, ClippingASphereGivesTheCapClosedFlat) {
  const SurfaceMesh s = sphere(Eigen::Vector3d::Zero(), 3e-3);
  const double h = 0.03;  // keep the cap z ≥ r − h
  const Eigen::AlignedBox3d keep(Eigen::Vector3d(-1, -1, kBodyRadius - h), Eigen::Vector3d(1, 1, 1));
  const SurfaceMesh cap = clip_to_box(s, keep, "sphere.obj");
  EXPECT_NO_THROW(check_closed_surface(cap, "cap"));
  const double analytic = std::numbers::pi * h * h * (3 * kBodyRadius - h) / 3.0;
  EXPECT_NEAR(enclosed_volume(cap), analytic, 0.01 * analytic);
  EXPECT_NEAR(cap.V.col(2).minCoeff(), kBodyRadius - h, 1e-12);
  // A bound far out means none (once a segfault in the corefinement, from
  // about 1e154 m): the same cap.
  const Eigen::AlignedBox3d unbounded(Eigen::Vector3d(-1, -1, kBodyRadius - h), Eigen::Vector3d(1e300, 1, 1));
  EXPECT_NEAR(enclosed_volume(clip_to_box(s, unbounded, "sphere.obj")), enclosed_volume(cap), 1e-9 * analytic);
  const Eigen::AlignedBox3d away(Eigen::Vector3d(0.2, 0.2, 0.2), Eigen::Vector3d(0.3, 0.3, 0.3));
  EXPECT_TRUE(throws_error([&] { clip_to_box(s, away, "sphere.obj"); }, ErrorKind::Input,
                           {"sphere.obj", "does not overlap the body"}));
  // A box without volume (min == max in one coordinate, or a point) is
  // refused before the corefinement sees it, inside the body or outside.
  const Eigen::AlignedBox3d sheet(Eigen::Vector3d(-1, -1, 0.01), Eigen::Vector3d(1, 1, 0.01));
  const Eigen::AlignedBox3d point(Eigen::Vector3d(0.2, 0.2, 0.2), Eigen::Vector3d(0.2, 0.2, 0.2));
  for (const auto& box : {sheet, point}) {
    EXPECT_TRUE(throws_error([&] { clip_to_box(s, box, "sphere.obj"); }, ErrorKind::Input,
                             {"sphere.obj", "has no volume", "min < max"}));
  }
  // A box touching the body only at its top face keeps no volume of it.
  const Eigen::AlignedBox3d above(Eigen::Vector3d(-1, -1, s.V.col(2).maxCoeff()), Eigen::Vector3d(1, 1, 1));
  EXPECT_TRUE(throws_error([&] { clip_to_box(s, above, "sphere.obj"); }, ErrorKind::Input,
                           {"does not overlap the body"}));
}

TEST(Csg, AFoldThroughTheSurfaceIsRemoved) {
  // A vertex pulled through the far side of the sphere: its fan crosses the
  // surface there.
  SurfaceMesh s = sphere(Eigen::Vector3d::Zero(), 8e-3);
  Eigen::Index top = 0;
  s.V.col(2).maxCoeff(&top);
  s.V.row(top) << 0.0, 0.0, -1.2 * kBodyRadius;
  EXPECT_TRUE(throws_error([&] { check_closed_surface(s, "fold.obj"); }, ErrorKind::Input,
                           {"intersects itself"}));
  Eigen::Index pairs = 0;
  const SurfaceMesh fixed = remove_self_intersections(s, "fold.obj", &pairs);
  EXPECT_GT(pairs, 0);
  EXPECT_NO_THROW(check_closed_surface(fixed, "fixed"));
  // Only the fold's neighbourhood changed: the volume stays near the sphere's.
  const double v = 4.0 / 3.0 * std::numbers::pi * std::pow(kBodyRadius, 3);
  EXPECT_NEAR(enclosed_volume(fixed), v, 0.1 * v);
  // A clean surface comes back unchanged.
  const SurfaceMesh clean = sphere(Eigen::Vector3d::Zero(), 8e-3);
  const SurfaceMesh same = remove_self_intersections(clean, "clean.obj", &pairs);
  EXPECT_EQ(pairs, 0);
  EXPECT_EQ(same.F.rows(), clean.F.rows());
  EXPECT_NEAR(enclosed_volume(same), enclosed_volume(clean), 1e-15);
}

TEST(Csg, TheNegativeImageHoldsThePressedBody) {
  // A 200 × 200 × 60 mm block with its top at z = 0; the sphere starts 30 mm
  // above it and is pressed 20 mm in.
  const SurfaceMesh block = box(Eigen::Vector3d(-0.1, -0.1, -0.06), Eigen::Vector3d(0.1, 0.1, 0.0));
  const SurfaceMesh body = sphere(Eigen::Vector3d(0, 0, 0.03 + kBodyRadius), 6e-3);
  NegativeImageOptions o;
  o.press = 0.02;
  o.edge_length = 6e-3;
  o.smoothing_rounds = 5;
  o.smoothing_band = 8e-3;
  o.clearance = 3e-3;
  const NegativeImage n = negative_image(block, body, o, "chair.json");
  EXPECT_NO_THROW(check_closed_surface(n.support, "negative image"));
  EXPECT_NEAR(n.body_shift.z(), -0.05, 1e-12);
  EXPECT_NEAR(n.body_shift.head<2>().norm(), 0.0, 1e-15);
  // The hollow is the cap, 23 mm high, of the sphere grown by the clearance
  // (smoothing only rounds its rim).
  const double R = kBodyRadius + o.clearance, h = o.press + o.clearance;
  const double cap = std::numbers::pi * h * h * (3 * R - h) / 3.0;
  EXPECT_NEAR(enclosed_volume(block) - enclosed_volume(n.support), cap, 0.03 * cap);
  // The top stays; Taubin's inflating step lifts the rim by well under 1 mm.
  EXPECT_NEAR(n.support.V.col(2).maxCoeff(), 0.0, 5e-4);
  // The deepest point of the hollow is the pressed depth plus the clearance.
  double deepest = 0.0;
  for (Eigen::Index i = 0; i < n.support.V.rows(); ++i) {
    if (n.support.V.row(i).head<2>().norm() < 0.01 && n.support.V(i, 2) > -0.05) deepest = std::min(deepest, n.support.V(i, 2));
  }
  EXPECT_NEAR(deepest, -h, 1e-3);
  // No vertex of the hollow comes closer to the pressed sphere than the
  // clearance (less the offset's approximation, a fifth of it, and the
  // polyhedral sphere's sagitta).
  const Eigen::RowVector3d centre(0, 0, kBodyRadius - o.press);
  EXPECT_GE(((n.support.V.rowwise() - centre).rowwise().norm().array() - kBodyRadius).minCoeff(), 0.8 * o.clearance - 2e-4);
  // The block's corners are kept sharp by the remeshing.
  EXPECT_NEAR(n.support.V.col(0).maxCoeff(), 0.1, 1e-12);
  EXPECT_NEAR(n.support.V.col(2).minCoeff(), -0.06, 1e-12);
  // Pressing through the block is refused.
  o.press = 0.07;
  EXPECT_TRUE(throws_error([&] { negative_image(block, body, o, "chair.json"); }, ErrorKind::Input,
                           {"chair.json", "cut through"}));
}

TEST(Csg, ANegativeImageIsPressedFromFirstContact) {
  // Two 50 mm spheres, the body's 40 mm to the side of the block's and far
  // above it: lowered, it first touches the block's flank where the centres
  // are 100 mm apart, z = √(0.1² − 0.04²), not where its lowest point meets
  // the block's highest; the hollow is pressed 10 mm past that.
  const SurfaceMesh block = sphere(Eigen::Vector3d::Zero());
  const SurfaceMesh body = sphere(Eigen::Vector3d(0.04, 0, 0.2));
  NegativeImageOptions o;
  o.press = 0.01;
  o.edge_length = 4e-3;
  o.smoothing_rounds = 0;
  o.clearance = 0.0;
  const NegativeImage n = negative_image(block, body, o, "mouse.json");
  EXPECT_NO_THROW(check_closed_surface(n.support, "negative image"));
  const double touch = 0.2 - std::sqrt(0.1 * 0.1 - 0.04 * 0.04);
  // To the polyhedral spheres' sagitta (4 mm edges: 0.04 mm) and the
  // contact's falling between their vertices.
  EXPECT_NEAR(n.body_shift.z(), -(touch + o.press), 3e-4);
  EXPECT_NEAR(n.body_shift.head<2>().norm(), 0.0, 1e-15);
  // A body beside the block, never meeting it, is refused by name.
  const SurfaceMesh beside = sphere(Eigen::Vector3d(0.2, 0, 0.2));
  EXPECT_TRUE(throws_error([&] { negative_image(block, beside, o, "mouse.json"); }, ErrorKind::Input,
                           {"mouse.json", "never meets the block"}));
}

TEST(Csg, ClampingThinsTheLayerWhereTheBodyIsThin) {
  // A 100 × 60 × 16 mm block: a 6.5 mm layer plus a two-edge core (10 mm)
  // does not fit its 16 mm.
  BodyOptions b;
  b.size = Eigen::Vector3d(0.1, 0.06, 0.016);
  b.edge_length = 2e-3;
  const SurfaceMesh slab = make_body(b);
  LayerOptions o;
  o.edge_length = 5e-3;
  o.source = "slab.obj";
  EXPECT_TRUE(throws_error([&] { make_layer(slab, DepthSpec{0.0065, std::nullopt}, std::nullopt, o); },
                           ErrorKind::Input, {"slab.obj", "does not fit"}));
  o.clamp_depth = true;
  const LayerMesh layer = make_layer(slab, DepthSpec{0.0065, std::nullopt}, std::nullopt, o);
  EXPECT_GT(layer.depth_clamped, 0);
  // Through the slab: half of 16 mm minus a one-edge core, 5.5 mm, at most.
  EXPECT_LE(layer.depth.maxCoeff(), 0.0065);
  EXPECT_LT(layer.depth.minCoeff(), 0.0056);
  EXPECT_GE(layer.depth.minCoeff(), 0.5 * o.edge_length);
  const LayerSummary s = summarize_layer(layer, layer.quality);
  EXPECT_EQ(s.quality.inverted, 0);
  EXPECT_NEAR(s.layer_volume, s.outer_volume - s.core_volume, 1e-9 * s.outer_volume);
  // A body thinner than one edge cannot be layered at all.
  b.size.z() = 0.004;
  b.edge_length = 1e-3;
  EXPECT_TRUE(throws_error([&] { make_layer(make_body(b), DepthSpec{0.0065, std::nullopt}, std::nullopt, o); },
                           ErrorKind::Input, {"slab.obj", "thinnest layers"}));
}

}  // namespace
}  // namespace palpa::mesh
