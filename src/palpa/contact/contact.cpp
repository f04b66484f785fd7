// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/contact/contact.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cassert>
#include <functional>
#include <numeric>

#include "palpa/core/error.hpp"

namespace palpa::contact {

namespace {

// Points per task of the parallel loops: a closest-point query costs ~1 µs.
constexpr std::size_t kGrain = 256;

Eigen::Vector3d point_of(Points points, int column) {
  return points.col(column);
}

}  // namespace

FeatureGeometry feature_geometry(const Obstacle& obstacle, const ClosestPoint& closest) {
  FeatureGeometry g;
  g.m = feature_size(closest.feature);
  for (int i = 0; i < g.m; ++i) {
    g.q[static_cast<std::size_t>(i)] =
        obstacle.world_vertex(closest.vertices[static_cast<std::size_t>(i)]);
  }
  return g;
}

Eigen::Matrix3d hessian_block(const Obstacle& obstacle, const Contact& contact, double k) {
  return penalty_hessian(feature_geometry(obstacle, contact.closest), k);
}

double detected_energy(const Obstacle& obstacle, Points points, std::span<const int> which,
                       double k, std::span<const double> scale) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, which.size(), kGrain), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double sum) {
        ClosestPoint c;
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          if (obstacle.penetration(point_of(points, which[i]), c)) {
            const double ki = scale.empty() ? k : k * scale[static_cast<std::size_t>(which[i])];
            sum += ki * c.distance * c.distance;
          }
        }
        return sum;
      },
      std::plus<>());
}

void ContactSet::detect(const Obstacle& obstacle, Points points, std::span<const int> which) {
  assert(
      std::all_of(which.begin(), which.end(), [&](int i) { return i >= 0 && i < points.cols(); }));
  slot_.resize(which.size());
  hit_.resize(which.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, which.size(), kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) {
                        hit_[i] =
                            obstacle.penetration(point_of(points, which[i]), slot_[i]) ? 1 : 0;
                      }
                    });
  contacts_.clear();
  for (std::size_t i = 0; i < which.size(); ++i) {
    if (hit_[i] != 0) contacts_.push_back({which[i], slot_[i]});
  }
}

void ContactSet::detect(const Obstacle& obstacle, Points points) {
  if (all_.size() != static_cast<std::size_t>(points.cols())) {
    all_.resize(static_cast<std::size_t>(points.cols()));
    std::iota(all_.begin(), all_.end(), 0);
  }
  detect(obstacle, points, all_);
}

void ContactSet::set_scale(std::vector<double> scale) { scale_ = std::move(scale); }

double ContactSet::stiffness_of(const Contact& c, double k) const {
  return scale_.empty() ? k : k * scale_[static_cast<std::size_t>(c.point)];
}

double ContactSet::max_depth() const {
  double m = 0.0;
  for (const Contact& c : contacts_) m = std::max(m, c.closest.distance);
  return m;
}

double ContactSet::energy(const Obstacle& obstacle, Points points, double k) const {
  double e = 0.0;
  for (const Contact& c : contacts_) {
    e += penalty_energy(point_of(points, c.point), feature_geometry(obstacle, c.closest), stiffness_of(c, k));
  }
  return e;
}

void ContactSet::add_gradient(const Obstacle& obstacle, Points points, double k,
                              Eigen::Ref<Eigen::Matrix3Xd> grad) const {
  assert(grad.cols() == points.cols());
  for (const Contact& c : contacts_) {
    grad.col(c.point) += penalty_gradient(point_of(points, c.point), feature_geometry(obstacle, c.closest),
                                          stiffness_of(c, k));
  }
}

void ContactSet::add_obstacle_gradient(const Obstacle& obstacle, Points points, double k,
                                       Eigen::Ref<Eigen::Matrix3Xd> grad) const {
  assert(grad.cols() == obstacle.vertices().rows());
  for (const Contact& c : contacts_) {
    const FeatureGeometry g = feature_geometry(obstacle, c.closest);
    const Vector12d full = penalty_gradient_full(point_of(points, c.point), g, stiffness_of(c, k));
    for (int i = 0; i < g.m; ++i) {
      grad.col(c.closest.vertices[static_cast<std::size_t>(i)]) += full.segment<3>(3 * (i + 1));
    }
  }
}

void ContactSet::forces(const Obstacle& obstacle, Points points, double k,
                        Eigen::Matrix3Xd& forces) const {
  forces.setZero(3, points.cols());
  for (const Contact& c : contacts_) {
    forces.col(c.point) -= penalty_gradient(point_of(points, c.point), feature_geometry(obstacle, c.closest),
                                            stiffness_of(c, k));
  }
}

Wrench ContactSet::obstacle_wrench(const Obstacle& obstacle, Points points, double k,
                                   const Eigen::Vector3d& about) const {
  Wrench w;
  for (const Contact& c : contacts_) {
    const Eigen::Vector3d p = point_of(points, c.point);
    const FeatureGeometry g = feature_geometry(obstacle, c.closest);
    const Eigen::Vector3d a = sliding_anchor(p, g).point;
    const Eigen::Vector3d reaction = 2.0 * stiffness_of(c, k) * (p - a);  // −f
    w.force += reaction;
    w.torque += (a - about).cross(reaction);
  }
  return w;
}

Eigen::VectorXd pressures(const Eigen::Matrix3Xd& forces, const Eigen::VectorXd& areas) {
  assert(areas.size() == forces.cols());
  Eigen::VectorXd p = Eigen::VectorXd::Zero(forces.cols());
  for (Eigen::Index i = 0; i < forces.cols(); ++i) {
    if (areas[i] > 0.0) p[i] = forces.col(i).norm() / areas[i];
  }
  return p;
}

double stiffness_for_penetration(double load, double contact_points, double target) {
  if (!(load > 0.0) || !(contact_points > 0.0) || !(target > 0.0)) {
    throw_input_error(
        fmt::format("cannot choose a contact stiffness from load {} N, {} contact points and "
                    "target penetration {} m",
                    load, contact_points, target),
        ErrorContext{}.with_field("contact stiffness"), "positive load, point count and target");
  }
  return load / (2.0 * contact_points * target);
}

double corrected_stiffness(double k, double max_depth, double target, double max_factor) {
  assert(k > 0.0 && target > 0.0 && max_factor >= 1.0);
  if (!(max_depth > 0.0)) return k;  // no contact: nothing to learn from
  return k * std::clamp(max_depth / target, 1.0 / max_factor, max_factor);
}

}  // namespace palpa::contact
