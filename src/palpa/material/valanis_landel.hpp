// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Valanis–Landel separable energies (thesis eq. 1.12 / 6.1):
//   Ψ(λ) = Σi f(λi) + Σ(i<j) g(λi λj) + h(λ1 λ2 λ3).
// A model supplies f, g, h (and their parameter derivatives) for arguments at or
// above kContinuationThreshold where it needs one; this base evaluates Ψ and
// its exact λ-derivatives, continues each function quadratically below the
// threshold (so inverted elements, J < 0, stay finite and restoring), and
// assembles ∂²Ψ/∂λ∂θ.
//
// Derivatives (i, j, k distinct; the thesis's 6.4 omits the g′ and h′ terms):
//   ∂Ψ/∂λi      = f′(λi) + λj g′(λiλj) + λk g′(λiλk) + λjλk h′(J)
//   ∂²Ψ/∂λi²    = f″(λi) + λj² g″(λiλj) + λk² g″(λiλk) + (λjλk)² h″(J)
//   ∂²Ψ/∂λi∂λj  = g′(λiλj) + λiλj g″(λiλj) + λk h′(J) + λiλjλk² h″(J)

#include "palpa/material/material.hpp"
#include "palpa/material/scalar_function.hpp"

namespace palpa::material {

class ValanisLandelMaterial : public Material {
 public:
  enum class Part { F, G, H };

  void evaluate(const Vec3& lambda, EvalOrder order, StretchEnergy& out) const final;
  void d2psi_dlambda_dparam(const Vec3& lambda, Eigen::Ref<Eigen::MatrixXd> out) const final;

  // The separable functions as used in Ψ (continuation included). Used to sample
  // a model into a spline material, and for plots.
  Scalar3 part(Part p, double x) const;
  // False if the part is identically zero for this model.
  virtual bool has_part(Part p) const noexcept = 0;

 protected:
  ValanisLandelMaterial() = default;
  ValanisLandelMaterial(const ValanisLandelMaterial&) = default;
  ValanisLandelMaterial& operator=(const ValanisLandelMaterial&) = default;

  // The model's own function (x >= kContinuationThreshold where
  // needs_continuation(p), any real x otherwise).
  virtual Scalar3 raw_part(Part p, double x) const = 0;
  // out(row, k) += w1 ∂(raw′)/∂θk (x) + w2 ∂(raw″)/∂θk (x), for every k.
  virtual void accumulate_part_dparam(Part p, double x, double w1, double w2,
                                      Eigen::Ref<Eigen::MatrixXd> out, Eigen::Index row) const = 0;
  // Whether the part is singular or undefined somewhere below the threshold
  // (ln x, x^α ...). Polynomials need no continuation.
  virtual bool needs_continuation(Part p) const noexcept = 0;

 private:
  // Adds w * ∂(part′)/∂θ at x to row `row` of out, continuation included.
  void add_part_dparam(Part p, double x, double w, Eigen::Ref<Eigen::MatrixXd> out,
                       Eigen::Index row) const;
};

}  // namespace palpa::material
