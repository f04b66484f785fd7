// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/material/spline_material.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <limits>

#include "palpa/core/error.hpp"

namespace palpa::material {

SplineMaterial::SplineMaterial(NaturalCubicSpline f, NaturalCubicSpline g, NaturalCubicSpline h)
    : f_(std::move(f)), g_(std::move(g)), h_(std::move(h)) {
  dc_ = Eigen::VectorXd::Zero(num_params());
  f_.accumulate_basis(1.0, 0.0, 1.0, 0.0, dc_.data() + offset(Part::F), 1);
  g_.accumulate_basis(1.0, 0.0, 2.0, 0.0, dc_.data() + offset(Part::G), 1);
  h_.accumulate_basis(1.0, 0.0, 1.0, 0.0, dc_.data() + offset(Part::H), 1);
  update_rest_terms();
}

void SplineMaterial::update_rest_terms() {
  const Scalar3 f1 = f_.evaluate(1.0);
  const Scalar3 g1 = g_.evaluate(1.0);
  const Scalar3 h1 = h_.evaluate(1.0);
  c_ = f1.d1 + 2.0 * g1.d1 + h1.d1;
  psi0_ = 3.0 * f1.v + 3.0 * g1.v + h1.v;
}

Eigen::Index SplineMaterial::offset(Part p) const noexcept {
  switch (p) {
    case Part::F: return 0;
    case Part::G: return f_.size();
    case Part::H: return f_.size() + g_.size();
  }
  return 0;
}

const NaturalCubicSpline& SplineMaterial::spline(Part p) const noexcept {
  switch (p) {
    case Part::F: return f_;
    case Part::G: return g_;
    case Part::H: return h_;
  }
  return f_;
}

std::string SplineMaterial::description() const {
  return fmt::format(
      "Valanis-Landel spline material: sum_i f(lambda_i) + sum_i<j g(lambda_i lambda_j) + h(J) "
      "- c ln J - Psi0 with natural cubic splines f ({} knots in [{:.4g}, {:.4g}]), g ({} knots in "
      "[{:.4g}, {:.4g}]), h ({} knots in [{:.4g}, {:.4g}]); c = {:.6g} Pa keeps the rest state "
      "stress-free; volumetric term: the spline h(J) (with -c ln J)",
      f_.size(), f_.knots().front(), f_.knots().back(), g_.size(), g_.knots().front(),
      g_.knots().back(), h_.size(), h_.knots().front(), h_.knots().back(), c_);
}

Eigen::Index SplineMaterial::num_params() const noexcept {
  return f_.size() + g_.size() + h_.size();
}

ParamInfo SplineMaterial::param_info(Eigen::Index k) const {
  const char* name = "h";
  Eigen::Index local = k - offset(Part::H);
  const NaturalCubicSpline* s = &h_;
  if (k < offset(Part::G)) {
    name = "f";
    local = k;
    s = &f_;
  } else if (k < offset(Part::H)) {
    name = "g";
    local = k - offset(Part::G);
    s = &g_;
  }
  return {fmt::format("{}[{}]", name, local), Dimension::Pressure,
          fmt::format("value of {} at knot {:.6g}", name, s->knots()[static_cast<std::size_t>(local)])};
}

Eigen::VectorXd SplineMaterial::params() const {
  Eigen::VectorXd t(num_params());
  for (Part p : {Part::F, Part::G, Part::H}) {
    const auto& s = spline(p);
    t.segment(offset(p), s.size()) = Eigen::Map<const Eigen::VectorXd>(s.values().data(), s.size());
  }
  return t;
}

void SplineMaterial::set_params(const Eigen::VectorXd& theta) {
  for (Eigen::Index k = 0; k < theta.size(); ++k) require_finite(theta[k], param_info(k).name);
  f_.set_values(theta.data() + offset(Part::F));
  g_.set_values(theta.data() + offset(Part::G));
  h_.set_values(theta.data() + offset(Part::H));
  update_rest_terms();
}

std::unique_ptr<Material> SplineMaterial::clone() const {
  return std::make_unique<SplineMaterial>(*this);
}

Scalar3 SplineMaterial::raw_part(Part p, double x) const {
  switch (p) {
    case Part::F: return f_.evaluate(x);
    case Part::G: return g_.evaluate(x);
    case Part::H: break;
  }
  const Scalar3 s = h_.evaluate(x);
  const double inv = 1.0 / x;
  return Scalar3{s.v - c_ * std::log(x) - psi0_, s.d1 - c_ * inv, s.d2 + c_ * inv * inv};
}

void SplineMaterial::accumulate_part_dparam(Part p, double x, double w1, double w2,
                                            Eigen::Ref<Eigen::MatrixXd> out,
                                            Eigen::Index row) const {
  spline(p).accumulate_basis(x, 0.0, w1, w2, &out(row, offset(p)), out.outerStride());
  if (p == Part::H) {
    const double inv = 1.0 / x;
    out.row(row) += (-w1 * inv + w2 * inv * inv) * dc_.transpose();
  }
}

namespace {

// Traction-free lateral stretch t for λ = (s, a t, t) paths (a = t: uniaxial
// handled by the caller's lambda), found by bisection on ∂Ψ/∂λ3.
double free_stretch(const Material& m, const std::function<Vec3(double)>& state) {
  double lo = 0.05;
  double hi = 20.0;
  const auto r = [&](double t) { return m.dpsi_dlambda(state(t))[2]; };
  if (!(r(lo) < 0.0 && r(hi) > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  for (int it = 0; it < 200 && hi - lo > 1e-14 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (r(mid) > 0.0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

std::vector<Vec3> characteristic_states(const Material& m, const SplineLayout& layout) {
  std::vector<Vec3> states;
  const std::vector<double> loads = NaturalCubicSpline::log_uniform_knots(layout.f.lo, layout.f.hi, 25);
  const std::vector<std::function<Vec3(double, double)>> paths = {
      [](double s, double t) { return Vec3(s, t, t); },    // uniaxial
      [](double s, double t) { return Vec3(s, s, t); },    // equibiaxial
      [](double s, double t) { return Vec3(s, 1.0, t); },  // planar
  };
  // Hydrostatic states over the h range pin down the volumetric response.
  for (double j : NaturalCubicSpline::log_uniform_knots(layout.h.lo, layout.h.hi, 25)) {
    states.push_back(Vec3::Constant(std::cbrt(j)));
  }
  for (const auto& path : paths) {
    for (double s : loads) {
      const double t = free_stretch(m, [&](double x) { return path(s, x); });
      if (!std::isfinite(t)) continue;
      for (double dv : {-0.04, -0.015, 0.0, 0.015, 0.04}) {
        states.push_back(path(s, t) * std::cbrt(1.0 + dv));
      }
    }
  }
  return states;
}

NaturalCubicSpline sampled(const ValanisLandelMaterial* vl, ValanisLandelMaterial::Part p,
                           const SplineRange& r, const char* name) {
  std::vector<double> x = NaturalCubicSpline::log_uniform_knots(r.lo, r.hi, r.knots);
  std::vector<double> y(x.size(), 0.0);
  if (vl != nullptr && vl->has_part(p)) {
    for (std::size_t k = 0; k < x.size(); ++k) y[k] = vl->part(p, x[k]).v;
  }
  return NaturalCubicSpline(std::move(x), std::move(y), name);
}

}  // namespace

SplineMaterial SplineMaterial::from_model(const Material& model, const SplineLayout& layout) {
  using Part = ValanisLandelMaterial::Part;
  const auto* vl = dynamic_cast<const ValanisLandelMaterial*>(&model);
  SplineMaterial out(sampled(vl, Part::F, layout.f, "f"), sampled(vl, Part::G, layout.g, "g"),
                     sampled(vl, Part::H, layout.h, "h"));
  if (vl != nullptr) return out;
  return fit_stresses(model, layout);
}

SplineMaterial SplineMaterial::fit_stresses(const Material& model, const SplineLayout& layout) {
  using Part = ValanisLandelMaterial::Part;
  SplineMaterial out(sampled(nullptr, Part::F, layout.f, "f"), sampled(nullptr, Part::G, layout.g, "g"),
                     sampled(nullptr, Part::H, layout.h, "h"));

  // Least-squares projection of the model's stresses. ∂Ψ/∂λ of the spline
  // material is linear in θ with matrix ∂²Ψ/∂λ∂θ, so each sample gives three
  // linear equations. The samples are the states the model itself goes
  // through: its traction-free uniaxial, equibiaxial and planar (λ2 = 1) load
  // paths over the f range, each also compressed and dilated a little so that
  // the volumetric response is pinned down too.
  const std::vector<Vec3> samples = characteristic_states(model, layout);
  const Eigen::Index p = out.num_params();
  const Eigen::Index rows = 3 * static_cast<Eigen::Index>(samples.size());
  const double scale = std::abs(small_strain_constants(model).mu);
  // Curvature rows: a small penalty on ∫ S″² of each spline (S″ at the knots is
  // z = M y) keeps directions the samples do not constrain smooth instead of
  // arbitrary.
  constexpr double kSmoothing = 1e-3;
  Eigen::Index smooth_rows = 0;
  for (Part part : {Part::F, Part::G, Part::H}) smooth_rows += out.spline(part).size();
  Eigen::MatrixXd a_mat = Eigen::MatrixXd::Zero(rows + smooth_rows, p);
  Eigen::VectorXd b_vec = Eigen::VectorXd::Zero(rows + smooth_rows);
  Eigen::MatrixXd block(3, p);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    out.d2psi_dlambda_dparam(samples[i], block);
    const Vec3 target = model.dpsi_dlambda(samples[i]);
    // Relative weighting: stiff volumetric samples must not drown the rest.
    const double w = 1.0 / (target.norm() + scale);
    a_mat.middleRows(3 * static_cast<Eigen::Index>(i), 3) = w * block;
    b_vec.segment<3>(3 * static_cast<Eigen::Index>(i)) = w * target;
  }
  Eigen::Index row = rows;
  for (Part part : {Part::F, Part::G, Part::H}) {
    const NaturalCubicSpline& sp = out.spline(part);
    const std::vector<double>& x = sp.knots();
    for (Eigen::Index k = 0; k < sp.size(); ++k, ++row) {
      // S″(x_k) as a linear function of this spline's values, weighted by the
      // knot's share of the interval lengths.
      const double left = k > 0 ? x[static_cast<std::size_t>(k)] - x[static_cast<std::size_t>(k - 1)] : 0.0;
      const double right = k + 1 < sp.size() ? x[static_cast<std::size_t>(k + 1)] - x[static_cast<std::size_t>(k)] : 0.0;
      const double w = kSmoothing * std::sqrt(0.5 * (left + right)) / scale;
      sp.accumulate_basis(x[static_cast<std::size_t>(k)], 0.0, 0.0, w, &a_mat(row, out.offset(part)),
                          a_mat.outerStride());
    }
  }
  // The Valanis–Landel split is not unique (a ln x added to f and −a ln J to h
  // give the same stresses; constants never matter): the minimum-norm solution
  // picks one.
  const Eigen::VectorXd theta = a_mat.completeOrthogonalDecomposition().solve(b_vec);
  out.set_params(theta);
  return out;
}

}  // namespace palpa::material
