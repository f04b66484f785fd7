// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/material/spline.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "palpa/core/error.hpp"

namespace palpa::material {

NaturalCubicSpline::NaturalCubicSpline(std::vector<double> knots, std::vector<double> values,
                                       std::string_view name)
    : x_(std::move(knots)), y_(std::move(values)) {
  if (x_.size() < 3) {
    throw_input_error(fmt::format("{} has {} knots", name, x_.size()), ErrorContext{},
                      "at least 3 knots");
  }
  if (y_.size() != x_.size()) {
    throw_input_error(fmt::format("{} has {} knots but {} values", name, x_.size(), y_.size()),
                      ErrorContext{}, "one value per knot");
  }
  for (std::size_t k = 0; k < x_.size(); ++k) {
    if (!std::isfinite(x_[k]) || !std::isfinite(y_[k])) {
      throw_input_error(fmt::format("{} knot {} or its value is not finite", name, k),
                        ErrorContext{}, "finite knots and values");
    }
    if (k > 0 && !(x_[k] > x_[k - 1])) {
      throw_input_error(fmt::format("{} knots are not increasing at knot {} ({} after {})", name,
                                    k, x_[k], x_[k - 1]),
                        ErrorContext{}, "strictly increasing knots");
    }
  }
  // M: curvatures from values. Interior rows solve the tridiagonal system
  // h_(k-1) z_(k-1) + 2 (h_(k-1) + h_k) z_k + h_k z_(k+1) = 6 (Δ_k − Δ_(k-1)),
  // one column per unit value vector (Thomas algorithm on each).
  const Eigen::Index n = size();
  m_ = Eigen::MatrixXd::Zero(n, n);
  const Eigen::Index ni = n - 2;  // interior knots
  std::vector<double> h(static_cast<std::size_t>(n - 1));
  for (Eigen::Index k = 0; k + 1 < n; ++k) h[static_cast<std::size_t>(k)] = x_[static_cast<std::size_t>(k + 1)] - x_[static_cast<std::size_t>(k)];
  std::vector<double> cprime(static_cast<std::size_t>(ni));
  std::vector<double> dprime(static_cast<std::size_t>(ni));
  for (Eigen::Index col = 0; col < n; ++col) {
    // Right-hand side for y = e_col.
    for (Eigen::Index r = 0; r < ni; ++r) {
      const Eigen::Index k = r + 1;
      const auto uk = [&](Eigen::Index j) { return j == col ? 1.0 : 0.0; };
      const double hkm = h[static_cast<std::size_t>(k - 1)];
      const double hk = h[static_cast<std::size_t>(k)];
      const double rhs = 6.0 * ((uk(k + 1) - uk(k)) / hk - (uk(k) - uk(k - 1)) / hkm);
      const double diag = 2.0 * (hkm + hk);
      const double lower = r > 0 ? hkm : 0.0;
      const double denom = diag - (r > 0 ? lower * cprime[static_cast<std::size_t>(r - 1)] : 0.0);
      cprime[static_cast<std::size_t>(r)] = hk / denom;
      dprime[static_cast<std::size_t>(r)] =
          (rhs - (r > 0 ? lower * dprime[static_cast<std::size_t>(r - 1)] : 0.0)) / denom;
    }
    for (Eigen::Index r = ni - 1; r >= 0; --r) {
      double z = dprime[static_cast<std::size_t>(r)];
      if (r + 1 < ni) z -= cprime[static_cast<std::size_t>(r)] * m_(r + 2, col);
      m_(r + 1, col) = z;
    }
  }
  z_.assign(static_cast<std::size_t>(n), 0.0);
  update_curvatures();
}

std::vector<double> NaturalCubicSpline::log_uniform_knots(double lo, double hi, int count) {
  if (!(lo > 0.0 && hi > lo && std::isfinite(hi))) {
    throw_input_error(fmt::format("knot range [{}, {}] is not a positive increasing range", lo, hi),
                      ErrorContext{}, "0 < low < high");
  }
  if (count < 3) {
    throw_input_error(fmt::format("{} knots requested", count), ErrorContext{}, "at least 3 knots");
  }
  std::vector<double> x(static_cast<std::size_t>(count));
  const double a = std::log(lo);
  const double b = std::log(hi);
  for (int k = 0; k < count; ++k) x[static_cast<std::size_t>(k)] = std::exp(a + (b - a) * k / (count - 1));
  x.front() = lo;
  x.back() = hi;
  return x;
}

void NaturalCubicSpline::set_values(const double* values) {
  std::copy(values, values + size(), y_.begin());
  update_curvatures();
}

void NaturalCubicSpline::update_curvatures() {
  const Eigen::Map<const Eigen::VectorXd> y(y_.data(), size());
  Eigen::Map<Eigen::VectorXd>(z_.data(), size()) = m_ * y;
}

Eigen::Index NaturalCubicSpline::interval(double x) const noexcept {
  const auto it = std::upper_bound(x_.begin(), x_.end(), x);
  const Eigen::Index i = static_cast<Eigen::Index>(it - x_.begin()) - 1;
  return std::clamp<Eigen::Index>(i, 0, size() - 2);
}

Scalar3 NaturalCubicSpline::evaluate(double x) const noexcept {
  const Eigen::Index n = size();
  const auto X = [&](Eigen::Index k) { return x_[static_cast<std::size_t>(k)]; };
  const auto Y = [&](Eigen::Index k) { return y_[static_cast<std::size_t>(k)]; };
  const auto Z = [&](Eigen::Index k) { return z_[static_cast<std::size_t>(k)]; };
  if (x < X(0)) {
    const double h0 = X(1) - X(0);
    const double slope = (Y(1) - Y(0)) / h0 - h0 * Z(1) / 6.0;
    const double kappa = 0.5 * Z(1);
    return quadratic_continuation(Scalar3{Y(0), slope, kappa}, X(0), x);
  }
  if (x > X(n - 1)) {
    const double hn = X(n - 1) - X(n - 2);
    const double slope = (Y(n - 1) - Y(n - 2)) / hn + hn * Z(n - 2) / 6.0;
    const double kappa = 0.5 * Z(n - 2);
    return quadratic_continuation(Scalar3{Y(n - 1), slope, kappa}, X(n - 1), x);
  }
  const Eigen::Index i = interval(x);
  const double h = X(i + 1) - X(i);
  const double a = (X(i + 1) - x) / h;
  const double b = 1.0 - a;
  Scalar3 s;
  s.v = a * Y(i) + b * Y(i + 1) + ((a * a * a - a) * Z(i) + (b * b * b - b) * Z(i + 1)) * h * h / 6.0;
  s.d1 = (Y(i + 1) - Y(i)) / h - (3.0 * a * a - 1.0) * h / 6.0 * Z(i) +
         (3.0 * b * b - 1.0) * h / 6.0 * Z(i + 1);
  s.d2 = a * Z(i) + b * Z(i + 1);
  return s;
}

void NaturalCubicSpline::accumulate_basis(double x, double w0, double w1, double w2, double* out,
                                          Eigen::Index stride) const noexcept {
  const Eigen::Index n = size();
  const auto X = [&](Eigen::Index k) { return x_[static_cast<std::size_t>(k)]; };
  auto add = [&](Eigen::Index k, double v) { out[k * stride] += v; };
  if (x < X(0) || x > X(n - 1)) {
    // Parabola at an end knot e with slope s_e and curvature κ, both linear in y:
    // value = y_e + s_e dx + κ dx²/2, slope = s_e + κ dx, curvature = κ.
    const bool left = x < X(0);
    const Eigen::Index e = left ? 0 : n - 1;        // end knot
    const Eigen::Index o = left ? 1 : n - 2;        // its neighbour
    const Eigen::Index zi = left ? 1 : n - 2;       // curvature row used
    const double h = left ? X(1) - X(0) : X(n - 1) - X(n - 2);
    const double dx = x - X(e);
    const double sign = left ? 1.0 : -1.0;          // s_e = ±(y_o − y_e)/h ∓ h z/6
    const double wv = w0;                            // weight of value
    const double ws = w0 * dx + w1;                  // weight of slope s_e
    const double wk = 0.5 * w0 * dx * dx + w1 * dx + w2;  // weight of κ
    add(e, wv - ws * sign / h);
    add(o, ws * sign / h);
    const double zcoef = -sign * ws * h / 6.0 + 0.5 * wk;
    for (Eigen::Index k = 0; k < n; ++k) add(k, zcoef * m_(zi, k));
    return;
  }
  const Eigen::Index i = interval(x);
  const double h = X(i + 1) - X(i);
  const double a = (X(i + 1) - x) / h;
  const double b = 1.0 - a;
  // Coefficients of y_i, y_(i+1), z_i, z_(i+1) in w0 S + w1 S′ + w2 S″.
  const double cyi = w0 * a - w1 / h;
  const double cyi1 = w0 * b + w1 / h;
  const double czi = w0 * (a * a * a - a) * h * h / 6.0 - w1 * (3.0 * a * a - 1.0) * h / 6.0 + w2 * a;
  const double czi1 = w0 * (b * b * b - b) * h * h / 6.0 + w1 * (3.0 * b * b - 1.0) * h / 6.0 + w2 * b;
  add(i, cyi);
  add(i + 1, cyi1);
  for (Eigen::Index k = 0; k < n; ++k) add(k, czi * m_(i, k) + czi1 * m_(i + 1, k));
}

}  // namespace palpa::material
