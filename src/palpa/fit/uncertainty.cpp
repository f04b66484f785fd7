// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/fit/uncertainty.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>

#include "palpa/core/error.hpp"

namespace palpa::fit {

namespace {

constexpr double kTradeOff = 0.95;  // |correlation| above which two estimates trade off

double normal_quantile(double p) {
  // Newton on Φ(z) = erfc(−z/√2)/2 from z = 0 (Φ is convex beyond 0: monotone).
  double z = 0.0;
  for (int k = 0; k < 60; ++k) {
    const double f = 0.5 * std::erfc(-z / std::sqrt(2.0)) - p;
    const double df = std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi);
    const double step = f / df;
    z -= step;
    if (std::abs(step) < 1e-14) break;
  }
  return z;
}

// E and ν (small strain) of the material at x.
Eigen::Vector2d young_poisson(const TrainingProblem& p, const Eigen::VectorXd& x) {
  const material::ElasticConstants c = material::small_strain_constants(*p.material_at(x));
  return {c.young(), c.poisson()};
}

// ∂(E, ν)/∂x by central differences (one-sided where a side is not a valid
// material): no simulation, only the rest Hessian of the material.
Eigen::MatrixXd young_poisson_gradient(const TrainingProblem& p, const Eigen::VectorXd& x) {
  Eigen::MatrixXd g(2, x.size());
  const Eigen::Vector2d at = young_poisson(p, x);
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double h = 1e-6 * std::max(1.0, std::abs(x[i]));
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    std::optional<Eigen::Vector2d> fp, fm;
    try {
      fp = young_poisson(p, xp);
    } catch (const Error&) {
    }
    try {
      fm = young_poisson(p, xm);
    } catch (const Error&) {
    }
    if (fp && fm) {
      g.col(i) = (*fp - *fm) / (2.0 * h);
    } else if (fp) {
      g.col(i) = (*fp - at) / h;
    } else if (fm) {
      g.col(i) = (at - *fm) / h;
    } else {
      g.col(i).setZero();
    }
  }
  return g;
}

void add_trade_off_warnings(Uncertainty& u, const std::vector<bool>& material_parameter) {
  const auto n = static_cast<Eigen::Index>(u.estimates.size());
  std::vector<std::string> pairs;
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = i + 1; j < n; ++j) {
      const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(j);
      // E and ν are functions of the material parameters: their correlation
      // with those says nothing.
      if (material_parameter[a] != material_parameter[b]) continue;
      const double c = u.correlation(i, j);
      if (!(std::abs(c) > kTradeOff)) continue;
      pairs.push_back(fmt::format("{} and {} ({:+.3f})", u.estimates[a].name, u.estimates[b].name, c));
    }
  }
  if (pairs.empty()) return;
  u.warnings.push_back(fmt::format("parameters that trade off (|correlation| > {}): {}; the curves pin down a "
                                   "combination of each pair, not each one",
                                   kTradeOff, fmt::join(pairs, ", ")));
}

}  // namespace

const Estimate* Uncertainty::find(const std::string& name) const {
  for (const auto& e : estimates) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

double student_t_quantile(double p, double dof) {
  const double z = normal_quantile(p);
  if (!std::isfinite(dof) || dof > 1e7) return z;
  const double z2 = z * z, z3 = z2 * z, z5 = z3 * z2, z7 = z5 * z2, z9 = z7 * z2, z11 = z9 * z2;
  const double g1 = (z3 + z) / 4.0;
  const double g2 = (5.0 * z5 + 16.0 * z3 + 3.0 * z) / 96.0;
  const double g3 = (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / 384.0;
  const double g4 = (79.0 * z9 + 776.0 * z7 + 1482.0 * z5 - 1920.0 * z3 - 945.0 * z) / 92160.0;
  const double g5 =
      (27.0 * z11 + 339.0 * z9 + 930.0 * z7 - 1782.0 * z5 - 765.0 * z3 + 17955.0 * z) / 368640.0;
  const double v = dof, v2 = v * v;
  return z + g1 / v + g2 / v2 + g3 / (v2 * v) + g4 / (v2 * v2) + g5 / (v2 * v2 * v);
}

Uncertainty fit_uncertainty(const TrainingProblem& p, const Eigen::VectorXd& x, const Evaluation& e,
                            bool report_parameters) {
  Uncertainty u;
  const Coordinates& c = p.coordinates();
  const auto material = p.material_at(x);
  const Eigen::Index m = p.num_data_residuals(), n = p.num_free();
  // Coordinates at an end of their range are held there (the usual reading
  // of a bound that is active: the others' covariance given it).
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (c.at_bound(x, i) != 0) {
      u.held.push_back(c.is_poisson(i) ? std::string("nu") : material->param_info(c.param(i)).name);
    } else {
      keep.push_back(i);
    }
  }
  const auto nk = static_cast<Eigen::Index>(keep.size());
  u.points = static_cast<int>(m);
  u.free_parameters = static_cast<int>(nk);
  // (JᵀJ)⁺ over the kept coordinates, columns scaled to unit norm (their
  // scales differ); eigenvalues below 1e-10 of the largest are directions
  // the curves do not see.
  Eigen::MatrixXd jk(e.jacobian.rows(), nk);
  for (Eigen::Index i = 0; i < nk; ++i) jk.col(i) = e.jacobian.col(keep[static_cast<std::size_t>(i)]);
  Eigen::VectorXd norms = jk.colwise().norm().transpose();
  for (Eigen::Index i = 0; i < nk; ++i) norms[i] = norms[i] > 0.0 ? norms[i] : 1.0;
  const Eigen::VectorXd inv_norms = norms.cwiseInverse();
  const Eigen::MatrixXd scaled = jk * inv_norms.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scaled.transpose() * scaled);
  const Eigen::VectorXd& lambda = eig.eigenvalues();  // ascending
  const double cut = 1e-10 * std::max(lambda.maxCoeff(), 0.0);
  Eigen::VectorXd inv_lambda = Eigen::VectorXd::Zero(nk);
  std::vector<Eigen::Index> null;
  for (Eigen::Index k = 0; k < nk; ++k) {
    if (lambda[k] > cut && lambda[k] > 0.0) {
      inv_lambda[k] = 1.0 / lambda[k];
    } else {
      null.push_back(k);
    }
  }
  const Eigen::MatrixXd& v = eig.eigenvectors();
  const Eigen::MatrixXd pinv = inv_norms.asDiagonal() * v * inv_lambda.asDiagonal() * v.transpose() *
                               inv_norms.asDiagonal();
  // Degrees of freedom m − tr(H), H = J_d (JᵀJ)⁺ J_dᵀ the data's hat matrix:
  // n without regularization, fewer where the spline's curvature rows (prior
  // information) hold directions the data alone would not.
  const Eigen::MatrixXd jd = jk.topRows(m);
  u.effective_parameters = (jd.transpose() * jd).cwiseProduct(pinv).sum();
  const double dof = static_cast<double>(m) - u.effective_parameters;
  if (!(dof >= 1.0)) {
    u.why_not = fmt::format("{} training points for {:.3g} effective free parameters", m, u.effective_parameters);
    return u;
  }
  const double eps = e.residuals.head(m).squaredNorm();
  const double s2 = eps / dof;
  u.sigma = std::sqrt(s2);
  u.t95 = student_t_quantile(0.975, dof);
  const Eigen::MatrixXd cov_k = s2 * pinv;

  // The quantities: material parameters (not ν's coordinate), E, ν; their
  // gradients over the kept coordinates.
  const Eigen::VectorXd theta = p.theta(x);
  const Eigen::MatrixXd dtheta = c.dtheta_dx(x);
  std::vector<Eigen::RowVectorXd> rows;
  std::vector<bool> is_parameter;
  Eigen::Index nu_coordinate = -1;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (c.is_poisson(i)) {
      nu_coordinate = i;
      continue;
    }
    const Eigen::Index k = c.param(i);
    // (E and ν are reported as the small-strain constants below)
    if (!report_parameters || material->param_info(k).name == "E") continue;
    u.estimates.push_back(Estimate{material->param_info(k).name, theta[k], 0.0, 0.0, 0.0});
    rows.push_back(dtheta.row(k));
    is_parameter.push_back(true);
  }
  const Eigen::Vector2d en = young_poisson(p, x);
  const Eigen::MatrixXd gen = young_poisson_gradient(p, x);
  u.estimates.push_back(Estimate{"E", en[0], 0.0, 0.0, 0.0});
  rows.push_back(gen.row(0));
  is_parameter.push_back(false);
  u.estimates.push_back(Estimate{"nu", en[1], 0.0, 0.0, 0.0});
  rows.push_back(gen.row(1));
  is_parameter.push_back(false);

  const auto q = static_cast<Eigen::Index>(rows.size());
  Eigen::MatrixXd g(q, nk);
  for (Eigen::Index i = 0; i < q; ++i) {
    const Eigen::RowVectorXd& row = rows[static_cast<std::size_t>(i)];
    for (Eigen::Index k = 0; k < nk; ++k) g(i, k) = row[keep[static_cast<std::size_t>(k)]];
  }
  const Eigen::MatrixXd cov = g * cov_k * g.transpose();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::vector<bool> determined(static_cast<std::size_t>(q), true);
  const bool nu_held = nu_coordinate >= 0 && std::find(keep.begin(), keep.end(), nu_coordinate) == keep.end();
  if (nu_held) determined.back() = false;
  for (Eigen::Index i = 0; i < q; ++i) {
    // A quantity with more than 0.1% of its gradient along a direction the
    // curves do not see is not determined by them.
    const Eigen::RowVectorXd gy = g.row(i) * inv_norms.asDiagonal();
    double along = 0.0;
    for (const Eigen::Index k : null) along = std::max(along, std::abs(gy.dot(v.col(k))) / gy.norm());
    spdlog::debug("fit uncertainty: {} has {:.3g} of its gradient along the {} unseen directions",
                  u.estimates[static_cast<std::size_t>(i)].name, along, null.size());
    // (a spline's global support leaves ~1e-5 along directions that hardly
    // change the material: measured on the silicone depth example)
    if (along > 1e-3) determined[static_cast<std::size_t>(i)] = false;
  }
  u.correlation.resize(q, q);
  for (Eigen::Index i = 0; i < q; ++i) {
    for (Eigen::Index k = 0; k < q; ++k) {
      const double d = std::sqrt(cov(i, i) * cov(k, k));
      const bool known = determined[static_cast<std::size_t>(i)] && determined[static_cast<std::size_t>(k)];
      u.correlation(i, k) = !known ? (i == k ? 1.0 : kNaN) : (d > 0.0 ? cov(i, k) / d : (i == k ? 1.0 : 0.0));
    }
  }
  for (Eigen::Index i = 0; i < q; ++i) {
    Estimate& est = u.estimates[static_cast<std::size_t>(i)];
    if (!determined[static_cast<std::size_t>(i)]) {
      est.standard_error = est.lo = est.hi = kNaN;
      if (!(nu_held && i + 1 == q)) u.undetermined.push_back(est.name);
      continue;
    }
    est.standard_error = std::sqrt(std::max(cov(i, i), 0.0));
    est.lo = est.value - u.t95 * est.standard_error;
    est.hi = est.value + u.t95 * est.standard_error;
  }
  // ν of a stable material lies in (−1, 0.5).
  Estimate& nu_estimate = u.estimates.back();
  nu_estimate.lo = std::max(nu_estimate.lo, -1.0);
  nu_estimate.hi = std::min(nu_estimate.hi, 0.5);
  // ν through its coordinate: the image of the coordinate's interval (so it
  // stays in its range); held at an end, ν has no interval.
  if (nu_coordinate >= 0 && !nu_held) {
    Estimate& nu = u.estimates.back();
    if (std::isfinite(nu.standard_error)) {
      const auto k = std::find(keep.begin(), keep.end(), nu_coordinate) - keep.begin();
      const double half = u.t95 * std::sqrt(cov_k(k, k));
      Eigen::VectorXd lo = x, hi = x;
      lo[nu_coordinate] -= half;
      hi[nu_coordinate] += half;
      const double a = young_poisson(p, lo)[1], b = young_poisson(p, hi)[1];
      nu.lo = std::min(a, b);
      nu.hi = std::max(a, b);
    }
  }
  add_trade_off_warnings(u, is_parameter);
  u.defined = true;
  return u;
}

Uncertainty modulus_uncertainty(double objective, int points, double scale, double sum_sim_squared,
                                double young_at_scale_one, double poisson) {
  Uncertainty u;
  u.points = points;
  u.free_parameters = 1;
  if (points <= 1 || !(sum_sim_squared > 0.0)) {
    u.why_not = fmt::format("{} training points for the modulus", points);
    return u;
  }
  const double s2 = objective / (points - 1);
  u.sigma = std::sqrt(s2);
  u.t95 = student_t_quantile(0.975, points - 1);
  const double se = young_at_scale_one * std::sqrt(s2 / sum_sim_squared);
  const double e = scale * young_at_scale_one;
  u.estimates.push_back(Estimate{"E", e, se, e - u.t95 * se, e + u.t95 * se});
  u.estimates.push_back(Estimate{"nu", poisson, 0.0, poisson, poisson});  // held
  u.correlation = Eigen::MatrixXd::Identity(2, 2);
  u.defined = true;
  return u;
}

void add_depth_uncertainty(Uncertainty& u, const std::vector<double>& depths, const std::vector<double>& objectives,
                           const std::vector<double>& young, std::size_t best, double sigma, double dof) {
  const std::size_t count = depths.size();
  if (count < 2 || best >= count) return;
  std::vector<std::size_t> order(count);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return depths[a] < depths[b]; });
  const auto pos = static_cast<std::size_t>(std::find(order.begin(), order.end(), best) - order.begin());
  Estimate depth{"layer_depth", depths[best], std::numeric_limits<double>::quiet_NaN(),
                 std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  const auto add = [&] {
    const auto q = u.correlation.rows();
    Eigen::MatrixXd c = Eigen::MatrixXd::Constant(q + 1, q + 1, std::numeric_limits<double>::quiet_NaN());
    c.topLeftCorner(q, q) = u.correlation;
    c(q, q) = 1.0;
    u.correlation = c;
    u.estimates.push_back(depth);
  };
  if (pos == 0 || pos + 1 == count) {
    u.warnings.push_back(fmt::format("the lowest objective is at an end of the searched depths ({:.3g} mm): the "
                                     "layer may be {} than the range; search a wider one",
                                     depths[best] * 1e3, pos == 0 ? "shallower" : "deeper"));
    add();
    return;
  }
  const std::size_t a = order[pos - 1], b = order[pos + 1];
  const double x0 = depths[a], x1 = depths[best], x2 = depths[b];
  const double y0 = objectives[a], y1 = objectives[best], y2 = objectives[b];
  // Parabola through the three points: y = y1 + β (x − x1) + α (x − x1)².
  const double d0 = x0 - x1, d2 = x2 - x1;
  const double alpha = ((y2 - y1) / d2 - (y0 - y1) / d0) / (d2 - d0);
  const double beta = (y2 - y1) / d2 - alpha * d2;
  if (!(alpha > 0.0) || !(sigma > 0.0)) {
    u.warnings.push_back(fmt::format("the objective is not curved around the best depth ({:.3g} mm): the curves "
                                     "do not tell the depths apart",
                                     depths[best] * 1e3));
    add();
    return;
  }
  const double vertex = std::clamp(x1 - beta / (2.0 * alpha), x0, x2);
  const double var_d = sigma * sigma / alpha;  // 2 s²/ε″, ε″ = 2α
  depth.value = vertex;
  depth.standard_error = std::sqrt(var_d);
  const double t = student_t_quantile(0.975, std::max(dof, 1.0));
  depth.lo = vertex - t * depth.standard_error;
  depth.hi = vertex + t * depth.standard_error;
  // E along the profile.
  const double de_dd = (young[b] - young[a]) / (x2 - x0);
  Estimate* e = nullptr;
  Eigen::Index ie = -1;
  for (std::size_t i = 0; i < u.estimates.size(); ++i) {
    if (u.estimates[i].name == "E") {
      e = &u.estimates[i];
      ie = static_cast<Eigen::Index>(i);
    }
  }
  add();
  if (e == nullptr) return;
  e = &u.estimates[static_cast<std::size_t>(ie)];
  const double var_e = e->standard_error * e->standard_error + de_dd * de_dd * var_d;
  const double corr = var_e > 0.0 ? de_dd * var_d / std::sqrt(var_e * var_d) : 0.0;
  // E's other correlations: its covariances are unchanged, its variance grew.
  const double shrink = var_e > 0.0 ? e->standard_error / std::sqrt(var_e) : 0.0;
  for (Eigen::Index k = 0; k + 1 < u.correlation.rows(); ++k) {
    if (k == ie) continue;
    u.correlation(ie, k) *= shrink;
    u.correlation(k, ie) *= shrink;
  }
  e->standard_error = std::sqrt(var_e);
  e->lo = e->value - u.t95 * e->standard_error;
  e->hi = e->value + u.t95 * e->standard_error;
  const Eigen::Index last = u.correlation.rows() - 1;
  u.correlation(ie, last) = u.correlation(last, ie) = corr;
  if (std::abs(corr) > kTradeOff) {
    u.warnings.push_back(fmt::format("E and layer_depth trade off (correlation {:+.3f}): a {} layer fits "
                                     "almost as well as a {} one",
                                     corr, corr > 0 ? "deeper, stiffer" : "deeper, softer",
                                     corr > 0 ? "shallower, softer" : "shallower, stiffer"));
  }
}

}  // namespace palpa::fit
