#include "palpa/sim3d/contact_term.hpp"

#include <chrono>
#include <cmath>
#include <fmt/format.h>

#include "palpa/core/error.hpp"

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

RigidContactTerm::RigidContactTerm(const contact::Obstacle& obstacle, std::vector<int> surface, double k)
    : obstacle_(&obstacle), surface_(std::move(surface)), k_(0.0) {
  set_stiffness(k);
}

void RigidContactTerm::set_stiffness(double k) {
  if (!std::isfinite(k) || !(k > 0.0)) {
    throw Error(ErrorKind::Input, fmt::format("{}: contact stiffness must be > 0 N/m, got {}", obstacle_->name(), k));
  }
  k_ = k;
}

double RigidContactTerm::energy(const Eigen::VectorXd& x) const {
  const Timer t(detection_ns_, detections_);
  return contact::detected_energy(*obstacle_, as_points(x), surface_, k_);
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
    blocks.emplace_back(c.point, contact::hessian_block(*obstacle_, c, k_));
  }
}

void RigidContactTerm::prepare(const Eigen::VectorXd& x) {
  const Timer t(detection_ns_, detections_);
  committed_.detect(*obstacle_, as_points(x), surface_);
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
