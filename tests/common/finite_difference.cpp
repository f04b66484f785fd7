// SPDX-License-Identifier: AGPL-3.0-or-later
#include "common/finite_difference.hpp"

#include <cmath>

namespace palpa::test {

namespace {
// Richardson-extrapolated central difference of a vector function along e_j.
Eigen::VectorXd directional(const VectorFunction& g, const Eigen::VectorXd& x, Eigen::Index j,
                            double h) {
  auto central = [&](double step) {
    Eigen::VectorXd xp = x;
    Eigen::VectorXd xm = x;
    xp[j] += step;
    xm[j] -= step;
    return Eigen::VectorXd((g(xp) - g(xm)) / (2.0 * step));
  };
  const Eigen::VectorXd d1 = central(h);
  const Eigen::VectorXd d2 = central(0.5 * h);
  return (4.0 * d2 - d1) / 3.0;
}
}  // namespace

Eigen::VectorXd fd_gradient(const ScalarFunction& f, const Eigen::VectorXd& x, double h) {
  const VectorFunction g = [&](const Eigen::VectorXd& y) {
    return Eigen::VectorXd::Constant(1, f(y));
  };
  Eigen::VectorXd grad(x.size());
  for (Eigen::Index j = 0; j < x.size(); ++j) grad[j] = directional(g, x, j, h)[0];
  return grad;
}

Eigen::MatrixXd fd_jacobian(const VectorFunction& g, const Eigen::VectorXd& x, double h) {
  Eigen::MatrixXd jac;
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    const Eigen::VectorXd col = directional(g, x, j, h);
    if (j == 0) jac.resize(col.size(), x.size());
    jac.col(j) = col;
  }
  return jac;
}

::testing::AssertionResult derivatives_match(const Eigen::MatrixXd& analytic,
                                             const Eigen::MatrixXd& numeric, double rel_tol,
                                             ZeroPolicy zero, double reference) {
  if (analytic.rows() != numeric.rows() || analytic.cols() != numeric.cols()) {
    return ::testing::AssertionFailure() << "shape " << analytic.rows() << "x" << analytic.cols()
                                         << " vs finite differences " << numeric.rows() << "x"
                                         << numeric.cols();
  }
  if (!analytic.allFinite()) return ::testing::AssertionFailure() << "analytic value not finite";
  if (!numeric.allFinite()) return ::testing::AssertionFailure() << "finite differences not finite";
  const double magnitude = std::max(analytic.cwiseAbs().maxCoeff(), numeric.cwiseAbs().maxCoeff());
  const double scale = std::max(magnitude, reference);
  if (magnitude == 0.0) {
    if (zero == ZeroPolicy::MayBeZero) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "derivative is exactly zero: the test would not catch errors";
  }
  const double err = (analytic - numeric).cwiseAbs().maxCoeff();
  if (err <= rel_tol * scale) {
    return ::testing::AssertionSuccess() << "relative error " << err / scale;
  }
  Eigen::Index r = 0;
  Eigen::Index c = 0;
  (analytic - numeric).cwiseAbs().maxCoeff(&r, &c);
  return ::testing::AssertionFailure()
         << "relative error " << err / scale << " > " << rel_tol << " (scale " << scale
         << "); worst entry (" << r << "," << c << "): analytic " << analytic(r, c) << " vs fd "
         << numeric(r, c);
}

}  // namespace palpa::test
