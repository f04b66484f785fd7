// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Isotropic hyperelastic energies in principal stretches (thesis §1.1.2, §6.1).
//
// A Material is an energy density Ψ(λ1, λ2, λ3) [Pa = J/m^3] of the singular
// values λi of the deformation gradient F, with its exact first and second
// derivatives in λ and, for every model parameter θk, the mixed derivative
// ∂²Ψ/∂λ∂θk that material fitting needs. Stretches are signed: an inverted
// element has λ3 < 0 (see kinematics.hpp), and every model is defined there too,
// so a simulation that briefly inverts gets finite, restoring forces, never NaN.
//
// Every model is stress-free at rest (∂Ψ/∂λ = 0 at λ = (1,1,1)) and has
// Ψ(1,1,1) = 0.
//
// Objects are immutable during evaluation (all evaluation methods are const and
// keep no scratch state), so one object may be shared by parallel loops.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <string_view>

#include "palpa/core/psd_projection.hpp"
#include "palpa/core/units.hpp"

namespace palpa::material {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// How an indefinite stretch-space Hessian is made positive semi-definite
// (core/psd_projection.hpp).
using palpa::PsdProjection;

// Which derivatives evaluate() computes.
enum class EvalOrder { Energy = 0, Gradient = 1, Hessian = 2 };

// Ψ and its derivatives at one stretch triple.
struct StretchEnergy {
  double psi = 0.0;            // [Pa]
  Vec3 grad = Vec3::Zero();    // ∂Ψ/∂λ [Pa]
  Mat3 hess = Mat3::Zero();    // ∂²Ψ/∂λ² [Pa]
};

// Name, unit kind and meaning of one model parameter.
struct ParamInfo {
  std::string name;       // "E", "nu", "mu[1]", "f[3]"
  Dimension dimension;    // Pressure for moduli, Dimensionless for ratios
  std::string meaning;    // "Young's modulus (small strain)"
};

// Small-strain (linearized at rest) elastic constants.
struct ElasticConstants {
  double mu = 0.0;      // shear modulus [Pa]
  double lambda = 0.0;  // Lamé's first parameter [Pa]
  double young() const noexcept;    // E [Pa]
  double poisson() const noexcept;  // ν
  double bulk() const noexcept;     // K [Pa]
};

class Material {
 public:
  virtual ~Material() = default;

  // Model name as used in material files ("neo-hookean").
  virtual std::string_view model() const noexcept = 0;
  // One-paragraph description: the energy, and which volumetric term it uses.
  virtual std::string description() const = 0;

  virtual Eigen::Index num_params() const noexcept = 0;
  virtual ParamInfo param_info(Eigen::Index k) const = 0;
  // Current parameters θ, in SI.
  virtual Eigen::VectorXd params() const = 0;
  // Replaces θ (size num_params(), SI). Throws palpa::Error (Input) naming the
  // parameter if a value is non-finite or non-physical.
  virtual void set_params(const Eigen::VectorXd& theta) = 0;

  // Ψ(λ) and, depending on `order`, ∂Ψ/∂λ and ∂²Ψ/∂λ². Allocation-free.
  virtual void evaluate(const Vec3& lambda, EvalOrder order, StretchEnergy& out) const = 0;

  // ∂²Ψ/∂λ∂θ: out is 3 × num_params(); column k is ∂(∂Ψ/∂λ)/∂θk [Pa per unit
  // of θk]. Allocation-free (out is sized by the caller).
  virtual void d2psi_dlambda_dparam(const Vec3& lambda, Eigen::Ref<Eigen::MatrixXd> out) const = 0;

  virtual std::unique_ptr<Material> clone() const = 0;

  // Conveniences over evaluate().
  double psi(const Vec3& lambda) const;
  Vec3 dpsi_dlambda(const Vec3& lambda) const;
  Mat3 d2psi_dlambda2(const Vec3& lambda) const;

 protected:
  Material() = default;
  Material(const Material&) = default;
  Material& operator=(const Material&) = default;
};

// Lamé parameters implied by the Hessian at rest (H_ii = λ + 2μ, H_ij = λ).
// Works for every model, including fitted splines.
ElasticConstants small_strain_constants(const Material& m);

// (E, ν) -> (μ, λ). E > 0, -1 < ν < 0.5.
ElasticConstants lame_from_young(double young, double poisson);

// Validation helpers shared by the models: throw palpa::Error (Input) naming
// the parameter.
void require_finite(double value, std::string_view name);
void require_positive(double value, std::string_view name);
void require_poisson(double nu, std::string_view name = "nu");

}  // namespace palpa::material
