// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The classic isotropic models, each exact (energy, λ-derivatives and parameter
// derivatives in closed form). Parameters are SI. See material.hpp for the
// common contract (stress-free rest state, signed stretches).
//
//   model name              parameters θ                 energy
//   neo-hookean             E, nu                        μ/2 (I_C − 3) − μ ln J + λ/2 (ln J)²
//   neo-hookean-volume      E, nu, volume_share          μ/2 (I_C − 3) − μ ln J + (1−s)λ/2 (ln J)²
//                                                        + sλ/2 (J − 1)²   (default tissue model)
//   neo-hookean-isochoric   C10, D1                      C10 (Ī1 − 3) + (J − 1)²/D1
//   mooney-rivlin           C10, C01, D1                 C10 (Ī1 − 3) + C01 (Ī2 − 3) + (J − 1)²/D1
//   yeoh                    C10, C20, C30, D1            Σ Ci0 (Ī1 − 3)^i + (J − 1)²/D1
//   stvk                    E, nu                        λ/8 (I_C − 3)² + μ/4 (II_C − 2 I_C + 3)
//   corotational            E, nu                        μ Σ(λi − 1)² + λ/2 (Σλi − 3)²
//   ogden                   mu[p], alpha[p], nu          Σp μp/αp Σi (λi^αp − 1) − (Σp μp) ln J
//                                                        + λ/2 (ln J)²,  λ = 2μ0ν/(1 − 2ν),
//                                                        μ0 = ½ Σp μp αp
// (μ, λ: Lamé parameters of (E, ν); Ī1 = J^(−2/3) I1, Ī2 = J^(−4/3) I2 with
// I2 = λ1²λ2² + λ2²λ3² + λ3²λ1²; D1 follows the convention of Abaqus, CalculiX
// and FEBio, where the bulk modulus at rest is K = 2/D1.)

#include <vector>

#include "palpa/material/valanis_landel.hpp"

namespace palpa::material {

// Compressible neo-Hookean (Bonet & Wood form), optionally with an added
// volume-preservation term (thesis §7.3.3). E and ν are the small-strain
// constants of the whole material; `volume_share` s ∈ [0, 1] is the share of
// Lamé's λ carried by sλ/2 (J − 1)² instead of (1−s)λ/2 (ln J)². The two agree at
// small strain; at finite strain the (J − 1)² term resists volume growth more
// strongly, the logarithm resists collapse (it grows without bound as J → 0).
class NeoHookean final : public ValanisLandelMaterial {
 public:
  NeoHookean(double young, double poisson);
  static NeoHookean with_volume_term(double young, double poisson, double volume_share);

  std::string_view model() const noexcept override;
  std::string description() const override;
  Eigen::Index num_params() const noexcept override { return volume_term_ ? 3 : 2; }
  ParamInfo param_info(Eigen::Index k) const override;
  Eigen::VectorXd params() const override;
  void set_params(const Eigen::VectorXd& theta) override;
  std::unique_ptr<Material> clone() const override;
  bool has_part(Part p) const noexcept override { return p != Part::G; }

 protected:
  Scalar3 raw_part(Part p, double x) const override;
  void accumulate_part_dparam(Part p, double x, double w1, double w2,
                              Eigen::Ref<Eigen::MatrixXd> out, Eigen::Index row) const override;
  bool needs_continuation(Part p) const noexcept override { return p == Part::H; }

 private:
  NeoHookean(double young, double poisson, double volume_share, bool volume_term);
  void update();

  bool volume_term_;
  double young_;
  double poisson_;
  double share_;
  // Derived: Lamé parameters and their (E, ν) derivatives.
  double mu_ = 0.0, lambda_ = 0.0;
  double dmu_dE_ = 0.0, dmu_dnu_ = 0.0, dlam_dE_ = 0.0, dlam_dnu_ = 0.0;
};

// Ogden in Valanis–Landel form, made compressible and stress-free by a
// logarithmic volumetric term (see the table above). With one term, α = 2 and
// μ1 = μ it is exactly neo-Hookean. Requires αp ≠ 0 and μ0 = ½ Σ μp αp > 0.
class Ogden final : public ValanisLandelMaterial {
 public:
  Ogden(std::vector<double> mu, std::vector<double> alpha, double poisson);

  std::string_view model() const noexcept override { return "ogden"; }
  std::string description() const override;
  Eigen::Index num_params() const noexcept override;
  ParamInfo param_info(Eigen::Index k) const override;
  Eigen::VectorXd params() const override;
  void set_params(const Eigen::VectorXd& theta) override;
  std::unique_ptr<Material> clone() const override;
  bool has_part(Part p) const noexcept override { return p != Part::G; }

  Eigen::Index num_terms() const noexcept { return static_cast<Eigen::Index>(mu_.size()); }

 protected:
  Scalar3 raw_part(Part p, double x) const override;
  void accumulate_part_dparam(Part p, double x, double w1, double w2,
                              Eigen::Ref<Eigen::MatrixXd> out, Eigen::Index row) const override;
  bool needs_continuation(Part) const noexcept override { return true; }

 private:
  void validate_and_update();

  std::vector<double> mu_;
  std::vector<double> alpha_;
  double poisson_;
  double mu_sum_ = 0.0;  // Σ μp (coefficient of −ln J)
  double mu0_ = 0.0;     // small-strain shear modulus
  double lambda_ = 0.0;  // 2 μ0 ν / (1 − 2ν)
};

// Base of the models written directly in λ and parametrized by (E, ν): holds
// and validates the parameters; the model supplies the energy.
class YoungPoissonMaterial : public Material {
 public:
  Eigen::Index num_params() const noexcept final { return 2; }
  ParamInfo param_info(Eigen::Index k) const final;
  Eigen::VectorXd params() const final;
  void set_params(const Eigen::VectorXd& theta) final;

 protected:
  YoungPoissonMaterial(double young, double poisson);
  double young_;
  double poisson_;
};

// Saint Venant–Kirchhoff (thesis 1.8), with II_C = C:C. Softens and collapses
// under strong compression: a reference model, not a tissue model.
class StVenantKirchhoff final : public YoungPoissonMaterial {
 public:
  StVenantKirchhoff(double young, double poisson) : YoungPoissonMaterial(young, poisson) {}
  std::string_view model() const noexcept override { return "stvk"; }
  std::string description() const override;
  void evaluate(const Vec3& lambda, EvalOrder order, StretchEnergy& out) const override;
  void d2psi_dlambda_dparam(const Vec3& lambda, Eigen::Ref<Eigen::MatrixXd> out) const override;
  std::unique_ptr<Material> clone() const override;
};

// Linear corotational: μ Σ(λi − 1)² + λ/2 (Σλi − 3)², linear elasticity in the
// rotated frame. (The thesis's 1.13 splits this into f and g with a sign slip
// in the μ terms that would make the rest state unstable; this is the standard
// form.)
class Corotational final : public YoungPoissonMaterial {
 public:
  Corotational(double young, double poisson) : YoungPoissonMaterial(young, poisson) {}
  std::string_view model() const noexcept override { return "corotational"; }
  std::string description() const override;
  void evaluate(const Vec3& lambda, EvalOrder order, StretchEnergy& out) const override;
  void d2psi_dlambda_dparam(const Vec3& lambda, Eigen::Ref<Eigen::MatrixXd> out) const override;
  std::unique_ptr<Material> clone() const override;
};

// The isochoric-invariant family of Abaqus, CalculiX and FEBio:
//   Ψ = Σ_{i=1..3} Ci0 (Ī1 − 3)^i + C01 (Ī2 − 3) + (J − 1)²/D1.
// neo-hookean-isochoric: C10, D1; mooney-rivlin: C10, C01, D1 (thesis 1.10,
// with their D1 = 1/D1 here); yeoh: C10, C20, C30, D1 (thesis 1.11 made
// isochoric, as those tools define it, so that it is stress-free at rest).
// Small strain: μ = 2 (C10 + C01), K = 2/D1. The factors J^(−2/3), J^(−4/3) are
// continued quadratically below J = kContinuationThreshold.
class IsochoricInvariant final : public Material {
 public:
  enum class Kind { NeoHookean, MooneyRivlin, Yeoh };
  static IsochoricInvariant neo_hookean(double c10, double d1);
  static IsochoricInvariant mooney_rivlin(double c10, double c01, double d1);
  static IsochoricInvariant yeoh(double c10, double c20, double c30, double d1);

  std::string_view model() const noexcept override;
  std::string description() const override;
  Eigen::Index num_params() const noexcept override;
  ParamInfo param_info(Eigen::Index k) const override;
  Eigen::VectorXd params() const override;
  void set_params(const Eigen::VectorXd& theta) override;
  void evaluate(const Vec3& lambda, EvalOrder order, StretchEnergy& out) const override;
  void d2psi_dlambda_dparam(const Vec3& lambda, Eigen::Ref<Eigen::MatrixXd> out) const override;
  std::unique_ptr<Material> clone() const override;

  Kind kind() const noexcept { return kind_; }

 private:
  IsochoricInvariant(Kind kind, double c10, double c01, double c20, double c30, double d1);
  void validate() const;

  Kind kind_;
  double c10_, c01_, c20_, c30_, d1_;
};

}  // namespace palpa::material
