// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/fit/coordinates.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "palpa/core/error.hpp"

namespace palpa::fit {

namespace {

double logit(double p) { return std::log(p / (1.0 - p)); }

}  // namespace

Coordinates::Coordinates(const material::Material& start, const std::vector<std::string>& fixed, double mu0,
                         PoissonRange nu)
    : theta0_(start.params()), nu_(nu) {
  if (!(nu.lo > -1.0 && nu.lo < nu.hi && nu.hi < 0.5)) {
    throw_input_error(fmt::format("Poisson's ratio range {}:{}", nu.lo, nu.hi), ErrorContext{"", 0, 0, "nu-range"},
                      "LO:HI with -1 < LO < HI < 0.5");
  }
  const auto is_fixed = [&](const std::string& name) {
    return std::find(fixed.begin(), fixed.end(), name) != fixed.end();
  };
  Eigen::Index k_nu = -1, k_d1 = -1;
  for (Eigen::Index k = 0; k < start.num_params(); ++k) {
    const material::ParamInfo info = start.param_info(k);
    if (info.name == "nu") k_nu = k;
    if (info.name == "D1" && info.dimension == Dimension::Compliance) k_d1 = k;
  }
  // D1 follows the moduli when μ0 is linear in them (the isochoric models).
  if (k_nu < 0 && k_d1 >= 0 && !is_fixed("D1")) {
    auto probe = start.clone();
    const auto mu_at = [&](const Eigen::VectorXd& t) {
      probe->set_params(t);
      return material::small_strain_constants(*probe).mu;
    };
    mu0_gradient_ = Eigen::VectorXd::Zero(theta0_.size());
    for (Eigen::Index k = 0; k < theta0_.size(); ++k) {
      if (start.param_info(k).dimension != Dimension::Pressure) continue;
      const double h = 1e-4 * std::max(std::abs(theta0_[k]), mu0);
      Eigen::VectorXd tp = theta0_, tm = theta0_;
      tp[k] += h;
      tm[k] -= h;
      mu0_gradient_[k] = (mu_at(tp) - mu_at(tm)) / (2.0 * h);
    }
    const double mu_start = material::small_strain_constants(start).mu;
    d1_follows_ = mu_start > 0.0 && std::abs(mu0_of(theta0_) - mu_start) <= 1e-6 * mu_start;
  }
  for (const auto& name : fixed) {
    bool found = name == "nu" && d1_follows_;
    for (Eigen::Index k = 0; k < start.num_params(); ++k) found |= start.param_info(k).name == name;
    if (!found) {
      std::string names;
      for (Eigen::Index k = 0; k < start.num_params(); ++k) names += (k ? ", " : "") + start.param_info(k).name;
      if (d1_follows_) names += ", nu";
      throw_input_error(fmt::format("model {} has no parameter '{}'", start.model(), name),
                        ErrorContext{"", 0, 0, "fix"}, fmt::format("one of {}", names));
    }
  }
  // ν at the start, moved inside the range (a held ν stays what it is).
  nu_param_ = k_nu >= 0 ? k_nu : (d1_follows_ ? k_d1 : -1);
  if (nu_param_ >= 0) {
    const double width = nu.hi - nu.lo;
    const double nu_start = k_nu >= 0 ? theta0_[k_nu] : material::small_strain_constants(start).poisson();
    const bool held = is_fixed("nu") || (k_nu < 0 && is_fixed("D1"));
    nu0_ = held ? nu_start : std::clamp(nu_start, nu.lo + 1e-4 * width, nu.hi - 1e-4 * width);
    if (k_nu >= 0) {
      theta0_[k_nu] = nu0_;
    } else {
      theta0_[k_d1] = 3.0 * (1.0 - 2.0 * nu0_) / (mu0_of(theta0_) * (1.0 + nu0_));
    }
  }
  for (Eigen::Index k = 0; k < start.num_params(); ++k) {
    const material::ParamInfo info = start.param_info(k);
    if (k == nu_param_) {
      if (is_fixed("nu") || is_fixed(info.name)) continue;
      nu_coordinate_ = size();
      param_.push_back(k);
      scale_.push_back(1.0);
      lower_.push_back(-std::numeric_limits<double>::infinity());
      upper_.push_back(std::numeric_limits<double>::infinity());
      continue;
    }
    if (is_fixed(info.name)) continue;
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
    if (info.name == "volume_share") {
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

double Coordinates::nu_of(double x) const noexcept { return nu_.lo + (nu_.hi - nu_.lo) / (1.0 + std::exp(-x)); }

double Coordinates::dnu_dx(double x) const noexcept {
  const double s = 1.0 / (1.0 + std::exp(-x));
  return (nu_.hi - nu_.lo) * s * (1.0 - s);
}

int Coordinates::at_bound(const Eigen::VectorXd& x, Eigen::Index i) const {
  if (i == nu_coordinate_) {
    const double share = (nu_of(x[i]) - nu_.lo) / (nu_.hi - nu_.lo);
    return share < 1e-3 ? -1 : (share > 1.0 - 1e-3 ? 1 : 0);
  }
  const auto k = static_cast<std::size_t>(i);
  if (std::isfinite(lower_[k]) && x[i] <= lower_[k] + 1e-9 * std::max(1.0, std::abs(lower_[k]))) return -1;
  if (std::isfinite(upper_[k]) && x[i] >= upper_[k] - 1e-9 * std::max(1.0, std::abs(upper_[k]))) return 1;
  return 0;
}

Eigen::VectorXd Coordinates::start() const {
  Eigen::VectorXd x(size());
  for (std::size_t i = 0; i < param_.size(); ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    x[c] = c == nu_coordinate_ ? logit((nu0_ - nu_.lo) / (nu_.hi - nu_.lo)) : theta0_[param_[i]] / scale_[i];
  }
  return x;
}

Eigen::VectorXd Coordinates::theta(const Eigen::VectorXd& x) const {
  Eigen::VectorXd t = theta0_;
  for (std::size_t i = 0; i < param_.size(); ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    if (c != nu_coordinate_) t[param_[i]] = x[c] * scale_[i];
  }
  if (nu_param_ >= 0) {
    const double nu = nu_coordinate_ >= 0 ? nu_of(x[nu_coordinate_]) : nu0_;
    t[nu_param_] = d1_follows_ ? 3.0 * (1.0 - 2.0 * nu) / (mu0_of(t) * (1.0 + nu)) : nu;
  }
  return t;
}

Eigen::MatrixXd Coordinates::dtheta_dx(const Eigen::VectorXd& x) const {
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(theta0_.size(), size());
  for (std::size_t i = 0; i < param_.size(); ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    if (c != nu_coordinate_) j(param_[i], c) = scale_[i];
  }
  if (nu_param_ < 0) return j;
  const double nu = nu_coordinate_ >= 0 ? nu_of(x[nu_coordinate_]) : nu0_;
  const double dnu = nu_coordinate_ >= 0 ? dnu_dx(x[nu_coordinate_]) : 0.0;
  if (!d1_follows_) {
    if (nu_coordinate_ >= 0) j(nu_param_, nu_coordinate_) = dnu;
    return j;
  }
  // D1 = 3(1 − 2ν)/(μ0(1 + ν)): ∂D1/∂μ0 = −D1/μ0, ∂D1/∂ν = −9/(μ0(1 + ν)²).
  const Eigen::VectorXd t = theta(x);
  const double mu = mu0_of(t), d1 = t[nu_param_];
  for (std::size_t i = 0; i < param_.size(); ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    if (c != nu_coordinate_) j(nu_param_, c) = -d1 / mu * mu0_gradient_[param_[i]] * scale_[i];
  }
  if (nu_coordinate_ >= 0) j(nu_param_, nu_coordinate_) = -9.0 / (mu * (1.0 + nu) * (1.0 + nu)) * dnu;
  return j;
}

}  // namespace palpa::fit
