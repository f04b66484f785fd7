// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Analytic test bodies: closed, outward-oriented, self-intersection-free
// triangle surfaces with near-equilateral triangles of a chosen edge length,
// so tests and examples need no scan files. Each is the zero level set of a
// smooth implicit function (documented per shape), meshed by projecting a
// fine sphere mesh onto it along rays from an inner centre (the shapes are
// star-shaped about it), remeshing isotropically and projecting the vertices
// back onto the level set (to ~1e-9 m).
//
// Frame: metres; the block and the thigh are centred at the origin; the foot
// stands on z = 0 with the heel at x = 0 and the toes towards +x.

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

#include "palpa/core/error.hpp"
#include "palpa/geometry/mesh.hpp"

namespace palpa::mesh {

enum class BodyShape {
  Sphere,        // |x| = radius
  RoundedBlock,  // a box of `size` with edges and corners rounded by `radius`
  Thigh,         // an ellipsoid of diameters `size` (long axis x)
  Foot,          // a stylized foot (sole, heel, toes, ankle stump; smooth union of ellipsoids)
};

// "sphere", "rounded-block", "thigh", "foot".
std::string_view body_shape_name(BodyShape shape) noexcept;
// The shape named (as above); palpa::Error (Input) at `where` listing the
// names otherwise.
BodyShape parse_body_shape(std::string_view name, const ErrorContext& where = {});

struct BodyOptions {
  BodyShape shape = BodyShape::RoundedBlock;
  // Outer dimensions [m]: block box size; thigh diameters (length, width,
  // height); foot: only size.x() (heel to toe) is used, the rest scale with it;
  // sphere: size.x() is the diameter. Zero = the shape's default (block
  // 100×60×40 mm, thigh 400×160×140 mm, foot 260 mm long, sphere 100 mm).
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  // Block edge rounding radius [m]; 0 = default (10 mm, at most a third of the
  // smallest size).
  double radius = 0.0;
  // Target triangle edge length [m] (> 0).
  double edge_length = 5e-3;
};

// The closed surface of the body. Throws palpa::Error (Input) for non-positive
// or non-finite sizes, a rounding radius over half the smallest size, or an
// edge length above a quarter of the smallest size.
SurfaceMesh make_body(const BodyOptions& options);

// The implicit function of the body (negative inside, zero on the surface,
// positive outside; a signed distance for the sphere and the block, a scaled
// level function for the others) at points P (#P×3) [m]; used by tests.
Eigen::VectorXd body_level(const BodyOptions& options, const Eigen::MatrixX3d& P);

// The body's smallest feature [m] (a sphere's radius, a block's or a thigh's
// smallest size, ...): make_body refuses an edge length above a quarter of it.
double body_smallest_feature(const BodyOptions& options);

// Exact enclosed volume [m³] for the sphere, block and thigh (nullopt-like NaN
// for the foot).
double body_volume(const BodyOptions& options);

}  // namespace palpa::mesh
