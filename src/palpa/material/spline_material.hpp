// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Valanis–Landel spline material (thesis §6.1): f, g, h are natural cubic
// splines with log-uniform knots; the control values are the parameters
// θ = (y_f, y_g, y_h) [Pa], in that order.
//
// Stress-free rest state by construction: the energy is
//   Ψ = Σ f(λi) + Σ g(λiλj) + h(J) − c ln J − Ψ0,
//   c  = f′(1) + 2 g′(1) + h′(1),   Ψ0 = 3 f(1) + 3 g(1) + h(1),
// so ∂Ψ/∂λ = 0 and Ψ = 0 at λ = (1,1,1) for any control values; c and Ψ0 are
// linear in θ, and ∂²Ψ/∂λ∂θ includes them exactly. (The term −c ln J is
// separable — it equals −c Σ ln λi — so this is still a Valanis–Landel energy.)
// Outside the knot ranges each spline continues as a parabola (spline.hpp); the
// logarithm is continued below J = kContinuationThreshold (inverted elements).

#include "palpa/material/spline.hpp"
#include "palpa/material/valanis_landel.hpp"

namespace palpa::material {

struct SplineRange {
  double lo;  // smallest knot (> 0)
  double hi;  // largest knot
  int knots;  // number of knots (>= 3)
};

// Knot ranges: f over single stretches, g over products of two stretches, h over
// the volume ratio J.
struct SplineLayout {
  SplineRange f{0.5, 2.0, 8};
  SplineRange g{0.4, 2.5, 8};
  SplineRange h{0.6, 1.6, 8};
};

class SplineMaterial final : public ValanisLandelMaterial {
 public:
  SplineMaterial(NaturalCubicSpline f, NaturalCubicSpline g, NaturalCubicSpline h);

  // The spline material that reproduces `model`: a Valanis–Landel model is
  // sampled at the knots (its f, g, h); any other model is projected by linear
  // least squares on its stresses over the knot ranges.
  static SplineMaterial from_model(const Material& model, const SplineLayout& layout = {});
  // The spline material whose stresses match `model`'s best (linear least
  // squares over its traction-free uniaxial, equibiaxial and planar paths
  // across the f range, each also compressed and dilated a little). For a
  // Valanis–Landel model this beats sampling f, g, h at the knots where
  // stresses count: the stress is the splines' slope, which knot sampling
  // gets wrong by O(h²) and a natural spline's end intervals bend.
  static SplineMaterial fit_stresses(const Material& model, const SplineLayout& layout = {});

  std::string_view model() const noexcept override { return "spline"; }
  std::string description() const override;
  Eigen::Index num_params() const noexcept override;
  ParamInfo param_info(Eigen::Index k) const override;
  Eigen::VectorXd params() const override;
  void set_params(const Eigen::VectorXd& theta) override;
  std::unique_ptr<Material> clone() const override;
  bool has_part(Part) const noexcept override { return true; }

  const NaturalCubicSpline& spline(Part p) const noexcept;
  // c of the rest-state correction, −c ln J [Pa].
  double rest_correction() const noexcept { return c_; }

 protected:
  Scalar3 raw_part(Part p, double x) const override;
  void accumulate_part_dparam(Part p, double x, double w1, double w2,
                              Eigen::Ref<Eigen::MatrixXd> out, Eigen::Index row) const override;
  bool needs_continuation(Part p) const noexcept override { return p == Part::H; }

 private:
  void update_rest_terms();
  Eigen::Index offset(Part p) const noexcept;

  NaturalCubicSpline f_;
  NaturalCubicSpline g_;
  NaturalCubicSpline h_;
  double c_ = 0.0;
  double psi0_ = 0.0;
  Eigen::VectorXd dc_;  // ∂c/∂θ (depends on the knots only)
};

}  // namespace palpa::material
