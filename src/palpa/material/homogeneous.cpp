// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/material/homogeneous.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <numeric>

#include "palpa/core/error.hpp"
#include "palpa/material/kinematics.hpp"

namespace palpa::material {

namespace {

// Traction-free lateral stretch: the root t > 0 of r(t) = ∂Ψ/∂λ_free. r grows
// with t for a stable material; a bracket is grown around the guess, then
// Newton steps are taken inside it, falling back to bisection.
double solve_lateral(const Material& m, LoadCase c, double s, double guess) {
  const auto stretches = [&](double t) {
    return c == LoadCase::Uniaxial ? Vec3(s, t, t) : Vec3(s, s, t);
  };
  const auto residual = [&](double t, double* slope) {
    StretchEnergy e;
    m.evaluate(stretches(t), slope != nullptr ? EvalOrder::Hessian : EvalOrder::Gradient, e);
    if (c == LoadCase::Uniaxial) {
      if (slope != nullptr) *slope = e.hess(1, 1) + e.hess(1, 2);  // d/dt of ψ2(s, t, t)
      return e.grad[1];
    }
    if (slope != nullptr) *slope = e.hess(2, 2);
    return e.grad[2];
  };
  double lo = std::max(guess, 1e-3) / 1.5;
  double hi = std::max(guess, 1e-3) * 1.5;
  for (int k = 0; k < 60 && residual(lo, nullptr) > 0.0; ++k) lo /= 2.0;
  for (int k = 0; k < 60 && residual(hi, nullptr) < 0.0; ++k) hi *= 2.0;
  if (residual(lo, nullptr) > 0.0 || residual(hi, nullptr) < 0.0) {
    throw_solver_error(fmt::format("no traction-free lateral stretch found at load {}", s));
  }
  double t = std::clamp(guess, lo, hi);
  for (int it = 0; it < 200; ++it) {
    double slope = 0.0;
    const double r = residual(t, &slope);
    if (r > 0.0) hi = t; else lo = t;
    double next = slope > 0.0 ? t - r / slope : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - t) <= 1e-15 * std::max(1.0, t) || hi - lo <= 1e-15 * hi) return next;
    t = next;
  }
  return t;
}

// Scratch for the parameter derivatives of one point, sized once per curve.
struct SensitivityWork {
  explicit SensitivityWork(Eigen::Index p) : dgrad(3, p), dP(9, p) {}
  Eigen::MatrixXd dgrad;  // 3 × p: ∂²Ψ/∂λ∂θ
  Eigen::MatrixXd dP;     // 9 × p: ∂vec(P)/∂θ (shear)
};

// The point at `load` and its θ-derivatives, written to row `row` of the three
// derivative matrices.
CurvePoint point_with_sensitivity(const Material& m, LoadCase c, double load, double guess,
                                  SensitivityWork& work, Eigen::Index row,
                                  Eigen::Ref<Eigen::MatrixXd> dnominal,
                                  Eigen::Ref<Eigen::MatrixXd> dcauchy,
                                  Eigen::Ref<Eigen::MatrixXd> dlateral) {
  const CurvePoint p = homogeneous_point(m, c, load, guess);
  if (c == LoadCase::SimpleShear) {
    // P = U diag(∂Ψ/∂λ) Vᵀ with U, V fixed by F alone; σ = P Fᵀ (J = 1), and
    // row 1 of F is e2ᵀ, so σ12 = P12.
    Mat3 F = Mat3::Identity();
    F(0, 1) = load;
    dP_dparam(m, F, work.dgrad, work.dP);
    dnominal.row(row) = work.dP.row(0 + 3 * 1);
    dcauchy.row(row).setZero();
    for (int k = 0; k < 3; ++k) dcauchy.row(row) += F(1, k) * work.dP.row(0 + 3 * k);
    dlateral.row(row).setZero();
    return p;
  }
  const double s = load;
  const double t = p.lateral;
  const bool uniaxial = c == LoadCase::Uniaxial;
  const Vec3 l = uniaxial ? Vec3(s, t, t) : Vec3(s, s, t);
  StretchEnergy e;
  m.evaluate(l, EvalOrder::Hessian, e);
  m.d2psi_dlambda_dparam(l, work.dgrad);
  // Lateral residual r = ∂Ψ/∂λ2 (uniaxial) or ∂Ψ/∂λ3 (equibiaxial); P = ∂Ψ/∂λ1.
  const Eigen::Index free = uniaxial ? 1 : 2;
  const double dr_dt = uniaxial ? e.hess(1, 1) + e.hess(1, 2) : e.hess(2, 2);
  const double dP_dt = uniaxial ? e.hess(0, 1) + e.hess(0, 2) : e.hess(0, 2);
  if (!(std::isfinite(dr_dt) && dr_dt != 0.0)) {
    throw_solver_error(fmt::format(
        "lateral equilibrium at load {} is singular: the lateral stretch has no parameter "
        "derivative there",
        load));
  }
  dlateral.row(row) = -work.dgrad.row(free) / dr_dt;
  dnominal.row(row) = work.dgrad.row(0) + dP_dt * dlateral.row(row);
  // σ = P s / J with J = s t² (uniaxial) or s² t (equibiaxial): dJ/dt / J = n/t
  // with n lateral stretches equal to t.
  const double jac = l.prod();
  const double n_free = uniaxial ? 2.0 : 1.0;
  dcauchy.row(row) =
      (s / jac) * (dnominal.row(row) - (p.nominal * n_free / t) * dlateral.row(row));
  return p;
}

}  // namespace

LoadCase parse_load_case(std::string_view name) {
  if (name == "uniaxial") return LoadCase::Uniaxial;
  if (name == "equibiaxial") return LoadCase::Equibiaxial;
  if (name == "shear" || name == "simple-shear") return LoadCase::SimpleShear;
  throw_input_error(fmt::format("unknown test '{}'", name), ErrorContext{},
                    "uniaxial, equibiaxial or shear");
}

CurvePoint homogeneous_point(const Material& m, LoadCase c, double load, double guess) {
  CurvePoint p;
  p.load = load;
  if (c == LoadCase::SimpleShear) {
    Mat3 F = Mat3::Identity();
    F(0, 1) = load;
    Stress3 st;
    stress(m, F, EvalOrder::Gradient, PsdProjection::None, st);
    const Mat3 sigma = st.P * F.transpose();  // J = 1
    p.nominal = st.P(0, 1);
    p.cauchy = sigma(0, 1);
    p.cauchy_11 = sigma(0, 0);
    p.cauchy_22 = sigma(1, 1);
    p.energy = st.psi;
    return p;
  }
  if (!(load > 0.0)) {
    throw_input_error(fmt::format("stretch {} is not positive", load), ErrorContext{},
                      "stretches > 0");
  }
  const double t = solve_lateral(m, c, load, guess);
  const Vec3 l = c == LoadCase::Uniaxial ? Vec3(load, t, t) : Vec3(load, load, t);
  StretchEnergy e;
  m.evaluate(l, EvalOrder::Gradient, e);
  const double jac = l.prod();
  p.lateral = t;
  p.nominal = e.grad[0];
  p.cauchy = e.grad[0] * load / jac;
  p.energy = e.psi;
  return p;
}

std::vector<CurvePoint> homogeneous_curve(const Material& m, LoadCase c, double from, double to,
                                          int count) {
  if (count < 2) {
    throw_input_error(fmt::format("{} points requested", count), ErrorContext{}, "at least 2");
  }
  const double rest = c == LoadCase::SimpleShear ? 0.0 : 1.0;
  std::vector<CurvePoint> out(static_cast<std::size_t>(count));
  // Visit points in order of distance from the rest state, carrying the
  // lateral stretch of the nearest solved neighbour.
  std::vector<int> order(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) order[static_cast<std::size_t>(i)] = i;
  const auto load_at = [&](int i) { return from + (to - from) * i / (count - 1); };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return std::abs(load_at(a) - rest) < std::abs(load_at(b) - rest);
  });
  std::vector<bool> done(static_cast<std::size_t>(count), false);
  for (int i : order) {
    double guess = 1.0;
    double best = std::numeric_limits<double>::infinity();
    for (int j : {i - 1, i + 1}) {
      if (j >= 0 && j < count && done[static_cast<std::size_t>(j)]) {
        const double dist = std::abs(load_at(j) - load_at(i));
        if (dist < best) {
          best = dist;
          guess = out[static_cast<std::size_t>(j)].lateral;
        }
      }
    }
    out[static_cast<std::size_t>(i)] = homogeneous_point(m, c, load_at(i), guess);
    done[static_cast<std::size_t>(i)] = true;
  }
  return out;
}

CurvePointSensitivity homogeneous_point_sensitivity(const Material& m, LoadCase c, double load,
                                                    double guess) {
  const Eigen::Index np = m.num_params();
  SensitivityWork work(np);
  Eigen::MatrixXd dnominal(1, np);
  Eigen::MatrixXd dcauchy(1, np);
  Eigen::MatrixXd dlateral(1, np);
  CurvePointSensitivity out;
  out.point = point_with_sensitivity(m, c, load, guess, work, 0, dnominal, dcauchy, dlateral);
  out.dnominal_dparams = dnominal.row(0).transpose();
  out.dcauchy_dparams = dcauchy.row(0).transpose();
  out.dlateral_dparams = dlateral.row(0).transpose();
  return out;
}

CurveSensitivity homogeneous_curve_sensitivity(const Material& m, LoadCase c,
                                               std::span<const double> loads) {
  const auto n = static_cast<Eigen::Index>(loads.size());
  const Eigen::Index np = m.num_params();
  CurveSensitivity out;
  out.points.resize(loads.size());
  out.dnominal_dparams.resize(n, np);
  out.dcauchy_dparams.resize(n, np);
  out.dlateral_dparams.resize(n, np);
  for (double load : loads) {
    if (!std::isfinite(load)) {
      throw_input_error(fmt::format("load {} is not finite", load), ErrorContext{},
                        "finite stretches or shears");
    }
  }
  SensitivityWork work(np);
  // Continuation: walk outward from the rest state on each side, in order of
  // load, carrying the lateral stretch of the previous point on that side.
  const double rest = c == LoadCase::SimpleShear ? 0.0 : 1.0;
  std::vector<std::size_t> order(loads.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return loads[a] < loads[b]; });
  const auto first_above = std::partition_point(
      order.begin(), order.end(), [&](std::size_t i) { return loads[i] < rest; });
  const auto solve = [&](std::size_t i, double guess) {
    const auto row = static_cast<Eigen::Index>(i);
    out.points[i] = point_with_sensitivity(m, c, loads[i], guess, work, row, out.dnominal_dparams,
                                           out.dcauchy_dparams, out.dlateral_dparams);
    return out.points[i].lateral;
  };
  double guess = 1.0;
  for (auto it = first_above; it != order.end(); ++it) guess = solve(*it, guess);
  guess = 1.0;
  for (auto it = std::make_reverse_iterator(first_above); it != order.rend(); ++it) {
    guess = solve(*it, guess);
  }
  return out;
}

}  // namespace palpa::material
