// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/solve/so3.hpp"

#include <cmath>

namespace palpa {

Eigen::Matrix3d hat(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0;
  return m;
}

Eigen::Matrix3d exp_so3(const Eigen::Vector3d& w) {
  const double t2 = w.squaredNorm();
  const Eigen::Matrix3d K = hat(w);
  double a, b;
  if (t2 < 1e-12) {
    a = 1.0 - t2 / 6.0;
    b = 0.5 - t2 / 24.0;
  } else {
    const double t = std::sqrt(t2);
    a = std::sin(t) / t;
    b = (1.0 - std::cos(t)) / t2;
  }
  return Eigen::Matrix3d::Identity() + a * K + b * K * K;
}

Eigen::Matrix3d left_jacobian_so3(const Eigen::Vector3d& w) {
  const double t2 = w.squaredNorm();
  const Eigen::Matrix3d K = hat(w);
  double a, b;
  if (t2 < 1e-12) {
    a = 0.5 - t2 / 24.0;
    b = 1.0 / 6.0 - t2 / 120.0;
  } else {
    const double t = std::sqrt(t2);
    a = (1.0 - std::cos(t)) / t2;
    b = (t - std::sin(t)) / (t2 * t);
  }
  return Eigen::Matrix3d::Identity() + a * K + b * K * K;
}

}  // namespace palpa
