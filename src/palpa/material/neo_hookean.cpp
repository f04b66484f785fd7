// SPDX-License-Identifier: AGPL-3.0-or-later
#include <fmt/format.h>

#include <cmath>

#include "palpa/core/error.hpp"
#include "palpa/material/elastic_constants.hpp"
#include "palpa/material/models.hpp"

namespace palpa::material {

NeoHookean::NeoHookean(double young, double poisson, double volume_share, bool volume_term)
    : volume_term_(volume_term), young_(young), poisson_(poisson), share_(volume_share) {
  update();
}

NeoHookean::NeoHookean(double young, double poisson) : NeoHookean(young, poisson, 0.0, false) {}

NeoHookean NeoHookean::with_volume_term(double young, double poisson, double volume_share) {
  return NeoHookean(young, poisson, volume_share, true);
}

void NeoHookean::update() {
  require_positive(young_, "E");
  require_poisson(poisson_);
  if (volume_term_) {
    require_finite(share_, "volume_share");
    if (share_ < 0.0 || share_ > 1.0) {
      throw_input_error(fmt::format("parameter volume_share = {} is outside [0, 1]", share_),
                        ErrorContext{}, "a share between 0 and 1");
    }
  }
  const LameWithDerivatives l = lame_with_derivatives(young_, poisson_);
  mu_ = l.mu;
  lambda_ = l.lambda;
  dmu_dE_ = l.dmu_dE;
  dmu_dnu_ = l.dmu_dnu;
  dlam_dE_ = l.dlambda_dE;
  dlam_dnu_ = l.dlambda_dnu;
}

std::string_view NeoHookean::model() const noexcept {
  return volume_term_ ? "neo-hookean-volume" : "neo-hookean";
}

std::string NeoHookean::description() const {
  if (!volume_term_) {
    return "compressible neo-Hookean: mu/2 (I_C - 3) - mu ln J + lambda/2 (ln J)^2; "
           "volumetric term: logarithmic, lambda/2 (ln J)^2";
  }
  return "neo-Hookean with a volume-preservation term: mu/2 (I_C - 3) - mu ln J "
         "+ (1-s) lambda/2 (ln J)^2 + s lambda/2 (J - 1)^2; volumetric terms: logarithmic "
         "(share 1-s) and quadratic in J - 1 (share s) of Lame's lambda";
}

ParamInfo NeoHookean::param_info(Eigen::Index k) const {
  switch (k) {
    case 0: return {"E", Dimension::Pressure, "Young's modulus (small strain)"};
    case 1: return {"nu", Dimension::Dimensionless, "Poisson's ratio (small strain)"};
    default:
      return {"volume_share", Dimension::Dimensionless,
              "share s of Lame's lambda carried by the (J - 1)^2 volume term"};
  }
}

Eigen::VectorXd NeoHookean::params() const {
  Eigen::VectorXd t(num_params());
  t[0] = young_;
  t[1] = poisson_;
  if (volume_term_) t[2] = share_;
  return t;
}

void NeoHookean::set_params(const Eigen::VectorXd& theta) {
  NeoHookean next = *this;
  next.young_ = theta[0];
  next.poisson_ = theta[1];
  if (volume_term_) next.share_ = theta[2];
  next.update();
  *this = next;
}

std::unique_ptr<Material> NeoHookean::clone() const { return std::make_unique<NeoHookean>(*this); }

Scalar3 NeoHookean::raw_part(Part p, double x) const {
  if (p == Part::F) return Scalar3{0.5 * mu_ * (x * x - 1.0), mu_ * x, mu_};
  // H: -μ ln J + a/2 (ln J)² + κ/2 (J − 1)²
  const double a = (1.0 - share_) * lambda_;
  const double kappa = share_ * lambda_;
  const double lj = std::log(x);
  const double inv = 1.0 / x;
  return Scalar3{-mu_ * lj + 0.5 * a * lj * lj + 0.5 * kappa * (x - 1.0) * (x - 1.0),
                 -mu_ * inv + a * lj * inv + kappa * (x - 1.0),
                 (mu_ + a * (1.0 - lj)) * inv * inv + kappa};
}

void NeoHookean::accumulate_part_dparam(Part p, double x, double w1, double w2,
                                        Eigen::Ref<Eigen::MatrixXd> out, Eigen::Index row) const {
  if (p == Part::F) {
    const double dmu = w1 * x + w2;  // ∂f′/∂μ = x, ∂f″/∂μ = 1
    out(row, 0) += dmu * dmu_dE_;
    out(row, 1) += dmu * dmu_dnu_;
    return;
  }
  const double lj = std::log(x);
  const double inv = 1.0 / x;
  const double dmu = -w1 * inv + w2 * inv * inv;
  const double da = w1 * lj * inv + w2 * (1.0 - lj) * inv * inv;
  const double dkappa = w1 * (x - 1.0) + w2;
  // a = (1 − s) λ, κ = s λ
  const double s = share_;
  const double dlam = (1.0 - s) * da + s * dkappa;
  out(row, 0) += dmu * dmu_dE_ + dlam * dlam_dE_;
  out(row, 1) += dmu * dmu_dnu_ + dlam * dlam_dnu_;
  if (volume_term_) out(row, 2) += lambda_ * (dkappa - da);
}

}  // namespace palpa::material
