// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/fit/coordinates.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "palpa/core/error.hpp"

namespace palpa::fit {

Coordinates::Coordinates(const material::Material& start, const std::vector<std::string>& fixed, double mu0)
    : theta0_(start.params()) {
  for (const auto& name : fixed) {
    bool found = false;
    for (Eigen::Index k = 0; k < start.num_params(); ++k) found |= start.param_info(k).name == name;
    if (!found) {
      std::string names;
      for (Eigen::Index k = 0; k < start.num_params(); ++k) names += (k ? ", " : "") + start.param_info(k).name;
      throw_input_error(fmt::format("model {} has no parameter '{}'", start.model(), name),
                        ErrorContext{"", 0, 0, "fix"}, fmt::format("one of {}", names));
    }
  }
  for (Eigen::Index k = 0; k < start.num_params(); ++k) {
    const material::ParamInfo info = start.param_info(k);
    if (std::find(fixed.begin(), fixed.end(), info.name) != fixed.end()) continue;
    param_.push_back(k);
    const double v = std::abs(theta0_[k]);
    double s = 1.0;
    switch (info.dimension) {
      case Dimension::Pressure: s = std::max(v, mu0); break;
      case Dimension::Compliance: s = v > 0.0 ? v : 1.0 / mu0; break;
      default: s = std::max(v, 0.1); break;
    }
    scale_.push_back(s);
    // Bounds of the ratios that have a closed range.
    double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    if (info.name == "nu") {
      lo = -0.9;
      hi = 0.4999;
    } else if (info.name == "volume_share") {
      lo = 0.0;
      hi = 1.0;
    } else if (info.dimension == Dimension::Compliance || info.name == "E" || info.name == "C10") {
      lo = 1e-6 * v;
    }
    lower_.push_back(lo / s);
    upper_.push_back(hi / s);
  }
  if (param_.empty()) {
    throw_input_error("every parameter is fixed", ErrorContext{"", 0, 0, "fix"}, "at least one free parameter");
  }
}

Eigen::VectorXd Coordinates::start() const {
  Eigen::VectorXd x(size());
  for (std::size_t i = 0; i < param_.size(); ++i) x[static_cast<Eigen::Index>(i)] = theta0_[param_[i]] / scale_[i];
  return x;
}

Eigen::VectorXd Coordinates::theta(const Eigen::VectorXd& x) const {
  Eigen::VectorXd t = theta0_;
  for (std::size_t i = 0; i < param_.size(); ++i) t[param_[i]] = x[static_cast<Eigen::Index>(i)] * scale_[i];
  return t;
}

Eigen::MatrixXd Coordinates::dtheta_dx(const Eigen::VectorXd& /*x*/) const {
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(theta0_.size(), size());
  for (std::size_t i = 0; i < param_.size(); ++i) j(param_[i], static_cast<Eigen::Index>(i)) = scale_[i];
  return j;
}

}  // namespace palpa::fit
