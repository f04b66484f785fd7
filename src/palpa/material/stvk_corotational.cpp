// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/material/elastic_constants.hpp"
#include "palpa/material/models.hpp"

namespace palpa::material {

YoungPoissonMaterial::YoungPoissonMaterial(double young, double poisson)
    : young_(young), poisson_(poisson) {
  lame_from_young(young_, poisson_);  // validates
}

ParamInfo YoungPoissonMaterial::param_info(Eigen::Index k) const {
  if (k == 0) return {"E", Dimension::Pressure, "Young's modulus (small strain)"};
  return {"nu", Dimension::Dimensionless, "Poisson's ratio (small strain)"};
}

Eigen::VectorXd YoungPoissonMaterial::params() const { return Eigen::Vector2d(young_, poisson_); }

void YoungPoissonMaterial::set_params(const Eigen::VectorXd& theta) {
  lame_from_young(theta[0], theta[1]);
  young_ = theta[0];
  poisson_ = theta[1];
}

namespace {

// Writes ∂grad/∂(E, ν) from ∂grad/∂μ and ∂grad/∂λ.
void chain_to_young_poisson(const LameWithDerivatives& l, const Vec3& dg_dmu, const Vec3& dg_dlam,
                            Eigen::Ref<Eigen::MatrixXd> out) {
  out.col(0) = l.dmu_dE * dg_dmu + l.dlambda_dE * dg_dlam;
  out.col(1) = l.dmu_dnu * dg_dmu + l.dlambda_dnu * dg_dlam;
}
}  // namespace

// ---------------------------------------------------------------- StVK

std::string StVenantKirchhoff::description() const {
  return "Saint Venant-Kirchhoff: lambda/8 (I_C - 3)^2 + mu/4 (II_C - 2 I_C + 3), II_C = C:C; "
         "volumetric term: none separate (lambda/8 (I_C - 3)^2; softens under strong compression)";
}

std::unique_ptr<Material> StVenantKirchhoff::clone() const {
  return std::make_unique<StVenantKirchhoff>(*this);
}

void StVenantKirchhoff::evaluate(const Vec3& l, EvalOrder order, StretchEnergy& out) const {
  const LameWithDerivatives lame = lame_with_derivatives(young_, poisson_);
  const Vec3 l2 = l.cwiseAbs2();
  const double ic = l2.sum();
  const double iic = l2.squaredNorm();
  out.psi = lame.lambda / 8.0 * (ic - 3.0) * (ic - 3.0) + lame.mu / 4.0 * (iic - 2.0 * ic + 3.0);
  if (order == EvalOrder::Energy) return;
  for (int i = 0; i < 3; ++i) {
    out.grad[i] = 0.5 * lame.lambda * (ic - 3.0) * l[i] + lame.mu * (l2[i] * l[i] - l[i]);
  }
  if (order == EvalOrder::Gradient) return;
  out.hess = lame.lambda * l * l.transpose();
  for (int i = 0; i < 3; ++i) {
    out.hess(i, i) += 0.5 * lame.lambda * (ic - 3.0) + lame.mu * (3.0 * l2[i] - 1.0);
  }
}

void StVenantKirchhoff::d2psi_dlambda_dparam(const Vec3& l, Eigen::Ref<Eigen::MatrixXd> out) const {
  const LameWithDerivatives lame = lame_with_derivatives(young_, poisson_);
  const double ic = l.squaredNorm();
  const Vec3 dg_dlam = 0.5 * (ic - 3.0) * l;
  const Vec3 dg_dmu = l.cwiseAbs2().cwiseProduct(l) - l;
  chain_to_young_poisson(lame, dg_dmu, dg_dlam, out);
}

// ---------------------------------------------------------------- corotational

std::string Corotational::description() const {
  return "linear corotational: mu sum_i (lambda_i - 1)^2 + lambda/2 (sum_i lambda_i - 3)^2; "
         "volumetric term: linearized, lambda/2 (tr(S) - 3)^2";
}

std::unique_ptr<Material> Corotational::clone() const {
  return std::make_unique<Corotational>(*this);
}

void Corotational::evaluate(const Vec3& l, EvalOrder order, StretchEnergy& out) const {
  const LameWithDerivatives lame = lame_with_derivatives(young_, poisson_);
  const Vec3 e = l - Vec3::Ones();
  const double tr = e.sum();
  out.psi = lame.mu * e.squaredNorm() + 0.5 * lame.lambda * tr * tr;
  if (order == EvalOrder::Energy) return;
  out.grad = 2.0 * lame.mu * e + Vec3::Constant(lame.lambda * tr);
  if (order == EvalOrder::Gradient) return;
  out.hess = Mat3::Constant(lame.lambda) + 2.0 * lame.mu * Mat3::Identity();
}

void Corotational::d2psi_dlambda_dparam(const Vec3& l, Eigen::Ref<Eigen::MatrixXd> out) const {
  const LameWithDerivatives lame = lame_with_derivatives(young_, poisson_);
  const Vec3 e = l - Vec3::Ones();
  chain_to_young_poisson(lame, 2.0 * e, Vec3::Constant(e.sum()), out);
}

}  // namespace palpa::material
