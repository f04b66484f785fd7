// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/mesh/bodies.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>

#include "palpa/core/error.hpp"
#include "palpa/core/units.hpp"
#include "palpa/geometry/icosphere.hpp"
#include "palpa/mesh/surface_check.hpp"

namespace palpa::mesh {
namespace {

using Level = std::function<double(const Eigen::Vector3d&)>;

struct Shape {
  Level level;
  Eigen::Vector3d centre;  // the body is star-shaped about it
  double reach;            // every surface point is within this of the centre [m]
  double smallest;         // smallest feature size [m]
};

// Smooth union of two level functions with blending width k [m] (polynomial
// smooth minimum).
double smooth_min(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k / 4.0;
}

// Ellipsoid level: (|(x − c)/a| − 1)·min(a), negative inside.
double ellipsoid(const Eigen::Vector3d& p, const Eigen::Vector3d& c, const Eigen::Vector3d& a) {
  return ((p - c).cwiseQuotient(a).norm() - 1.0) * a.minCoeff();
}

Eigen::Vector3d default_size(BodyShape shape) {
  switch (shape) {
    case BodyShape::Sphere: return {0.1, 0.1, 0.1};
    case BodyShape::RoundedBlock: return {0.1, 0.06, 0.04};
    case BodyShape::Thigh: return {0.4, 0.16, 0.14};
    case BodyShape::Foot: return {0.26, 0.0, 0.0};
  }
  return {0.1, 0.1, 0.1};
}

Eigen::Vector3d size_of(const BodyOptions& o) {
  Eigen::Vector3d size = o.size;
  const Eigen::Vector3d d = default_size(o.shape);
  if (size.isZero()) size = d;
  if (o.shape == BodyShape::Sphere) size = Eigen::Vector3d::Constant(size.x());
  if (o.shape == BodyShape::Foot) size = Eigen::Vector3d(size.x(), 0.38 * size.x(), 0.6 * size.x());
  return size;
}

double radius_of(const BodyOptions& o, const Eigen::Vector3d& size) {
  return o.radius > 0.0 ? o.radius : std::min(0.01, size.minCoeff() / 3.0);
}

Shape shape_of(const BodyOptions& o) {
  const Eigen::Vector3d size = size_of(o);
  switch (o.shape) {
    case BodyShape::Sphere: {
      const double r = size.x() / 2.0;
      return {[r](const Eigen::Vector3d& p) { return p.norm() - r; }, Eigen::Vector3d::Zero(),
              1.01 * r, r};
    }
    case BodyShape::RoundedBlock: {
      const double r = radius_of(o, size);
      const Eigen::Vector3d inner = size / 2.0 - Eigen::Vector3d::Constant(r);
      return {[inner, r](const Eigen::Vector3d& p) {
                const Eigen::Vector3d q = p.cwiseAbs() - inner;
                return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0) - r;
              },
              Eigen::Vector3d::Zero(), 1.01 * (size / 2.0).norm(), size.minCoeff()};
    }
    case BodyShape::Thigh: {
      const Eigen::Vector3d a = size / 2.0;
      return {[a](const Eigen::Vector3d& p) { return ellipsoid(p, Eigen::Vector3d::Zero(), a); },
              Eigen::Vector3d::Zero(), 1.01 * a.maxCoeff(), 2.0 * a.minCoeff()};
    }
    case BodyShape::Foot: {
      const double L = size.x();
      // Proportions of an adult foot: sole 0.38 L wide, ankle stump to 0.6 L.
      const Level level = [L](const Eigen::Vector3d& p) {
        const double sole = ellipsoid(p, L * Eigen::Vector3d(0.52, 0.0, 0.09),
                                      L * Eigen::Vector3d(0.40, 0.17, 0.085));
        const double heel = ellipsoid(p, L * Eigen::Vector3d(0.17, 0.0, 0.12),
                                      L * Eigen::Vector3d(0.16, 0.13, 0.12));
        const double toes = ellipsoid(p, L * Eigen::Vector3d(0.80, 0.015, 0.065),
                                      L * Eigen::Vector3d(0.19, 0.19, 0.065));
        const double ankle = ellipsoid(p, L * Eigen::Vector3d(0.22, 0.0, 0.36),
                                       L * Eigen::Vector3d(0.13, 0.12, 0.26));
        const double k = 0.08 * L;
        return smooth_min(smooth_min(smooth_min(sole, heel, k), toes, k), ankle, k);
      };
      return {level, L * Eigen::Vector3d(0.3, 0.0, 0.13), 0.8 * L, 0.12 * L};
    }
  }
  return {};
}

Eigen::Vector3d gradient(const Level& f, const Eigen::Vector3d& p, double h) {
  Eigen::Vector3d g;
  for (int c = 0; c < 3; ++c) {
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e(c) = h;
    g(c) = (f(p + e) - f(p - e)) / (2.0 * h);
  }
  return g;
}

// Newton steps along the gradient onto f = 0.
Eigen::Vector3d project(const Level& f, Eigen::Vector3d p, double h) {
  for (int it = 0; it < 20; ++it) {
    const double value = f(p);
    const Eigen::Vector3d g = gradient(f, p, h);
    const double g2 = g.squaredNorm();
    if (!(g2 > 0.0)) break;
    p -= value / g2 * g;
    if (std::abs(value) < 1e-12) break;
  }
  return p;
}

// The last crossing of f from inside to outside along centre + t·d, t in (0, reach].
double ray_root(const Level& f, const Eigen::Vector3d& centre, const Eigen::Vector3d& d,
                double reach) {
  constexpr int kSteps = 200;
  double outside = reach;
  double inside = 0.0;
  for (int s = kSteps - 1; s >= 0; --s) {
    const double t = reach * s / kSteps;
    if (f(centre + t * d) < 0.0) {
      inside = t;
      outside = reach * (s + 1) / kSteps;
      break;
    }
  }
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (inside + outside);
    (f(centre + mid * d) < 0.0 ? inside : outside) = mid;
  }
  return 0.5 * (inside + outside);
}

}  // namespace

std::string_view body_shape_name(BodyShape shape) noexcept {
  switch (shape) {
    case BodyShape::Sphere: return "sphere";
    case BodyShape::RoundedBlock: return "rounded-block";
    case BodyShape::Thigh: return "thigh";
    case BodyShape::Foot: return "foot";
  }
  return "?";
}

BodyShape parse_body_shape(std::string_view name, const ErrorContext& where) {
  for (BodyShape s :
       {BodyShape::Sphere, BodyShape::RoundedBlock, BodyShape::Thigh, BodyShape::Foot}) {
    if (body_shape_name(s) == name) return s;
  }
  throw_input_error(fmt::format("unknown body shape '{}'", name), where,
                    "one of sphere, rounded-block, thigh, foot");
}

Eigen::VectorXd body_level(const BodyOptions& options, const Eigen::MatrixX3d& P) {
  const Shape shape = shape_of(options);
  Eigen::VectorXd values(P.rows());
  for (Eigen::Index i = 0; i < P.rows(); ++i) values(i) = shape.level(P.row(i).transpose());
  return values;
}

double body_smallest_feature(const BodyOptions& options) { return shape_of(options).smallest; }

double body_volume(const BodyOptions& options) {
  const Eigen::Vector3d size = size_of(options);
  const double pi = std::numbers::pi;
  switch (options.shape) {
    case BodyShape::Sphere: return pi * std::pow(size.x(), 3) / 6.0;
    case BodyShape::Thigh: return pi * size.prod() / 6.0;
    case BodyShape::RoundedBlock: {
      const double r = radius_of(options, size);
      const Eigen::Vector3d a = size - Eigen::Vector3d::Constant(2.0 * r);
      // Box + 6 slabs + 12 quarter cylinders + 8 sphere octants.
      return a.prod() + 2.0 * r * (a.x() * a.y() + a.y() * a.z() + a.z() * a.x()) +
             pi * r * r * a.sum() + 4.0 / 3.0 * pi * r * r * r;
    }
    case BodyShape::Foot: return std::numeric_limits<double>::quiet_NaN();
  }
  return std::numeric_limits<double>::quiet_NaN();
}

SurfaceMesh make_body(const BodyOptions& options) {
  const Eigen::Vector3d size = size_of(options);
  if (!size.allFinite() || !(size.minCoeff() > 0.0)) {
    throw_input_error("a body size is not positive", {}, "sizes > 0");
  }
  if (options.shape == BodyShape::RoundedBlock &&
      !(radius_of(options, size) <= size.minCoeff() / 2.0)) {
    throw_input_error(fmt::format("rounding radius {} exceeds half the smallest size {}",
                                  format_quantity(options.radius, Dimension::Length),
                                  format_quantity(size.minCoeff(), Dimension::Length)),
                      {}, "a radius ≤ half the smallest size");
  }
  const Shape shape = shape_of(options);
  if (!(options.edge_length > 0.0) || !(options.edge_length <= shape.smallest / 4.0)) {
    throw_input_error(
        fmt::format("edge length {} for a body whose smallest feature is {}",
                    format_quantity(options.edge_length, Dimension::Length),
                    format_quantity(shape.smallest, Dimension::Length)),
        {}, "an edge length > 0 and at most a quarter of the smallest feature");
  }
  // A sphere mesh whose rays sample the body at about 1.5 target edge lengths
  // (capped: level 6 has 81 920 triangles); remeshing refines and evens it out
  // and the final projection puts every vertex back on the level set.
  constexpr double kSamplingEdges = 1.5;
  int level = 2;
  while (level < 6 &&
         shape.reach * 1.1 / std::pow(2.0, level) > kSamplingEdges * options.edge_length) {
    ++level;
  }
  SurfaceMesh m = geometry::unit_icosphere(level);
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
    const Eigen::Vector3d d = m.V.row(i).transpose();
    m.V.row(i) = (shape.centre + ray_root(shape.level, shape.centre, d, shape.reach) * d).transpose();
  }
  const double h = 1e-6 * shape.reach;
  SurfaceMesh out = remesh_surface(m, options.edge_length, 5);
  for (Eigen::Index i = 0; i < out.V.rows(); ++i) {
    out.V.row(i) = project(shape.level, out.V.row(i).transpose(), h).transpose();
  }
  return out;
}

}  // namespace palpa::mesh
