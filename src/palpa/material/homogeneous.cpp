#include "palpa/material/homogeneous.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

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

}  // namespace palpa::material
