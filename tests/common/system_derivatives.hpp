// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A System's Hessian as a dense symmetric matrix and central differences of
// its gradient, for the derivative tests of every System (any type with
// gradient(x, g) and hessian(x, H) storing the lower triangle).

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "common/finite_difference.hpp"

namespace palpa::test {

template <class System>
Eigen::MatrixXd dense_hessian(const System& system, const Eigen::VectorXd& x) {
  Eigen::SparseMatrix<double> H;
  system.hessian(x, H);
  return Eigen::MatrixXd(Eigen::SparseMatrix<double>(H.template selfadjointView<Eigen::Lower>()));
}

template <class System>
Eigen::MatrixXd fd_hessian(const System& system, const Eigen::VectorXd& x, double h) {
  return fd_jacobian(
      [&](const Eigen::VectorXd& v) {
        Eigen::VectorXd g;
        system.gradient(v, g);
        return g;
      },
      x, h);
}

}  // namespace palpa::test
