// SPDX-License-Identifier: AGPL-3.0-or-later
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "palpa/core/error.hpp"
#include "palpa/core/parallel.hpp"
#include "palpa/fit/optimize.hpp"
#include "palpa/material/checks.hpp"
#include "palpa/material/spline_material.hpp"

namespace palpa::fit {

using material::Material;

// The training problem of one layer depth, in scaled free parameters x:
// θ_free = scale ⊙ x, the other parameters held (optimize.hpp).

TrainingProblem::TrainingProblem(const Dataset& d, double layer_depth, const SimulationOptions& so,
                                 const Material& start, const std::vector<std::string>& fixed, double mu0,
                                 PoissonRange nu)
    : material_(start.clone()), theta0_(start.params()), coords_(start, fixed, mu0, nu) {
  for (const auto& c : d.curves) {
    if (c.role != CurveRole::Train) continue;
    curves_.push_back(&c);
    sims_.push_back(make_curve_simulator(d, c, layer_depth, so, &start));
    offsets_.push_back(residuals_);
    residuals_ += static_cast<Eigen::Index>(c.y.size());
  }
}

TrainingProblem::~TrainingProblem() = default;

std::unique_ptr<Material> TrainingProblem::material_at(const Eigen::VectorXd& x) const {
  auto m = material_->clone();
  m->set_params(theta(x));
  return m;
}

bool TrainingProblem::evaluate(const Eigen::VectorXd& x, Evaluation& out) {
  out = Evaluation{};
  ++evaluations_;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || x[i] < lower()[static_cast<std::size_t>(i)] ||
        x[i] > upper()[static_cast<std::size_t>(i)]) {
      out.reason = "a parameter left its range";
      return false;
    }
  }
  std::unique_ptr<Material> m;
  try {
    m = material_at(x);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Input) throw;
    out.reason = e.problem();
    return false;
  }
  const material::MaterialCheck check = material::check_material(*m);
  if (!check.problems.empty()) {
    out.reason = "not a physically valid material: " + check.problems.front();
    return false;
  }
  std::vector<CurvePrediction> preds(curves_.size());
  std::vector<std::string> failures(curves_.size());
  parallel_for_each_index(curves_.size(), [&](std::size_t i) {
    try {
      preds[i] = sims_[i]->predict(*m, true);
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::Solver) throw;
      failures[i] = fmt::format("curve {}: {}", curves_[i]->name, e.problem());
    }
  });
  for (const auto& f : failures) {
    if (!f.empty()) {
      out.reason = f;
      return false;
    }
  }
  const Eigen::MatrixXd dtheta = coords_.dtheta_dx(x);
  out.residuals.resize(residuals_);
  out.jacobian.resize(residuals_, num_free());
  for (std::size_t i = 0; i < curves_.size(); ++i) {
    const MeasuredCurve& c = *curves_[i];
    const auto n = static_cast<Eigen::Index>(c.y.size());
    for (Eigen::Index j = 0; j < n; ++j) {
      out.residuals[offsets_[i] + j] = preds[i].y[static_cast<std::size_t>(j)] - c.y[static_cast<std::size_t>(j)];
    }
    out.jacobian.middleRows(offsets_[i], n) = preds[i].dy_dparams.topRows(n) * dtheta;
    out.newton_iterations += preds[i].newton_iterations;
  }
  if (curvature_weight_ > 0.0 && curvature_.rows() > 0) {
    const Eigen::Index n = curvature_.rows();
    out.residuals.conservativeResize(residuals_ + n);
    out.jacobian.conservativeResize(residuals_ + n, num_free());
    out.residuals.tail(n) = curvature_weight_ * (curvature_ * (theta(x) - theta0_));
    out.jacobian.bottomRows(n) = curvature_weight_ * (curvature_ * dtheta);
  }
  out.objective = out.residuals.squaredNorm();
  return true;
}

void TrainingProblem::set_curvature_regularization(double weight) {
  curvature_weight_ = std::max(weight, 0.0);
  curvature_.resize(0, 0);
  const auto* spline = dynamic_cast<const material::SplineMaterial*>(material_.get());
  if (spline == nullptr || curvature_weight_ == 0.0) {
    curvature_weight_ = 0.0;
    return;
  }
  using Part = material::ValanisLandelMaterial::Part;
  std::vector<Eigen::RowVectorXd> rows;
  Eigen::Index offset = 0;
  for (const Part part : {Part::F, Part::G, Part::H}) {
    const material::NaturalCubicSpline& sp = spline->spline(part);
    const std::vector<double>& knots = sp.knots();
    for (std::size_t k = 1; k + 1 < knots.size(); ++k) {
      Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(theta0_.size());
      sp.accumulate_basis(knots[k], 0.0, 0.0, 1.0, row.data() + offset, 1);
      rows.push_back(std::move(row));
    }
    offset += sp.size();
  }
  curvature_.resize(static_cast<Eigen::Index>(rows.size()), theta0_.size());
  for (std::size_t i = 0; i < rows.size(); ++i) curvature_.row(static_cast<Eigen::Index>(i)) = rows[i];
}

double TrainingProblem::regularization(const Eigen::VectorXd& x) const {
  if (curvature_weight_ == 0.0) return 0.0;
  return (curvature_weight_ * (curvature_ * (theta(x) - theta0_))).squaredNorm();
}

std::vector<axisym::WarmStart> TrainingProblem::warm_starts() const {
  std::vector<axisym::WarmStart> out;
  out.reserve(sims_.size());
  for (const auto& sim : sims_) out.push_back(sim->warm_start());
  return out;
}

void TrainingProblem::set_warm_starts(std::vector<axisym::WarmStart> warm) {
  if (warm.size() != sims_.size()) return;
  for (std::size_t i = 0; i < sims_.size(); ++i) sims_[i]->set_warm_start(std::move(warm[i]));
}

}  // namespace palpa::fit
