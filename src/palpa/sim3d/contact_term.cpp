// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/sim3d/contact_term.hpp"

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <fmt/format.h>

#include "palpa/core/error.hpp"
#include "palpa/geometry/surface_operators.hpp"

namespace palpa::sim3d {

namespace {

contact::Points as_points(const Eigen::VectorXd& x) {
  return Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, x.size() / 3);
}

class Timer {
 public:
  Timer(std::atomic<std::int64_t>& ns, std::atomic<std::int64_t>& count)
      : ns_(ns), count_(count), start_(std::chrono::steady_clock::now()) {}
  ~Timer() {
    ns_ += std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start_).count();
    ++count_;
  }
  Timer(const Timer&) = delete;
  Timer& operator=(const Timer&) = delete;

 private:
  std::atomic<std::int64_t>& ns_;
  std::atomic<std::int64_t>& count_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

RigidContactTerm::RigidContactTerm(const contact::Obstacle& obstacle, const Eigen::MatrixX3d& rest,
                                   Eigen::MatrixX3i faces, double k)
    : obstacle_(&obstacle), faces_(std::move(faces)), k_(0.0) {
  set_stiffness(k);
  skin_area_ = geometry::vertex_areas(rest, faces_);
  face_area_ = geometry::face_areas(rest, faces_);
  std::vector<char> on(static_cast<std::size_t>(rest.rows()), 0);
  for (Eigen::Index f = 0; f < faces_.rows(); ++f) {
    for (int c = 0; c < 3; ++c) on[static_cast<std::size_t>(faces_(f, c))] = 1;
  }
  for (std::size_t v = 0; v < on.size(); ++v) {
    if (on[v]) {
      surface_.push_back(static_cast<int>(v));
      mean_area_ += skin_area_[static_cast<Eigen::Index>(v)];
    }
  }
  if (surface_.empty()) throw Error(ErrorKind::Input, fmt::format("{}: the body has no skin to touch it", obstacle_->name()));
  mean_area_ /= static_cast<double>(surface_.size());
  area_.assign(skin_area_.data(), skin_area_.data() + skin_area_.size());
  scale_.resize(area_.size());
  for (std::size_t v = 0; v < area_.size(); ++v) scale_[v] = area_[v] / mean_area_;
  committed_.set_scale(scale_);
}

void RigidContactTerm::set_stiffness(double k) {
  if (!std::isfinite(k) || !(k > 0.0)) {
    throw Error(ErrorKind::Input, fmt::format("{}: contact stiffness must be > 0 N/m, got {}", obstacle_->name(), k));
  }
  k_ = k;
}

double RigidContactTerm::energy(const Eigen::VectorXd& x) const {
  const Timer t(detection_ns_, detections_);
  return contact::detected_energy(*obstacle_, as_points(x), surface_, k_, scale_);
}

double RigidContactTerm::add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  if (committed_.empty()) return 0.0;
  Eigen::Map<Eigen::Matrix3Xd> grad(g.data(), 3, g.size() / 3);
  committed_.add_gradient(*obstacle_, as_points(x), k_, grad);
  return committed_.energy(*obstacle_, as_points(x), k_);
}

void RigidContactTerm::add_hessian(const Eigen::VectorXd&, bool,
                                   std::vector<std::pair<int, Eigen::Matrix3d>>& blocks) const {
  // 2k P⊥ is the true Hessian of the committed energy in p (positive
  // semi-definite), so both modes use it.
  for (const contact::Contact& c : committed_.contacts()) {
    blocks.emplace_back(c.point, contact::hessian_block(*obstacle_, c, committed_.stiffness_of(c, k_)));
  }
}

void RigidContactTerm::prepare(const Eigen::VectorXd& x) {
  const Timer t(detection_ns_, detections_);
  committed_.detect(*obstacle_, as_points(x), surface_);
}

double RigidContactTerm::update_areas(double min_change) {
  // The full skin share off contact; in contact, the share of the triangles
  // wholly in contact (the full share if there is none).
  std::vector<char> touching(area_.size(), 0);
  for (const contact::Contact& c : committed_.contacts()) touching[static_cast<std::size_t>(c.point)] = 1;
  std::vector<double> contact_area(area_.size(), 0.0);
  for (Eigen::Index f = 0; f < faces_.rows(); ++f) {
    const int a = faces_(f, 0), b = faces_(f, 1), c = faces_(f, 2);
    if (!touching[static_cast<std::size_t>(a)] || !touching[static_cast<std::size_t>(b)] ||
        !touching[static_cast<std::size_t>(c)]) {
      continue;
    }
    const double third = face_area_[f] / 3.0;
    contact_area[static_cast<std::size_t>(a)] += third;
    contact_area[static_cast<std::size_t>(b)] += third;
    contact_area[static_cast<std::size_t>(c)] += third;
  }
  std::vector<double> next(area_.size());
  double changed = 0.0, total = 0.0;
  for (std::size_t v = 0; v < area_.size(); ++v) {
    next[v] = touching[v] && contact_area[v] > 0.0 ? contact_area[v] : skin_area_[static_cast<Eigen::Index>(v)];
    const double d = std::abs(next[v] - area_[v]);
    if (d > 1e-9 * mean_area_) changed += d;
    if (touching[v]) total += next[v];
  }
  // Relative to the area in contact (to the mean share when nothing touches).
  const double change = changed / std::max(total, mean_area_);
  if (!(change > min_change)) return 0.0;
  area_ = next;
  for (std::size_t v = 0; v < area_.size(); ++v) scale_[v] = area_[v] / mean_area_;
  committed_.set_scale(scale_);
  return change;
}

void RigidContactTerm::set_areas(const std::vector<double>& areas) {
  if (areas.size() != area_.size()) {
    throw Error(ErrorKind::Input, fmt::format("{}: {} saved spring areas for {} vertices", obstacle_->name(),
                                              areas.size(), area_.size()));
  }
  for (int v : surface_) {
    const double a = areas[static_cast<std::size_t>(v)];
    if (!std::isfinite(a) || !(a > 0.0)) {
      throw Error(ErrorKind::Input, fmt::format("{}: saved spring area of vertex {} is {}", obstacle_->name(), v, a));
    }
  }
  area_ = areas;
  for (std::size_t v = 0; v < area_.size(); ++v) scale_[v] = area_[v] / mean_area_;
  committed_.set_scale(scale_);
}

Eigen::VectorXd RigidContactTerm::pressures(const Eigen::VectorXd& x) const {
  const Eigen::Matrix3Xd f = vertex_forces(x);
  Eigen::VectorXd p = Eigen::VectorXd::Zero(f.cols());
  for (Eigen::Index v = 0; v < f.cols(); ++v) {
    if (area_[static_cast<std::size_t>(v)] > 0.0) p[v] = f.col(v).norm() / area_[static_cast<std::size_t>(v)];
  }
  return p;
}

Eigen::Matrix3Xd RigidContactTerm::vertex_forces(const Eigen::VectorXd& x) const {
  Eigen::Matrix3Xd f;
  committed_.forces(*obstacle_, as_points(x), k_, f);
  return f;
}

contact::Wrench RigidContactTerm::obstacle_wrench(const Eigen::VectorXd& x, const Eigen::Vector3d& about) const {
  return committed_.obstacle_wrench(*obstacle_, as_points(x), k_, about);
}

}  // namespace palpa::sim3d
