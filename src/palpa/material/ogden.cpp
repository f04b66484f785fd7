// SPDX-License-Identifier: AGPL-3.0-or-later
#include <fmt/format.h>

#include <cmath>

#include "palpa/core/error.hpp"
#include "palpa/material/models.hpp"

namespace palpa::material {

Ogden::Ogden(std::vector<double> mu, std::vector<double> alpha, double poisson)
    : mu_(std::move(mu)), alpha_(std::move(alpha)), poisson_(poisson) {
  validate_and_update();
}

void Ogden::validate_and_update() {
  if (mu_.empty() || mu_.size() != alpha_.size()) {
    throw_input_error(fmt::format("Ogden needs as many mu as alpha values (got {} and {})",
                                  mu_.size(), alpha_.size()),
                      ErrorContext{}, "one or more (mu, alpha) pairs");
  }
  mu_sum_ = 0.0;
  mu0_ = 0.0;
  for (std::size_t p = 0; p < mu_.size(); ++p) {
    require_finite(mu_[p], fmt::format("mu[{}]", p));
    require_finite(alpha_[p], fmt::format("alpha[{}]", p));
    if (alpha_[p] == 0.0) {
      throw_input_error(fmt::format("parameter alpha[{}] is zero", p), ErrorContext{},
                        "non-zero exponents");
    }
    mu_sum_ += mu_[p];
    mu0_ += 0.5 * mu_[p] * alpha_[p];
  }
  if (!(mu0_ > 0.0)) {
    throw_input_error(fmt::format("Ogden shear modulus mu0 = sum(mu*alpha)/2 = {} is not positive",
                                  mu0_),
                      ErrorContext{}, "parameters with sum(mu[p] * alpha[p]) > 0");
  }
  require_poisson(poisson_);
  lambda_ = 2.0 * mu0_ * poisson_ / (1.0 - 2.0 * poisson_);
}

std::string Ogden::description() const {
  return fmt::format(
      "Ogden ({} term{}) in Valanis-Landel form: sum_p mu_p/alpha_p sum_i (lambda_i^alpha_p - 1) "
      "- (sum_p mu_p) ln J + lambda/2 (ln J)^2 with lambda = 2 mu0 nu/(1 - 2 nu), "
      "mu0 = sum_p mu_p alpha_p / 2; volumetric term: logarithmic",
      mu_.size(), mu_.size() == 1 ? "" : "s");
}

Eigen::Index Ogden::num_params() const noexcept {
  return 2 * static_cast<Eigen::Index>(mu_.size()) + 1;
}

ParamInfo Ogden::param_info(Eigen::Index k) const {
  const Eigen::Index n = num_terms();
  if (k < n) return {fmt::format("mu[{}]", k), Dimension::Pressure, "Ogden modulus"};
  if (k < 2 * n) return {fmt::format("alpha[{}]", k - n), Dimension::Dimensionless, "Ogden exponent"};
  return {"nu", Dimension::Dimensionless, "Poisson's ratio (small strain)"};
}

Eigen::VectorXd Ogden::params() const {
  const Eigen::Index n = num_terms();
  Eigen::VectorXd t(num_params());
  for (Eigen::Index p = 0; p < n; ++p) {
    t[p] = mu_[static_cast<std::size_t>(p)];
    t[n + p] = alpha_[static_cast<std::size_t>(p)];
  }
  t[2 * n] = poisson_;
  return t;
}

void Ogden::set_params(const Eigen::VectorXd& theta) {
  Ogden next = *this;
  const Eigen::Index n = num_terms();
  for (Eigen::Index p = 0; p < n; ++p) {
    next.mu_[static_cast<std::size_t>(p)] = theta[p];
    next.alpha_[static_cast<std::size_t>(p)] = theta[n + p];
  }
  next.poisson_ = theta[2 * n];
  next.validate_and_update();
  *this = std::move(next);
}

std::unique_ptr<Material> Ogden::clone() const { return std::make_unique<Ogden>(*this); }

Scalar3 Ogden::raw_part(Part p, double x) const {
  if (p == Part::F) {
    Scalar3 s;
    for (std::size_t q = 0; q < mu_.size(); ++q) {
      const double a = alpha_[q];
      const double xa2 = std::pow(x, a - 2.0);  // x^(α−2)
      s.v += mu_[q] / a * (xa2 * x * x - 1.0);
      s.d1 += mu_[q] * xa2 * x;
      s.d2 += mu_[q] * (a - 1.0) * xa2;
    }
    return s;
  }
  const double lj = std::log(x);
  const double inv = 1.0 / x;
  return Scalar3{-mu_sum_ * lj + 0.5 * lambda_ * lj * lj, (-mu_sum_ + lambda_ * lj) * inv,
                 (mu_sum_ + lambda_ * (1.0 - lj)) * inv * inv};
}

void Ogden::accumulate_part_dparam(Part p, double x, double w1, double w2,
                                   Eigen::Ref<Eigen::MatrixXd> out, Eigen::Index row) const {
  const Eigen::Index n = num_terms();
  if (p == Part::F) {
    const double lx = std::log(x);
    for (Eigen::Index q = 0; q < n; ++q) {
      const double m = mu_[static_cast<std::size_t>(q)];
      const double a = alpha_[static_cast<std::size_t>(q)];
      const double xa2 = std::pow(x, a - 2.0);
      const double xa1 = xa2 * x;
      out(row, q) += w1 * xa1 + w2 * (a - 1.0) * xa2;
      out(row, n + q) += w1 * m * xa1 * lx + w2 * m * xa2 * (1.0 + (a - 1.0) * lx);
    }
    return;
  }
  const double lj = std::log(x);
  const double inv = 1.0 / x;
  const double dmsum = -w1 * inv + w2 * inv * inv;               // ∂/∂(Σμ)
  const double dlam = w1 * lj * inv + w2 * (1.0 - lj) * inv * inv;  // ∂/∂λ
  const double c = poisson_ / (1.0 - 2.0 * poisson_);            // λ = 2 c μ0
  for (Eigen::Index q = 0; q < n; ++q) {
    const double m = mu_[static_cast<std::size_t>(q)];
    const double a = alpha_[static_cast<std::size_t>(q)];
    out(row, q) += dmsum + dlam * c * a;
    out(row, n + q) += dlam * c * m;
  }
  const double onu = 1.0 - 2.0 * poisson_;
  out(row, 2 * n) += dlam * 2.0 * mu0_ / (onu * onu);
}

}  // namespace palpa::material
