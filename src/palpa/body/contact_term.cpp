// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/body/contact_term.hpp"

#include "palpa/contact/traction_recovery.hpp"

#include <algorithm>
#include <chrono>

namespace palpa::body {

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

namespace {

contact::ContactSamples samples_of(ContactSampling sampling, const Eigen::MatrixX3d& rest,
                                   const contact::SpringAreas& areas, int subdivisions) {
  if (sampling == ContactSampling::Vertices) return contact::vertex_samples(areas.surface(), areas.skin_areas());
  return contact::surface_samples(rest, areas.faces(), contact::subdivision_rule(subdivisions));
}

}  // namespace

ContactTerm::ContactTerm(const contact::Obstacle& obstacle, const Eigen::MatrixX3d& rest, Eigen::MatrixX3i faces,
                         double k, ContactSampling sampling, int subdivisions)
    : obstacle_(&obstacle),
      sampling_(sampling),
      areas_(rest, std::move(faces), obstacle.name()),
      potential_(samples_of(sampling, rest, areas_, subdivisions), k, obstacle.name()) {
  rescale();
}

void ContactTerm::rescale() {
  if (sampling_ == ContactSampling::Surface) return;
  // Sample s sits on skin vertex surface()[s].
  const std::vector<int>& surface = areas_.surface();
  std::vector<double> scale(surface.size());
  for (std::size_t s = 0; s < surface.size(); ++s) scale[s] = areas_.scale()[static_cast<std::size_t>(surface[s])];
  potential_.set_scale(std::move(scale));
}

double ContactTerm::energy(const VertexState& s) const { return detected_energy(*obstacle_, s.p); }

double ContactTerm::detected_energy(const contact::Obstacle& obstacle, const Eigen::VectorXd& p) const {
  const Timer t(detection_ns_, detections_);
  return potential_.detected_energy(obstacle, as_points(p));
}

double ContactTerm::add_gradient(const VertexState& s, Eigen::VectorXd& g) const {
  if (potential_.empty()) return 0.0;
  Eigen::Map<Eigen::Matrix3Xd> grad(g.data(), 3, g.size() / 3);
  potential_.add_gradient(*obstacle_, as_points(s.p), grad);
  return potential_.energy(*obstacle_, as_points(s.p));
}

void ContactTerm::add_blocks(const VertexState&, PsdProjection, std::vector<VertexBlock>& blocks) const {
  // N_a N_b 2k P⊥ is the true Hessian of the committed energy over the skin
  // (positive semi-definite), so both modes use it.
  potential_.for_each_surface_hessian(*obstacle_, [&](int a, int b, const Eigen::Matrix3d& block) {
    blocks.push_back({a, b, block});
  });
}

std::vector<std::array<int, 2>> ContactTerm::vertex_pairs() const {
  if (sampling_ == ContactSampling::Vertices) return {};
  std::vector<std::array<int, 2>> pairs;
  const Eigen::MatrixX3i& F = areas_.faces();
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int a = F(f, c), b = F(f, (c + 1) % 3);
      pairs.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

void ContactTerm::prepare(const VertexState& s) {
  const Timer t(detection_ns_, detections_);
  potential_.commit(*obstacle_, as_points(s.p));
}

int ContactTerm::anchor(const Eigen::VectorXd& x, const Eigen::VectorXd& reference,
                        const contact::Pose& reference_pose) {
  const Timer t(detection_ns_, detections_);
  return potential_.anchor(*obstacle_, as_points(x), as_points(reference), reference_pose);
}

double ContactTerm::update_areas(double min_change) {
  if (sampling_ == ContactSampling::Surface) return 0.0;
  std::vector<int> touching;
  touching.reserve(potential_.size());
  for (const contact::SampleContact& c : potential_.contacts()) touching.push_back(areas_.surface()[static_cast<std::size_t>(c.sample)]);
  const double change = areas_.update(touching, min_change);
  if (change > 0.0) rescale();
  return change;
}

void ContactTerm::set_areas(const std::vector<double>& areas) {
  areas_.set(areas);
  rescale();
}

Eigen::Matrix3Xd ContactTerm::vertex_forces(const Eigen::VectorXd& x) const {
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.size() / 3);
  Eigen::Matrix3Xd none(3, 0);
  potential_.add_forces(*obstacle_, as_points(x), f, none);
  return f;
}

Eigen::VectorXd ContactTerm::pressures(const Eigen::VectorXd& x) const {
  const Eigen::Matrix3Xd f = vertex_forces(x);
  const Eigen::MatrixX3d V = as_points(x).transpose();
  const Eigen::VectorXd F = f.colwise().norm().transpose();
  return contact::TractionRecovery(areas_.faces(), V.rows(), 0.0).recover(V, F);
}

contact::Wrench ContactTerm::obstacle_wrench(const Eigen::VectorXd& x, const Eigen::Vector3d& about) const {
  return potential_.obstacle_wrench(*obstacle_, as_points(x), about);
}

}  // namespace palpa::body
