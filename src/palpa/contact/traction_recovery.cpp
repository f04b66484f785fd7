// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/contact/traction_recovery.hpp"

#include <cassert>
#include <cmath>
#include <fmt/format.h>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include "palpa/core/error.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/geometry/umbrella.hpp"

namespace palpa::contact {

namespace {

// φ(q) = (1 − q²)² and its derivative.
double kernel(double q) { return q < 1.0 ? (1.0 - q * q) * (1.0 - q * q) : 0.0; }
double kernel_derivative(double q) { return q < 1.0 ? -4.0 * q * (1.0 - q * q) : 0.0; }

}  // namespace

TractionRecovery::TractionRecovery(Eigen::MatrixX3i F, Eigen::Index n, double radius)
    : F_(std::move(F)), n_(n), radius_(radius) {
  if (!(radius >= 0.0) || !std::isfinite(radius)) {
    throw Error(ErrorKind::Input, fmt::format("a pressure footprint must be a finite radius ≥ 0 m, got {}", radius));
  }
  if (F_.size() > 0 && (F_.minCoeff() < 0 || F_.maxCoeff() >= n)) {
    throw Error(ErrorKind::Input, fmt::format("a triangle's vertex lies outside the surface's {} vertices", n));
  }
  if (radius_ > 0.0) neighbours_ = geometry::vertex_neighbours(F_, n_);
}

TractionRecovery::Reach TractionRecovery::reach(const Eigen::MatrixX3d& V, int k, std::vector<double>& path) const {
  // Dijkstra along edges from k, no farther than 2r; the weights from the
  // straight distances. path: +∞ for every vertex, and so again on return.
  Reach r;
  const double limit = 2.0 * radius_;
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  std::vector<int> touched{k};
  path[static_cast<std::size_t>(k)] = 0.0;
  queue.emplace(0.0, k);
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > path[static_cast<std::size_t>(v)]) continue;
    for (int u : neighbours_[static_cast<std::size_t>(v)]) {
      const double du = d + (V.row(u) - V.row(v)).norm();
      double& known = path[static_cast<std::size_t>(u)];
      if (du > limit || du >= known) continue;
      if (known == std::numeric_limits<double>::infinity()) touched.push_back(u);
      known = du;
      queue.emplace(du, u);
    }
  }
  for (int u : touched) {
    path[static_cast<std::size_t>(u)] = std::numeric_limits<double>::infinity();
    const double w = kernel((V.row(u) - V.row(k)).norm() / radius_);
    if (w <= 0.0) continue;
    r.vertex.push_back(u);
    r.weight.push_back(w);
  }
  return r;
}

template <class Fn>
void TractionRecovery::for_each_source(const Eigen::MatrixX3d& V, const Eigen::VectorXd& F, const Eigen::VectorXd& A,
                                       Fn&& fn) const {
  std::vector<double> path(radius_ > 0.0 ? static_cast<std::size_t>(n_) : 0, std::numeric_limits<double>::infinity());
  for (Eigen::Index k = 0; k < n_; ++k) {
    if (F[k] == 0.0 || !(A[k] > 0.0)) continue;
    const Reach r = radius_ > 0.0 ? reach(V, static_cast<int>(k), path) : Reach{{static_cast<int>(k)}, {1.0}};
    double W = 0.0;
    for (std::size_t i = 0; i < r.vertex.size(); ++i) W += r.weight[i] * A[r.vertex[i]];
    fn(static_cast<int>(k), r, W);
  }
}

Eigen::VectorXd TractionRecovery::recover(const Eigen::MatrixX3d& V, const Eigen::VectorXd& F) const {
  assert(V.rows() == n_ && F.size() == n_);
  Eigen::VectorXd p = Eigen::VectorXd::Zero(n_);
  for_each_source(V, F, geometry::vertex_areas(V, F_), [&](int k, const Reach& r, double W) {
    for (std::size_t i = 0; i < r.vertex.size(); ++i) p[r.vertex[i]] += r.weight[i] * F[k] / W;
  });
  return p;
}

void TractionRecovery::add_pullback(const Eigen::MatrixX3d& V, const Eigen::VectorXd& F, const Eigen::VectorXd& g,
                                    Eigen::VectorXd& d_force, Eigen::MatrixX3d& d_position) const {
  assert(V.rows() == n_ && F.size() == n_ && g.size() == n_ && d_force.size() == n_ && d_position.rows() == n_);
  const Eigen::VectorXd A = geometry::vertex_areas(V, F_);
  Eigen::VectorXd d_area = Eigen::VectorXd::Zero(n_);
  for_each_source(V, F, A, [&](int k, const Reach& r, double W) {
    double gw = 0.0;
    for (std::size_t i = 0; i < r.vertex.size(); ++i) gw += g[r.vertex[i]] * r.weight[i];
    // p_j = w_jk F_k / W_k: ∂/∂F_k = gw / W; ∂/∂W_k = −gw F_k / W² =: λ.
    d_force[k] += gw / W;
    const double lambda = -gw * F[k] / (W * W);
    for (std::size_t i = 0; i < r.vertex.size(); ++i) {
      const int j = r.vertex[i];
      d_area[j] += lambda * r.weight[i];
      if (j == k) continue;
      // ∂/∂w_jk, then through w_jk = φ(|V_j − V_k| / r).
      const double dw = g[j] * F[k] / W + lambda * A[j];
      const Eigen::RowVector3d e = V.row(j) - V.row(k);
      const double d = e.norm();
      const Eigen::RowVector3d dd = kernel_derivative(d / radius_) / (radius_ * d) * e;
      d_position.row(j) += dw * dd;
      d_position.row(k) -= dw * dd;
    }
  });
  geometry::add_vertex_area_gradient(V, F_, d_area, d_position);
}

}  // namespace palpa::contact
