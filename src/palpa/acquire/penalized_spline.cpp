// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/acquire/penalized_spline.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace palpa::acquire {

namespace {

// The segment of x (clamped to the range) and the four uniform cubic B-spline
// weights of basis functions segment .. segment + 3 there.
struct Span4 {
  Eigen::Index first = 0;
  std::array<double, 4> w{};
};

Span4 basis_at(double x, double x0, double h, Eigen::Index segments) {
  const double s = (x - x0) / h;
  const Eigen::Index j = std::clamp(static_cast<Eigen::Index>(std::floor(s)), Eigen::Index{0}, segments - 1);
  const double u = s - static_cast<double>(j);
  const double v = 1.0 - u;
  return {j, {v * v * v / 6.0, (3.0 * u * u * u - 6.0 * u * u + 4.0) / 6.0,
              (-3.0 * u * u * u + 3.0 * u * u + 3.0 * u + 1.0) / 6.0, u * u * u / 6.0}};
}

// Dᵀ D for differences of `order` on n coefficients.
Eigen::MatrixXd difference_penalty(Eigen::Index n, int order) {
  Eigen::MatrixXd d = Eigen::MatrixXd::Identity(n, n);
  for (int k = 0; k < order; ++k) d = (d.bottomRows(d.rows() - 1) - d.topRows(d.rows() - 1)).eval();
  return d.transpose() * d;
}

}  // namespace

double PenalizedSpline::operator()(double x) const {
  const Span4 b = basis_at(x, x0, h, coefficients.size() - 3);
  double y = 0.0;
  for (Eigen::Index k = 0; k < 4; ++k) y += b.w[static_cast<std::size_t>(k)] * coefficients[b.first + k];
  return y;
}

PenalizedSpline fit_penalized_spline(std::span<const double> x, std::span<const double> y, double lo, double hi,
                                     const PenalizedSplineOptions& o) {
  if (x.size() != y.size()) throw std::invalid_argument("fit_penalized_spline: x and y differ in length");
  if (x.size() < static_cast<std::size_t>(o.penalty_order) + 1 || o.segments < 1) {
    throw std::invalid_argument("fit_penalized_spline: too few pairs");
  }
  const auto [xmin, xmax] = std::minmax_element(x.begin(), x.end());
  PenalizedSpline s;
  s.x0 = std::min(*xmin, lo);
  const double x1 = std::max(*xmax, hi);
  if (!(x1 > s.x0)) throw std::invalid_argument("fit_penalized_spline: the pairs share one x");
  // The penalty leaves polynomials below its order free: the pairs must fix
  // them, at as many distinct x.
  std::vector<double> sorted(x.begin(), x.end());
  std::sort(sorted.begin(), sorted.end());
  int distinct = 1;
  for (std::size_t i = 1; i < sorted.size(); ++i) {
    if (sorted[i] - sorted[i - 1] > 1e-12 * (x1 - s.x0)) ++distinct;
  }
  if (distinct < o.penalty_order) {
    throw std::invalid_argument("fit_penalized_spline: too few distinct x for the penalty's free polynomials");
  }
  const auto segments = static_cast<Eigen::Index>(o.segments);
  s.h = (x1 - s.x0) / static_cast<double>(segments);
  const Eigen::Index nb = segments + 3;

  Eigen::MatrixXd btb = Eigen::MatrixXd::Zero(nb, nb);
  Eigen::VectorXd bty = Eigen::VectorXd::Zero(nb);
  std::vector<Span4> rows(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    rows[i] = basis_at(x[i], s.x0, s.h, segments);
    const Span4& b = rows[i];
    for (Eigen::Index p = 0; p < 4; ++p) {
      bty[b.first + p] += b.w[static_cast<std::size_t>(p)] * y[i];
      for (Eigen::Index q = 0; q < 4; ++q) {
        btb(b.first + p, b.first + q) += b.w[static_cast<std::size_t>(p)] * b.w[static_cast<std::size_t>(q)];
      }
    }
  }
  const Eigen::MatrixXd penalty = difference_penalty(nb, o.penalty_order);
  const double scale = btb.trace() / penalty.trace();
  const double n = static_cast<double>(x.size());

  // The weight on a logarithmic grid, then a parabola through the best three.
  auto evaluate = [&](double log_lambda, Eigen::VectorXd& c, double& dof, double& rss) {
    const Eigen::MatrixXd a = btb + std::pow(10.0, log_lambda) * scale * penalty;
    const Eigen::LLT<Eigen::MatrixXd> llt(a);
    if (llt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
    c = llt.solve(bty);
    dof = llt.solve(btb).trace();
    rss = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      double f = 0.0;
      for (Eigen::Index k = 0; k < 4; ++k) f += rows[i].w[static_cast<std::size_t>(k)] * c[rows[i].first + k];
      rss += (y[i] - f) * (y[i] - f);
    }
    const double denominator = n - o.gcv_gamma * dof;
    if (!(denominator > 0.0)) return std::numeric_limits<double>::infinity();
    return n * rss / (denominator * denominator);
  };
  constexpr double kLogLo = -8.0, kLogHi = 8.0, kLogStep = 0.25;
  const int steps = static_cast<int>(std::round((kLogHi - kLogLo) / kLogStep));
  std::vector<double> scores(static_cast<std::size_t>(steps) + 1);
  Eigen::VectorXd c;
  double dof = 0.0, rss = 0.0;
  for (int k = 0; k <= steps; ++k) scores[static_cast<std::size_t>(k)] = evaluate(kLogLo + k * kLogStep, c, dof, rss);
  const auto best = static_cast<int>(std::min_element(scores.begin(), scores.end()) - scores.begin());
  if (!std::isfinite(scores[static_cast<std::size_t>(best)])) {
    throw std::invalid_argument("fit_penalized_spline: the pairs do not determine a curve");
  }
  double log_lambda = kLogLo + best * kLogStep;
  if (best > 0 && best < steps) {
    const double sm = scores[static_cast<std::size_t>(best - 1)], s0 = scores[static_cast<std::size_t>(best)],
                 sp = scores[static_cast<std::size_t>(best + 1)];
    const double curvature = sm - 2.0 * s0 + sp;
    if (std::isfinite(sm) && std::isfinite(sp) && curvature > 0.0) log_lambda += 0.5 * kLogStep * (sm - sp) / curvature;
  }
  if (!std::isfinite(evaluate(log_lambda, c, dof, rss))) {
    log_lambda = kLogLo + best * kLogStep;
    evaluate(log_lambda, c, dof, rss);
  }
  s.coefficients = c;
  s.lambda = std::pow(10.0, log_lambda);
  s.effective_dof = dof;
  s.rms = std::sqrt(rss / n);
  s.pairs = x.size();
  return s;
}

}  // namespace palpa::acquire
