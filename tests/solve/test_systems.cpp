// SPDX-License-Identifier: AGPL-3.0-or-later
#include "solve/test_systems.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

namespace palpa::test {

namespace {

constexpr double kRosenbrockA = 100.0;
constexpr std::size_t kGrain = 256;

// Builds a lower-triangle pattern (diagonal, plus the first sub-diagonal if
// `tridiagonal`) into H unless H already has it.
void ensure_banded_pattern(Eigen::SparseMatrix<double>& H, Eigen::Index n, bool tridiagonal) {
  const Eigen::Index nnz = tridiagonal ? 2 * n - 1 : n;
  if (H.rows() == n && H.cols() == n && H.nonZeros() == nnz && H.isCompressed()) return;
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index i = 0; i < n; ++i) {
    t.emplace_back(static_cast<int>(i), static_cast<int>(i), 0.0);
    if (tridiagonal && i + 1 < n) t.emplace_back(static_cast<int>(i + 1), static_cast<int>(i), 0.0);
  }
  H.resize(n, n);
  H.setFromTriplets(t.begin(), t.end());
  H.makeCompressed();
}

}  // namespace

// --- QuadraticSystem ---------------------------------------------------------

QuadraticSystem::QuadraticSystem(Eigen::SparseMatrix<double> A, Eigen::VectorXd b)
    : A_(std::move(A)), b_(std::move(b)) {
  lower_ = A_.triangularView<Eigen::Lower>();
  lower_.makeCompressed();
}

double QuadraticSystem::energy(const Eigen::VectorXd& x) const {
  return 0.5 * x.dot(A_ * x) - b_.dot(x);
}

void QuadraticSystem::gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  g = A_ * x - b_;
}

void QuadraticSystem::hessian(const Eigen::VectorXd& /*x*/, Eigen::SparseMatrix<double>& H) const {
  H = lower_;
}

// --- RosenbrockSystem --------------------------------------------------------

double RosenbrockSystem::energy(const Eigen::VectorXd& x) const {
  double e = 0.0;
  for (Eigen::Index i = 0; i + 1 < n_; ++i) {
    const double u = x[i + 1] - x[i] * x[i];
    const double v = 1.0 - x[i];
    e += kRosenbrockA * u * u + v * v;
  }
  return e;
}

void RosenbrockSystem::gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  g.setZero(n_);
  for (Eigen::Index i = 0; i + 1 < n_; ++i) {
    const double u = x[i + 1] - x[i] * x[i];
    g[i] += -4.0 * kRosenbrockA * x[i] * u - 2.0 * (1.0 - x[i]);
    g[i + 1] += 2.0 * kRosenbrockA * u;
  }
}

void RosenbrockSystem::hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const {
  ensure_banded_pattern(H, n_, true);
  for (Eigen::Index i = 0; i < n_; ++i) {
    double d = 0.0;
    if (i + 1 < n_) d += 12.0 * kRosenbrockA * x[i] * x[i] - 4.0 * kRosenbrockA * x[i + 1] + 2.0;
    if (i > 0) d += 2.0 * kRosenbrockA;
    H.coeffRef(i, i) = d;
    if (i + 1 < n_) H.coeffRef(i + 1, i) = -4.0 * kRosenbrockA * x[i];
  }
}

// --- DoubleWellChain ---------------------------------------------------------

double DoubleWellChain::energy(const Eigen::VectorXd& x) const {
  double e = 0.0;
  for (Eigen::Index i = 0; i < n_; ++i) {
    const double w = x[i] * x[i] - 1.0;
    e += w * w;
    if (i + 1 < n_) e += kappa_ * (x[i + 1] - x[i]) * (x[i + 1] - x[i]);
  }
  return e;
}

void DoubleWellChain::gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  g.resize(n_);
  for (Eigen::Index i = 0; i < n_; ++i) {
    g[i] = 4.0 * x[i] * (x[i] * x[i] - 1.0);
    if (i > 0) g[i] += 2.0 * kappa_ * (x[i] - x[i - 1]);
    if (i + 1 < n_) g[i] -= 2.0 * kappa_ * (x[i + 1] - x[i]);
  }
}

void DoubleWellChain::hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const {
  assemble(x, StandIn::None, H);
}

bool DoubleWellChain::projected_hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const {
  if (stand_in_ == StandIn::None) return false;
  assemble(x, stand_in_, H);
  return true;
}

void DoubleWellChain::assemble(const Eigen::VectorXd& x, StandIn kind, Eigen::SparseMatrix<double>& H) const {
  ensure_banded_pattern(H, n_, true);
  for (Eigen::Index i = 0; i < n_; ++i) {
    double d = 12.0 * x[i] * x[i] - 4.0;
    if (kind == StandIn::Clamp) d = std::max(d, 0.0);
    if (kind == StandIn::Absolute) d = std::abs(d);
    if (i > 0) d += 2.0 * kappa_;
    if (i + 1 < n_) d += 2.0 * kappa_;
    H.coeffRef(i, i) = d;
    if (i + 1 < n_) H.coeffRef(i + 1, i) = -2.0 * kappa_;
  }
}

// --- BarrierSystem -----------------------------------------------------------

double BarrierSystem::energy(const Eigen::VectorXd& x) const {
  if (!admissible(x)) {
    ++inadmissible_energy_;
    return std::numeric_limits<double>::infinity();
  }
  return c_.dot(x) - x.array().log().sum();
}

void BarrierSystem::note_derivative_call(const Eigen::VectorXd& x, bool hessian) const {
  if (!admissible(x)) ++inadmissible_derivative_;
  if (hessian && prepared_.size() == x.size()) {
    max_distance_ = std::max(max_distance_, (x - prepared_).cwiseAbs().maxCoeff());
  }
}

void BarrierSystem::gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  note_derivative_call(x, false);
  g = c_.array() - x.array().inverse();
}

void BarrierSystem::hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const {
  note_derivative_call(x, true);
  ensure_banded_pattern(H, c_.size(), false);
  for (Eigen::Index i = 0; i < c_.size(); ++i) H.coeffRef(i, i) = 1.0 / (x[i] * x[i]);
}

void BarrierSystem::prepare(const Eigen::VectorXd& x) {
  ++prepare_calls_;
  prepared_ = x;
}

// --- ParallelQuarticSystem ---------------------------------------------------

ParallelQuarticSystem::ParallelQuarticSystem(Eigen::VectorXd weights, Eigen::VectorXd targets)
    : w_(std::move(weights)), t_(std::move(targets)) {}

double ParallelQuarticSystem::energy(const Eigen::VectorXd& x) const {
  const auto n = static_cast<std::size_t>(t_.size());
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, n, kGrain), 0.0,
      [&](const tbb::blocked_range<std::size_t>& range, double sum) {
        for (std::size_t k = range.begin(); k != range.end(); ++k) {
          const auto i = static_cast<Eigen::Index>(k);
          const double r = x[i] - t_[i];
          sum += w_[i] * (0.25 * r * r * r * r + 0.5 * r * r);
        }
        return sum;
      },
      [](double a, double b) { return a + b; });
}

void ParallelQuarticSystem::gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  const auto n = static_cast<std::size_t>(t_.size());
  g.resize(t_.size());
  const std::size_t poisoned = n / 2;
  const int call = ++gradient_calls;
  const bool fail = call == fail_at_gradient_call.load();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      if (fail && range.begin() <= poisoned && poisoned < range.end()) {
                        throw std::runtime_error("gradient kernel failed");
                      }
                      for (std::size_t k = range.begin(); k != range.end(); ++k) {
                        const auto i = static_cast<Eigen::Index>(k);
                        const double r = x[i] - t_[i];
                        g[i] = w_[i] * (r * r * r + r);
                      }
                    });
}

void ParallelQuarticSystem::hessian(const Eigen::VectorXd& x,
                                    Eigen::SparseMatrix<double>& H) const {
  ensure_banded_pattern(H, t_.size(), false);
  double* values = H.valuePtr();
  const auto n = static_cast<std::size_t>(t_.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t k = range.begin(); k != range.end(); ++k) {
                        const auto i = static_cast<Eigen::Index>(k);
                        const double r = x[i] - t_[i];
                        values[k] = w_[i] * (3.0 * r * r + 1.0);
                      }
                    });
}

}  // namespace palpa::test
