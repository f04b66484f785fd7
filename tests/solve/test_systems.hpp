// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Small analytic Systems for the Newton tests, each with a known minimizer.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <atomic>

#include "palpa/solve/system.hpp"

namespace palpa::test {

// E = ½ xᵀ A x − bᵀ x, A SPD (both triangles stored). Minimizer A⁻¹ b.
class QuadraticSystem final : public System {
 public:
  QuadraticSystem(Eigen::SparseMatrix<double> A, Eigen::VectorXd b);
  Eigen::Index num_dofs() const override { return b_.size(); }
  double energy(const Eigen::VectorXd& x) const override;
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  void hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const override;

 private:
  Eigen::SparseMatrix<double> A_;
  Eigen::SparseMatrix<double> lower_;
  Eigen::VectorXd b_;
};

// The n-D (chained) Rosenbrock function
//   E = Σ_{i<n−1} 100 (x_{i+1} − x_i²)² + (1 − x_i)²,
// minimum 0 at x = (1, ..., 1). Tridiagonal Hessian, indefinite in places.
class RosenbrockSystem final : public System {
 public:
  explicit RosenbrockSystem(Eigen::Index n) : n_(n) {}
  Eigen::Index num_dofs() const override { return n_; }
  double energy(const Eigen::VectorXd& x) const override;
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  void hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const override;

 private:
  Eigen::Index n_;
};

// A chain of double wells: E = Σ (x_i² − 1)² + κ Σ (x_{i+1} − x_i)².
// Hessian diag 12 x_i² − 4 (+ coupling): indefinite for |x_i| < 1/√3.
// Minima: all x_i = 1 or all x_i = −1 (energy 0).
class DoubleWellChain final : public System {
 public:
  DoubleWellChain(Eigen::Index n, double coupling) : n_(n), kappa_(coupling) {}
  Eigen::Index num_dofs() const override { return n_; }
  double energy(const Eigen::VectorXd& x) const override;
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  void hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const override;
  // A PSD stand-in (the coupling is PSD): each well's curvature clamped at 0,
  // or its absolute value (which, near the wells' maxima, overestimates the
  // curvature and makes steps that hardly cut the gradient).
  enum class StandIn { None, Clamp, Absolute };
  bool projected_hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const override;
  void offer_projected_hessian(StandIn kind) { stand_in_ = kind; }

 private:
  void assemble(const Eigen::VectorXd& x, StandIn kind, Eigen::SparseMatrix<double>& H) const;
  Eigen::Index n_;
  double kappa_;
  StandIn stand_in_ = StandIn::None;
};

// E = Σ c_i x_i − ln x_i, +inf unless every x_i > 0. Minimizer x_i = 1/c_i.
// From x_i > 2/c_i the full Newton step lands at x_i < 0. Counts what the
// solver did so a test can check it never asked for derivatives at an
// inadmissible point.
class BarrierSystem final : public System {
 public:
  explicit BarrierSystem(Eigen::VectorXd c) : c_(std::move(c)) {}
  Eigen::Index num_dofs() const override { return c_.size(); }
  double energy(const Eigen::VectorXd& x) const override;
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  void hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const override;
  void prepare(const Eigen::VectorXd& x) override;

  int inadmissible_energy_calls() const noexcept { return inadmissible_energy_.load(); }
  int inadmissible_derivative_calls() const noexcept { return inadmissible_derivative_.load(); }
  int prepare_calls() const noexcept { return prepare_calls_; }
  // Largest |x − last prepared x| over Hessian calls (0 if the solver only asks
  // for Hessians where it prepared).
  double hessian_distance_from_prepared() const noexcept { return max_distance_; }

 private:
  bool admissible(const Eigen::VectorXd& x) const { return (x.array() > 0.0).all(); }
  void note_derivative_call(const Eigen::VectorXd& x, bool hessian) const;

  Eigen::VectorXd c_;
  // Test instrumentation only (a real system keeps no per-call state).
  mutable std::atomic<int> inadmissible_energy_{0};
  mutable std::atomic<int> inadmissible_derivative_{0};
  int prepare_calls_ = 0;
  Eigen::VectorXd prepared_;
  mutable double max_distance_ = 0.0;
};

// E = Σ w_i ((x_i − t_i)⁴/4 + (x_i − t_i)²/2), evaluated in TBB parallel loops.
// Minimizer x = t. The gradient call number fail_at_gradient_call (1-based; 0:
// never) throws std::runtime_error from one worker of its parallel loop.
class ParallelQuarticSystem final : public System {
 public:
  ParallelQuarticSystem(Eigen::VectorXd weights, Eigen::VectorXd targets);
  Eigen::Index num_dofs() const override { return t_.size(); }
  double energy(const Eigen::VectorXd& x) const override;
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  void hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const override;

  std::atomic<int> fail_at_gradient_call{0};
  mutable std::atomic<int> gradient_calls{0};

 private:
  Eigen::VectorXd w_;
  Eigen::VectorXd t_;
};

}  // namespace palpa::test

#include <gtest/gtest.h>

#include <string>

#include "palpa/solve/newton.hpp"

namespace palpa::test {

// Test-name suffix for tests parameterized over line-search kinds.
inline std::string line_search_test_name(const ::testing::TestParamInfo<LineSearchKind>& p) {
  switch (p.param) {
    case LineSearchKind::Backtracking:
      return "Backtracking";
    case LineSearchKind::Brent:
      return "Brent";
    case LineSearchKind::GoldenSection:
      return "GoldenSection";
    case LineSearchKind::BacktrackingThenBrent:
      break;
  }
  return "BacktrackingThenBrent";
}

}  // namespace palpa::test
