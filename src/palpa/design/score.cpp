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

ErgonomicScore::ErgonomicScore(const rest::RestSimulation& sim, ScoreOptions options) : options_(options) {
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

void add_area_gradient(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::VectorXd& w,
                       Eigen::MatrixX3d& grad) {
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int ia = F(f, 0), ib = F(f, 1), ic = F(f, 2);
    const double wf = (w[ia] + w[ib] + w[ic]) / 3.0;  // each vertex gets a third of the area
    if (wf == 0.0) continue;
    const Eigen::Vector3d a = V.row(ia), b = V.row(ib), c = V.row(ic);
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    if (!(len > 0.0)) continue;
    const Eigen::Vector3d u = n / len;
    grad.row(ia) += wf * 0.5 * u.cross(c - b).transpose();
    grad.row(ib) += wf * 0.5 * u.cross(a - c).transpose();
    grad.row(ic) += wf * 0.5 * u.cross(b - a).transpose();
  }
}

void ErgonomicScore::sum(const rest::RestSimulation& sim, const Eigen::VectorXd& support_area, Score& s,
                         Eigen::VectorXd& wb, Eigen::VectorXd& ws) const {
  const int e = options_.exponent;
  s.body_smoothed = body_smoothing_ * s.body_pressure;
  s.support_smoothed = support_smoothing_ * s.support_pressure;
  const Eigen::VectorXd& area = sim.contact_term().pressure_areas();
  wb = Eigen::VectorXd::Zero(s.body_pressure.size());
  ws = Eigen::VectorXd::Zero(s.support_pressure.size());
  for (int v : sim.surface_vertices()) {
    const double pb = s.body_smoothed[v];
    if (pb <= 0.0) continue;
    const double sa = area[v];
    s.zeta_body += sa * power(pb, e);
    wb[v] = e * sa * power(pb, e - 1);
  }
  for (Eigen::Index v = 0; v < ws.size(); ++v) {
    const double ps = s.support_smoothed[v];
    if (ps <= 0.0) continue;
    s.zeta_support += support_area[v] * power(ps, e);
    ws[v] = e * support_area[v] * power(ps, e - 1);
  }
  s.zeta = s.zeta_body + s.zeta_support;
}

Score ErgonomicScore::evaluate(const rest::RestSimulation& sim, bool gradient) const {
  // p_i = ‖f_i‖/A_i with f the nodal contact forces (both passes on a
  // deformable support), so
  // ∂p_i/∂y = −f̂_iᵀ H_c(i, ·)/A_i (f = −∂E_c/∂y) and ∂ζ/∂y = −H_c v with
  // v_i = (∂ζ/∂p_i / A_i) f̂_i: one product with the contact Hessian.
  const rest::ContactPressures cp = rest::contact_pressures(sim);
  const Eigen::Index nb = sim.model().num_vertices();
  const Eigen::Index ns = sim.support().vertices().rows();
  const int e = options_.exponent;
  Score s;
  s.body_pressure = cp.body;
  s.support_pressure = cp.support;
  s.body_contacts = static_cast<int>((cp.body.array() > 0.0).count());
  s.support_contacts = static_cast<int>((cp.support.array() > 0.0).count());
  const Eigen::VectorXd& body_area = sim.contact_term().pressure_areas();
  const Eigen::MatrixX3d& X = sim.support_rest_vertices();
  const Eigen::MatrixX3i& F = sim.support().triangles();
  const Eigen::VectorXd support_area = geometry::vertex_areas(X, F);
  Eigen::VectorXd wb, ws;
  sum(sim, support_area, s, wb, ws);
  if (!gradient) return s;

  const Eigen::VectorXd gb = body_smoothing_.transpose() * wb;
  const Eigen::VectorXd gs = support_smoothing_.transpose() * ws;
  Eigen::Matrix3Xd vb = Eigen::Matrix3Xd::Zero(3, nb), vs = Eigen::Matrix3Xd::Zero(3, ns);
  for (int v : sim.surface_vertices()) {
    const double f = cp.body_force.col(v).norm();
    if (f > 0.0 && gb[v] != 0.0) vb.col(v) = gb[v] / (body_area[v] * f) * cp.body_force.col(v);
  }
  // ζ_s = Σ A_j p̄_j^e with p_j = ‖f_j‖/A_j: the area enters twice.
  Eigen::VectorXd area_weight = Eigen::VectorXd::Zero(ns);
  for (Eigen::Index j = 0; j < ns; ++j) {
    const double f = cp.support_force.col(j).norm();
    if (s.support_smoothed[j] > 0.0) area_weight[j] = power(s.support_smoothed[j], e);
    if (f > 0.0 && gs[j] != 0.0) {
      vs.col(j) = gs[j] / (support_area[j] * f) * cp.support_force.col(j);
      area_weight[j] -= gs[j] * s.support_pressure[j] / support_area[j];
    }
  }
  Eigen::Matrix3Xd hb, hs;
  rest::contact_hessian_product(sim, vb, vs, hb, hs);
  s.d_body = -Eigen::Map<const Eigen::VectorXd>(hb.data(), hb.size());
  s.d_support = -hs.transpose();
  s.d_support_area = Eigen::MatrixX3d::Zero(ns, 3);
  add_area_gradient(X, F, area_weight, s.d_support_area);
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
