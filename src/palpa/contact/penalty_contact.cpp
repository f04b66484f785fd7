// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/contact/penalty_contact.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <functional>

#include "palpa/core/error.hpp"

namespace palpa::contact {

namespace {

// Points per task of the parallel loops: a closest-point query costs ~1 µs.
constexpr std::size_t kDetectionGrain = 256;

}  // namespace

PenaltyContact::PenaltyContact(std::vector<int> candidates, double k, std::string name)
    : name_(std::move(name)), candidates_(std::move(candidates)) {
  set_stiffness(k);
}

void PenaltyContact::set_stiffness(double k) {
  if (!std::isfinite(k) || !(k > 0.0)) {
    throw Error(ErrorKind::Input, fmt::format("{}: contact stiffness must be > 0 N/m, got {}", name_, k));
  }
  k_ = k;
}

void PenaltyContact::set_scale(std::vector<double> scale) { scale_ = std::move(scale); }

void PenaltyContact::set_excluded(std::vector<char> excluded_obstacle_vertices) {
  excluded_ = std::move(excluded_obstacle_vertices);
}

bool PenaltyContact::excluded(const ClosestPoint& c) const {
  if (excluded_.empty()) return false;
  for (int i = 0; i < feature_size(c.feature); ++i) {
    if (excluded_[static_cast<std::size_t>(c.vertices[static_cast<std::size_t>(i)])] != 0) return true;
  }
  return false;
}

double PenaltyContact::stiffness_of(const Contact& c) const {
  return scale_.empty() ? k_ : k_ * scale_[static_cast<std::size_t>(c.point)];
}

Stencil PenaltyContact::stencil_of(const Contact& c) const {
  Stencil s;
  s.point = c.point;
  s.m = feature_size(c.closest.feature);
  s.obstacle_vertex = c.closest.vertices;
  return s;
}

double PenaltyContact::detected_energy(const Obstacle& obstacle, Points points) const {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, candidates_.size(), kDetectionGrain), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double sum) {
        ClosestPoint c;
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          const int point = candidates_[i];
          if (!obstacle.penetration(points.col(point), c) || excluded(c)) continue;
          const double k = scale_.empty() ? k_ : k_ * scale_[static_cast<std::size_t>(point)];
          sum += k * c.distance * c.distance;
        }
        return sum;
      },
      std::plus<>());
}

void PenaltyContact::commit(const Obstacle& obstacle, Points points) {
  detection_.detect(obstacle, points, candidates_);
  contacts_.clear();
  for (const Contact& c : detection_.contacts()) {
    if (!excluded(c.closest)) contacts_.push_back(c);
  }
}

double PenaltyContact::max_depth() const {
  double m = 0.0;
  for (const Contact& c : contacts_) m = std::max(m, c.closest.distance);
  return m;
}

double PenaltyContact::energy(const Obstacle& obstacle, Points points) const {
  double e = 0.0;
  for (const Contact& c : contacts_) {
    e += penalty_energy(points.col(c.point), feature_geometry(obstacle, c.closest), stiffness_of(c));
  }
  return e;
}

void PenaltyContact::add_gradient(const Obstacle& obstacle, Points points, Eigen::Ref<Eigen::Matrix3Xd> grad) const {
  assert(grad.cols() == points.cols());
  for (const Contact& c : contacts_) {
    grad.col(c.point) += penalty_gradient(points.col(c.point), feature_geometry(obstacle, c.closest), stiffness_of(c));
  }
}

void PenaltyContact::add_obstacle_gradient(const Obstacle& obstacle, Points points,
                                           Eigen::Ref<Eigen::Matrix3Xd> grad) const {
  assert(grad.cols() == obstacle.vertices().rows());
  for (const Contact& c : contacts_) {
    const FeatureGeometry g = feature_geometry(obstacle, c.closest);
    const Vector12d full = penalty_gradient_full(points.col(c.point), g, stiffness_of(c));
    for (int i = 0; i < g.m; ++i) grad.col(c.closest.vertices[static_cast<std::size_t>(i)]) += full.segment<3>(3 * (i + 1));
  }
}

void PenaltyContact::add_forces(const Obstacle& obstacle, Points points, Eigen::Ref<Eigen::Matrix3Xd> on_points,
                                Eigen::Ref<Eigen::Matrix3Xd> on_obstacle) const {
  assert(on_points.cols() == points.cols());
  assert(on_obstacle.cols() == 0 || on_obstacle.cols() == obstacle.vertices().rows());
  for (const Contact& c : contacts_) {
    const FeatureGeometry g = feature_geometry(obstacle, c.closest);
    if (on_obstacle.cols() == 0) {
      on_points.col(c.point) -= penalty_gradient(points.col(c.point), g, stiffness_of(c));
      continue;
    }
    const Vector12d full = penalty_gradient_full(points.col(c.point), g, stiffness_of(c));
    on_points.col(c.point) -= full.head<3>();
    for (int i = 0; i < g.m; ++i) {
      on_obstacle.col(c.closest.vertices[static_cast<std::size_t>(i)]) -= full.segment<3>(3 * (i + 1));
    }
  }
}

Wrench PenaltyContact::obstacle_wrench(const Obstacle& obstacle, Points points, const Eigen::Vector3d& about) const {
  Wrench w;
  for (const Contact& c : contacts_) {
    const Eigen::Vector3d p = points.col(c.point);
    const Eigen::Vector3d a = sliding_anchor(p, feature_geometry(obstacle, c.closest)).point;
    const Eigen::Vector3d reaction = 2.0 * stiffness_of(c) * (p - a);  // −f
    w.force += reaction;
    w.torque += (a - about).cross(reaction);
  }
  return w;
}

void PenaltyContact::add_hessian_product(const Obstacle& obstacle, Points points, Points v_points,
                                         Points v_obstacle, Eigen::Ref<Eigen::Matrix3Xd> out_points,
                                         Eigen::Ref<Eigen::Matrix3Xd> out_obstacle) const {
  assert(v_points.cols() == points.cols() && out_points.cols() == points.cols());
  const bool has_v = v_obstacle.cols() > 0, has_out = out_obstacle.cols() > 0;
  for_each_stencil_hessian(obstacle, points, [&](const Stencil& s, const Matrix12d& H) {
    Vector12d v = Vector12d::Zero();
    v.head<3>() = v_points.col(s.point);
    if (has_v) {
      for (int i = 0; i < s.m; ++i) v.segment<3>(3 * (i + 1)) = v_obstacle.col(s.obstacle_vertex[static_cast<std::size_t>(i)]);
    }
    const Vector12d Hv = H * v;
    out_points.col(s.point) += Hv.head<3>();
    if (!has_out) return;
    for (int i = 0; i < s.m; ++i) out_obstacle.col(s.obstacle_vertex[static_cast<std::size_t>(i)]) += Hv.segment<3>(3 * (i + 1));
  });
}

}  // namespace palpa::contact
