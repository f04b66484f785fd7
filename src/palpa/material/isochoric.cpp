// SPDX-License-Identifier: AGPL-3.0-or-later
#include <fmt/format.h>

#include <cmath>

#include "palpa/core/error.hpp"
#include "palpa/material/models.hpp"

namespace palpa::material {

namespace {

// J^(-2/3) and J^(-4/3), continued quadratically below the threshold.
Scalar3 power_of_j(double jac, double exponent) {
  const double x = std::max(jac, kContinuationThreshold);
  const double p = std::pow(x, exponent);
  const Scalar3 at{p, exponent * p / x, exponent * (exponent - 1.0) * p / (x * x)};
  if (jac >= kContinuationThreshold) return at;
  return quadratic_continuation(at, kContinuationThreshold, jac);
}

// A reduced invariant q = φ(J) I with its λ-gradient and Hessian.
struct Reduced {
  double v = 0.0;
  Vec3 grad = Vec3::Zero();
  Mat3 hess = Mat3::Zero();
};

Reduced reduce(const Scalar3& phi, double inv, const Vec3& dinv, const Mat3& d2inv,
               const Vec3& dj, const Mat3& d2j, bool with_hessian) {
  Reduced r;
  r.v = phi.v * inv;
  r.grad = phi.d1 * inv * dj + phi.v * dinv;
  if (with_hessian) {
    r.hess = phi.d2 * inv * dj * dj.transpose() + phi.d1 * inv * d2j +
             phi.d1 * (dj * dinv.transpose() + dinv * dj.transpose()) + phi.v * d2inv;
  }
  return r;
}

struct Kinematics {
  double i1, i2, j;
  Vec3 di1, di2, dj;
  Mat3 d2i1, d2i2, d2j;
};

Kinematics kinematics(const Vec3& l) {
  Kinematics k;
  const Vec3 s = l.cwiseAbs2();
  k.i1 = s.sum();
  k.i2 = s[0] * s[1] + s[1] * s[2] + s[2] * s[0];
  k.j = l[0] * l[1] * l[2];
  k.di1 = 2.0 * l;
  k.d2i1 = 2.0 * Mat3::Identity();
  k.dj = Vec3(l[1] * l[2], l[0] * l[2], l[0] * l[1]);
  k.d2j << 0.0, l[2], l[1], l[2], 0.0, l[0], l[1], l[0], 0.0;
  for (int i = 0; i < 3; ++i) {
    const int a = (i + 1) % 3;
    const int b = (i + 2) % 3;
    k.di2[i] = 2.0 * l[i] * (s[a] + s[b]);
    k.d2i2(i, i) = 2.0 * (s[a] + s[b]);
    k.d2i2(i, a) = 4.0 * l[i] * l[a];
    k.d2i2(i, b) = 4.0 * l[i] * l[b];
  }
  return k;
}

}  // namespace

IsochoricInvariant::IsochoricInvariant(Kind kind, double c10, double c01, double c20, double c30,
                                       double d1)
    : kind_(kind), c10_(c10), c01_(c01), c20_(c20), c30_(c30), d1_(d1) {
  validate();
}

IsochoricInvariant IsochoricInvariant::neo_hookean(double c10, double d1) {
  return IsochoricInvariant(Kind::NeoHookean, c10, 0.0, 0.0, 0.0, d1);
}

IsochoricInvariant IsochoricInvariant::mooney_rivlin(double c10, double c01, double d1) {
  return IsochoricInvariant(Kind::MooneyRivlin, c10, c01, 0.0, 0.0, d1);
}

IsochoricInvariant IsochoricInvariant::yeoh(double c10, double c20, double c30, double d1) {
  return IsochoricInvariant(Kind::Yeoh, c10, 0.0, c20, c30, d1);
}

void IsochoricInvariant::validate() const {
  for (Eigen::Index k = 0; k < num_params(); ++k) require_finite(params()[k], param_info(k).name);
  require_positive(d1_, "D1");
  if (kind_ == Kind::MooneyRivlin) {
    if (!(c10_ + c01_ > 0.0)) {
      throw_input_error(fmt::format("Mooney-Rivlin shear modulus 2 (C10 + C01) = {} is not positive",
                                    2.0 * (c10_ + c01_)),
                        ErrorContext{}, "C10 + C01 > 0");
    }
  } else {
    require_positive(c10_, "C10");
  }
}

std::string_view IsochoricInvariant::model() const noexcept {
  switch (kind_) {
    case Kind::NeoHookean: return "neo-hookean-isochoric";
    case Kind::MooneyRivlin: return "mooney-rivlin";
    case Kind::Yeoh: return "yeoh";
  }
  return "";
}

std::string IsochoricInvariant::description() const {
  const char* vol =
      "; volumetric term: (J - 1)^2 / D1 (Abaqus/CalculiX/FEBio convention, K = 2/D1), "
      "with the isochoric invariants Ibar1 = J^(-2/3) I1, Ibar2 = J^(-4/3) I2";
  switch (kind_) {
    case Kind::NeoHookean:
      return std::string("isochoric neo-Hookean: C10 (Ibar1 - 3) + (J - 1)^2 / D1") + vol;
    case Kind::MooneyRivlin:
      return std::string("Mooney-Rivlin: C10 (Ibar1 - 3) + C01 (Ibar2 - 3) + (J - 1)^2 / D1") + vol;
    case Kind::Yeoh:
      return std::string("Yeoh: C10 (Ibar1 - 3) + C20 (Ibar1 - 3)^2 + C30 (Ibar1 - 3)^3 + "
                         "(J - 1)^2 / D1") +
             vol;
  }
  return "";
}

Eigen::Index IsochoricInvariant::num_params() const noexcept {
  switch (kind_) {
    case Kind::NeoHookean: return 2;
    case Kind::MooneyRivlin: return 3;
    case Kind::Yeoh: return 4;
  }
  return 0;
}

ParamInfo IsochoricInvariant::param_info(Eigen::Index k) const {
  const ParamInfo d1{"D1", Dimension::Compliance,
                     "volumetric compliance [1/Pa]: K = 2/D1 at rest"};
  if (k == num_params() - 1) return d1;
  if (k == 0) return {"C10", Dimension::Pressure, "coefficient of (Ibar1 - 3)"};
  if (kind_ == Kind::MooneyRivlin) return {"C01", Dimension::Pressure, "coefficient of (Ibar2 - 3)"};
  if (k == 1) return {"C20", Dimension::Pressure, "coefficient of (Ibar1 - 3)^2"};
  return {"C30", Dimension::Pressure, "coefficient of (Ibar1 - 3)^3"};
}

Eigen::VectorXd IsochoricInvariant::params() const {
  switch (kind_) {
    case Kind::NeoHookean: return Eigen::Vector2d(c10_, d1_);
    case Kind::MooneyRivlin: return Eigen::Vector3d(c10_, c01_, d1_);
    case Kind::Yeoh: return Eigen::Vector4d(c10_, c20_, c30_, d1_);
  }
  return {};
}

void IsochoricInvariant::set_params(const Eigen::VectorXd& t) {
  IsochoricInvariant next = *this;
  switch (kind_) {
    case Kind::NeoHookean:
      next.c10_ = t[0];
      next.d1_ = t[1];
      break;
    case Kind::MooneyRivlin:
      next.c10_ = t[0];
      next.c01_ = t[1];
      next.d1_ = t[2];
      break;
    case Kind::Yeoh:
      next.c10_ = t[0];
      next.c20_ = t[1];
      next.c30_ = t[2];
      next.d1_ = t[3];
      break;
  }
  next.validate();
  *this = next;
}

std::unique_ptr<Material> IsochoricInvariant::clone() const {
  return std::make_unique<IsochoricInvariant>(*this);
}

void IsochoricInvariant::evaluate(const Vec3& l, EvalOrder order, StretchEnergy& out) const {
  const Kinematics k = kinematics(l);
  const bool hess = order == EvalOrder::Hessian;
  const Reduced b1 = reduce(power_of_j(k.j, -2.0 / 3.0), k.i1, k.di1, k.d2i1, k.dj, k.d2j, hess);
  const double t = b1.v - 3.0;
  const double w = c10_ * t + c20_ * t * t + c30_ * t * t * t;
  const double w1 = c10_ + 2.0 * c20_ * t + 3.0 * c30_ * t * t;
  const double w11 = 2.0 * c20_ + 6.0 * c30_ * t;
  const double u = (k.j - 1.0) * (k.j - 1.0) / d1_;
  const double u1 = 2.0 * (k.j - 1.0) / d1_;
  const double u2 = 2.0 / d1_;
  out.psi = w + u;
  Reduced b2;
  if (c01_ != 0.0) {
    b2 = reduce(power_of_j(k.j, -4.0 / 3.0), k.i2, k.di2, k.d2i2, k.dj, k.d2j, hess);
    out.psi += c01_ * (b2.v - 3.0);
  }
  if (order == EvalOrder::Energy) return;
  out.grad = w1 * b1.grad + u1 * k.dj;
  if (c01_ != 0.0) out.grad += c01_ * b2.grad;
  if (!hess) return;
  out.hess = w11 * b1.grad * b1.grad.transpose() + w1 * b1.hess + u2 * k.dj * k.dj.transpose() +
             u1 * k.d2j;
  if (c01_ != 0.0) out.hess += c01_ * b2.hess;
}

void IsochoricInvariant::d2psi_dlambda_dparam(const Vec3& l, Eigen::Ref<Eigen::MatrixXd> out) const {
  const Kinematics k = kinematics(l);
  const Reduced b1 = reduce(power_of_j(k.j, -2.0 / 3.0), k.i1, k.di1, k.d2i1, k.dj, k.d2j, false);
  const double t = b1.v - 3.0;
  out.col(0) = b1.grad;
  out.col(num_params() - 1) = -2.0 * (k.j - 1.0) / (d1_ * d1_) * k.dj;
  if (kind_ == Kind::MooneyRivlin) {
    const Reduced b2 = reduce(power_of_j(k.j, -4.0 / 3.0), k.i2, k.di2, k.d2i2, k.dj, k.d2j, false);
    out.col(1) = b2.grad;
  } else if (kind_ == Kind::Yeoh) {
    out.col(1) = 2.0 * t * b1.grad;
    out.col(2) = 3.0 * t * t * b1.grad;
  }
}

}  // namespace palpa::material
