// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/material/kinematics.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <cmath>

namespace palpa::material {

namespace {

constexpr double kInvSqrt2 = 0.70710678118654752440;
// |σi − σj| below this (relative) uses the limit of the flip stiffness: its error
// is O(Δσ²) while the quotient's rounding error is O(ε/Δσ), balanced near 1e-5.
constexpr double kRepeatedTolerance = 1e-5;
// |σi + σj| is kept at least this large in the twist stiffness.
constexpr double kTwistFloor = 1e-6;

double project(double v, PsdProjection p) noexcept {
  switch (p) {
    case PsdProjection::None: return v;
    case PsdProjection::Clamp: return v > 0.0 ? v : 0.0;
    case PsdProjection::Abs: return std::abs(v);
  }
  return v;
}

Mat3 project_matrix(const Mat3& h, PsdProjection p) {
  if (p == PsdProjection::None) return h;
  // Positive definite (the common case): nothing to do, and a 3×3 Cholesky is
  // far cheaper than an eigen-decomposition.
  if (Eigen::LLT<Mat3>(h).info() == Eigen::Success) return h;
  Eigen::SelfAdjointEigenSolver<Mat3> eig;
  eig.computeDirect(h);
  Vec3 ev = eig.eigenvalues();
  if (ev.minCoeff() >= 0.0) return h;
  for (int k = 0; k < 3; ++k) ev[k] = project(ev[k], p);
  return eig.eigenvectors() * ev.asDiagonal() * eig.eigenvectors().transpose();
}

Vec9 vec_outer(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  Vec9 v;
  for (int col = 0; col < 3; ++col) v.segment<3>(3 * col) = a * b[col];
  return v;
}

}  // namespace

Svd3 signed_svd(const Mat3& F) {
  const Eigen::JacobiSVD<Mat3, Eigen::NoQRPreconditioner> svd(F, Eigen::ComputeFullU |
                                                                   Eigen::ComputeFullV);
  Svd3 out{svd.matrixU(), svd.singularValues(), svd.matrixV()};
  if (out.U.determinant() < 0.0) {
    out.U.col(2) *= -1.0;
    out.sigma[2] *= -1.0;
  }
  if (out.V.determinant() < 0.0) {
    out.V.col(2) *= -1.0;
    out.sigma[2] *= -1.0;
  }
  return out;
}

namespace {

// The unit complex number (c, s) = e^{iθ}, and a square root of it: e^{iθ/2}
// or −e^{iθ/2} (either serves: see signed_svd). Without trigonometry:
// √w = (1 + w)/|1 + w| where Re w >= 0, else i (1 − w)/|1 − w|.
Vec2 unit_sqrt(double c, double s) {
  if (c >= 0.0) {
    const double n = std::sqrt((1.0 + c) * (1.0 + c) + s * s);
    return Vec2((1.0 + c) / n, s / n);
  }
  const double n = std::sqrt((1.0 - c) * (1.0 - c) + s * s);
  return Vec2(s / n, (1.0 - c) / n);
}

}  // namespace

Svd2 signed_svd(const Mat2& F) {
  // F = q R(φ1) + r R(φ2) K with K = diag(1, −1): the conformal and
  // anti-conformal parts. Then F = R(α) diag(q + r, q − r) R(β)ᵀ for any α, β
  // with α + β = φ2 and α − β = φ1 (mod 2π). With z1 = e^{iφ1}, z2 = e^{iφ2}:
  // e^{iα} = √(z1 z2) (either root) and e^{iβ} = e^{iα} / z1, all algebraic.
  const double e = 0.5 * (F(0, 0) + F(1, 1));
  const double f = 0.5 * (F(0, 0) - F(1, 1));
  const double g = 0.5 * (F(1, 0) + F(0, 1));
  const double h = 0.5 * (F(1, 0) - F(0, 1));
  const double q = std::hypot(e, h);
  const double r = std::hypot(f, g);
  // z1, z2 (1 where the part vanishes: any angle serves there).
  const double c1 = q > 0.0 ? e / q : 1.0;
  const double s1 = q > 0.0 ? h / q : 0.0;
  const double c2 = r > 0.0 ? f / r : 1.0;
  const double s2 = r > 0.0 ? g / r : 0.0;
  const Vec2 za = unit_sqrt(c1 * c2 - s1 * s2, s1 * c2 + c1 * s2);
  const double ca = za[0];
  const double sa = za[1];
  const double cb = ca * c1 + sa * s1;  // e^{iα} · conj(z1)
  const double sb = sa * c1 - ca * s1;
  Svd2 out;
  out.sigma = Vec2(q + r, q - r);
  out.U << ca, -sa, sa, ca;
  out.V << cb, -sb, sb, cb;
  return out;
}

double flip_stiffness(const Vec3& s, const StretchEnergy& e, int i, int j) noexcept {
  const double diff = s[i] - s[j];
  const double scale = std::max(1.0, 0.5 * (std::abs(s[i]) + std::abs(s[j])));
  if (std::abs(diff) <= kRepeatedTolerance * scale) {
    return 0.5 * (e.hess(i, i) + e.hess(j, j)) - e.hess(i, j);
  }
  return (e.grad[i] - e.grad[j]) / diff;
}

double twist_stiffness(const Vec3& s, const StretchEnergy& e, int i, int j) noexcept {
  double sum = s[i] + s[j];
  if (std::abs(sum) < kTwistFloor) sum = sum < 0.0 ? -kTwistFloor : kTwistFloor;
  return (e.grad[i] + e.grad[j]) / sum;
}

void stress(const Material& m, const Mat3& F, EvalOrder order, PsdProjection projection,
            Stress3& out) {
  const Svd3 svd = signed_svd(F);
  StretchEnergy e;
  m.evaluate(svd.sigma, order, e);
  out.psi = e.psi;
  if (order == EvalOrder::Energy) return;
  out.P = svd.U * e.grad.asDiagonal() * svd.V.transpose();
  if (order == EvalOrder::Gradient) return;

  // Stretch block.
  Eigen::Matrix<double, 9, 3> d;
  for (int k = 0; k < 3; ++k) d.col(k) = vec_outer(svd.U.col(k), svd.V.col(k));
  const Mat3 h = project_matrix(e.hess, projection);
  out.dPdF.noalias() = d * h * d.transpose();
  // Flip and twist modes of each pair.
  constexpr int kPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (const auto& pr : kPairs) {
    const int i = pr[0];
    const int j = pr[1];
    const Vec9 uv = vec_outer(svd.U.col(i), svd.V.col(j));
    const Vec9 vu = vec_outer(svd.U.col(j), svd.V.col(i));
    const Vec9 flip = kInvSqrt2 * (uv + vu);
    const Vec9 twist = kInvSqrt2 * (uv - vu);
    const double a = project(flip_stiffness(svd.sigma, e, i, j), projection);
    const double b = project(twist_stiffness(svd.sigma, e, i, j), projection);
    out.dPdF.noalias() += a * flip * flip.transpose();
    out.dPdF.noalias() += b * twist * twist.transpose();
  }
}

void dP_dparam(const Material& m, const Mat3& F, Eigen::Ref<Eigen::MatrixXd> work,
               Eigen::Ref<Eigen::MatrixXd> out) {
  const Svd3 svd = signed_svd(F);
  m.d2psi_dlambda_dparam(svd.sigma, work);
  Eigen::Matrix<double, 9, 3> d;
  for (int k = 0; k < 3; ++k) d.col(k) = vec_outer(svd.U.col(k), svd.V.col(k));
  out.noalias() = d * work;
}

void stress_axisymmetric(const Material& m, const Mat2& F2, double hoop, EvalOrder order,
                         PsdProjection projection, StressAxisym& out) {
  const Svd2 svd = signed_svd(F2);
  const Vec3 sigma(svd.sigma[0], svd.sigma[1], hoop);
  StretchEnergy e;
  m.evaluate(sigma, order, e);
  out.psi = e.psi;
  if (order == EvalOrder::Energy) return;

  // Mode vectors over x = (F_rr, F_zr, F_rz, F_zz, F_θθ).
  const auto mode2 = [](const Vec2& a, const Vec2& b) {
    Vec5 v;
    v << a[0] * b[0], a[1] * b[0], a[0] * b[1], a[1] * b[1], 0.0;
    return v;
  };
  Eigen::Matrix<double, 5, 3> d;
  d.col(0) = mode2(svd.U.col(0), svd.V.col(0));
  d.col(1) = mode2(svd.U.col(1), svd.V.col(1));
  d.col(2) << 0.0, 0.0, 0.0, 0.0, 1.0;
  out.P.noalias() = d * e.grad;
  if (order == EvalOrder::Gradient) return;

  const Mat3 h = project_matrix(e.hess, projection);
  out.dPdF.noalias() = d * h * d.transpose();
  // Only the in-plane pair (0, 1) has flip/twist modes: the others would need
  // the F_rθ, F_θz entries, which axisymmetry keeps at zero.
  const Vec5 uv = mode2(svd.U.col(0), svd.V.col(1));
  const Vec5 vu = mode2(svd.U.col(1), svd.V.col(0));
  const Vec5 flip = kInvSqrt2 * (uv + vu);
  const Vec5 twist = kInvSqrt2 * (uv - vu);
  const double a = project(flip_stiffness(sigma, e, 0, 1), projection);
  const double b = project(twist_stiffness(sigma, e, 0, 1), projection);
  out.dPdF.noalias() += a * flip * flip.transpose();
  out.dPdF.noalias() += b * twist * twist.transpose();
}

void dP_dparam_axisymmetric(const Material& m, const Mat2& F2, double hoop,
                            Eigen::Ref<Eigen::MatrixXd> work, Eigen::Ref<Eigen::MatrixXd> out) {
  const Svd2 svd = signed_svd(F2);
  m.d2psi_dlambda_dparam(Vec3(svd.sigma[0], svd.sigma[1], hoop), work);
  for (int k = 0; k < 2; ++k) {
    const Vec2 u = svd.U.col(k);
    const Vec2 v = svd.V.col(k);
    const Eigen::Vector4d mode(u[0] * v[0], u[1] * v[0], u[0] * v[1], u[1] * v[1]);
    if (k == 0) {
      out.topRows<4>().noalias() = mode * work.row(0);
    } else {
      out.topRows<4>().noalias() += mode * work.row(1);
    }
  }
  out.row(4) = work.row(2);
}

}  // namespace palpa::material
