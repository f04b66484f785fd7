// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/design/score.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "palpa/core/error.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/geometry/umbrella.hpp"
#include "palpa/rest/adjoint.hpp"
#include "palpa/rest/measurements.hpp"

namespace palpa::design {

namespace {

Eigen::SparseMatrix<double> identity_plus(const Eigen::SparseMatrix<double>& W, double lambda) {
  Eigen::SparseMatrix<double> I(W.rows(), W.cols());
  I.setIdentity();
  Eigen::SparseMatrix<double> S = (1.0 - lambda) * I + lambda * W;
  S.makeCompressed();
  return S;
}

// s·p̄^e and its derivative e·s·p̄^(e−1).
double power(double x, int e) {
  double r = 1.0;
  for (int i = 0; i < e; ++i) r *= x;
  return r;
}

}  // namespace

ErgonomicScore::ErgonomicScore(const rest::RestSimulation& sim, ScoreOptions options)
    : options_(options), recovery_(rest::pressure_recovery(sim)) {
  if (options_.exponent < 2 || options_.exponent > 4) {
    throw Error(ErrorKind::Input,
                fmt::format("the ergonomic score's exponent must be 2, 3 or 4, got {}", options_.exponent));
  }
  if (!(options_.pressure_smoothing >= 0.0 && options_.pressure_smoothing <= 1.0)) {
    throw Error(ErrorKind::Input, fmt::format("the pressure smoothing λ must be in [0, 1], got {}",
                                              options_.pressure_smoothing));
  }
  body_smoothing_ =
      identity_plus(geometry::umbrella_matrix(sim.surface_faces(), sim.model().num_vertices()), options_.pressure_smoothing);
  support_smoothing_ = identity_plus(geometry::umbrella_matrix(sim.support().triangles(), sim.support().vertices().rows()),
                                     options_.pressure_smoothing);
}

void ErgonomicScore::sum(const rest::ContactPressures& cp, Score& s, Eigen::VectorXd& wb, Eigen::VectorXd& ws) const {
  const int e = options_.exponent;
  s.body_smoothed = body_smoothing_ * s.body_pressure;
  s.support_smoothed = support_smoothing_ * s.support_pressure;
  wb = Eigen::VectorXd::Zero(s.body_pressure.size());
  ws = Eigen::VectorXd::Zero(s.support_pressure.size());
  for (Eigen::Index v = 0; v < wb.size(); ++v) {
    const double pb = s.body_smoothed[v];
    if (pb <= 0.0 || cp.body_area[v] == 0.0) continue;
    s.zeta_body += cp.body_area[v] * power(pb, e);
    wb[v] = e * cp.body_area[v] * power(pb, e - 1);
  }
  for (Eigen::Index v = 0; v < ws.size(); ++v) {
    const double ps = s.support_smoothed[v];
    if (ps <= 0.0) continue;
    s.zeta_support += cp.support_area[v] * power(ps, e);
    ws[v] = e * cp.support_area[v] * power(ps, e - 1);
  }
  s.zeta = s.zeta_body + s.zeta_support;
}

Score ErgonomicScore::evaluate(const rest::RestSimulation& sim, bool gradient) const {
  // ζ = Σ A_i(y) p̄_i^e on each side, p̄ = S p, p = R(y) |f| the recovered
  // traction (rest/measurements.hpp) of the nodal forces f = −∂E_c/∂y. So
  // ∂ζ/∂y = −H_c v + (the pullbacks of R and of the areas), with
  // v_i = (∂ζ/∂|f_i|) f̂_i: one product with the contact Hessian.
  const rest::ContactPressures cp = rest::contact_pressures(sim, recovery_);
  const Eigen::Index nb = sim.model().num_vertices();
  const Eigen::Index ns = sim.support().vertices().rows();
  const int e = options_.exponent;
  Score s;
  s.body_pressure = cp.body;
  s.support_pressure = cp.support;
  s.body_contacts = static_cast<int>((cp.body.array() > 0.0).count());
  s.support_contacts = static_cast<int>((cp.support.array() > 0.0).count());
  Eigen::VectorXd wb, ws;
  sum(cp, s, wb, ws);
  if (!gradient) return s;

  const Eigen::MatrixX3d Yb = rest::body_points(sim), Ys = rest::support_points(sim);
  const Eigen::VectorXd fb = cp.body_force.colwise().norm().transpose();
  const Eigen::VectorXd fs = cp.support_force.colwise().norm().transpose();
  Eigen::VectorXd d_fb = Eigen::VectorXd::Zero(nb), d_fs = Eigen::VectorXd::Zero(ns);
  Eigen::MatrixX3d d_yb = Eigen::MatrixX3d::Zero(nb, 3), d_ys = Eigen::MatrixX3d::Zero(ns, 3);
  recovery_.body.add_pullback(Yb, fb, body_smoothing_.transpose() * wb, d_fb, d_yb);
  recovery_.support.add_pullback(Ys, fs, support_smoothing_.transpose() * ws, d_fs, d_ys);
  // The areas weighing p̄^e.
  Eigen::VectorXd ab = Eigen::VectorXd::Zero(nb), as = Eigen::VectorXd::Zero(ns);
  for (Eigen::Index v = 0; v < nb; ++v) {
    if (wb[v] != 0.0) ab[v] = power(s.body_smoothed[v], e);
  }
  for (Eigen::Index v = 0; v < ns; ++v) {
    if (ws[v] != 0.0) as[v] = power(s.support_smoothed[v], e);
  }
  geometry::add_vertex_area_gradient(Yb, recovery_.body.triangles(), ab, d_yb);
  geometry::add_vertex_area_gradient(Ys, recovery_.support.triangles(), as, d_ys);

  Eigen::Matrix3Xd vb = Eigen::Matrix3Xd::Zero(3, nb), vs = Eigen::Matrix3Xd::Zero(3, ns);
  for (Eigen::Index v = 0; v < nb; ++v) {
    if (fb[v] > 0.0 && d_fb[v] != 0.0) vb.col(v) = d_fb[v] / fb[v] * cp.body_force.col(v);
  }
  for (Eigen::Index j = 0; j < ns; ++j) {
    if (fs[j] > 0.0 && d_fs[j] != 0.0) vs.col(j) = d_fs[j] / fs[j] * cp.support_force.col(j);
  }
  Eigen::Matrix3Xd hb, hs;
  rest::contact_hessian_product(sim, vb, vs, hb, hs);
  const Eigen::Matrix3Xd d_body = d_yb.transpose() - hb;
  s.d_body = Eigen::Map<const Eigen::VectorXd>(d_body.data(), d_body.size());
  s.d_support = d_ys - hs.transpose();
  s.d_support_area = Eigen::MatrixX3d::Zero(ns, 3);
  // A deformable support's held base is where it was made: what the score
  // sees of it there is its shape's own.
  if (sim.deformable_support()) {
    for (Eigen::Index j = 0; j < ns; ++j) {
      if (sim.support_vertex_fixed(static_cast<int>(j))) {
        s.d_support_area.row(j) = s.d_support.row(j);
        s.d_support.row(j).setZero();
      }
    }
  }
  return s;
}

Smoothness::Smoothness(const Eigen::MatrixX3i& F, Eigen::Index n, std::vector<int> design, int iterations,
                       double lambda, double mu)
    : design_(std::move(design)), iterations_(iterations) {
  if (iterations < 1) {
    throw Error(ErrorKind::Input, fmt::format("Taubin smoothing needs at least one iteration, got {}", iterations));
  }
  const Eigen::SparseMatrix<double> W = geometry::umbrella_matrix(F, n);
  step_lambda_ = identity_plus(W, lambda);
  step_mu_ = identity_plus(W, mu);
}

Eigen::MatrixX3d Smoothness::smoothed(const Eigen::MatrixX3d& X) const {
  Eigen::MatrixX3d T = X;
  for (int i = 0; i < iterations_; ++i) {
    T = step_lambda_ * T;
    T = step_mu_ * T;
  }
  return T;
}

double Smoothness::evaluate(const Eigen::MatrixX3d& X, Eigen::MatrixX3d* grad) const {
  const Eigen::MatrixX3d r_all = X - smoothed(X);
  Eigen::MatrixX3d r = Eigen::MatrixX3d::Zero(X.rows(), 3);  // D r
  double psi = 0.0;
  for (int v : design_) {
    r.row(v) = r_all.row(v);
    psi += r_all.row(v).squaredNorm();
  }
  if (grad != nullptr) {
    // ∂ψ/∂X = 2 (I − T)ᵀ D r, Tᵀ applying the steps' transposes in reverse.
    Eigen::MatrixX3d t = r;
    for (int i = 0; i < iterations_; ++i) {
      t = step_mu_.transpose() * t;
      t = step_lambda_.transpose() * t;
    }
    *grad = 2.0 * (r - t);
  }
  return psi;
}

}  // namespace palpa::design
