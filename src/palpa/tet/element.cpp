// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/tet/element.hpp"

#include <cmath>

#include "palpa/material/kinematics.hpp"

namespace palpa::tet {

using material::Mat3;
using material::Mat9;
using material::Vec9;

double signed_volume(const Mat34& X) noexcept {
  Mat3 D;
  D.col(0) = X.col(1) - X.col(0);
  D.col(1) = X.col(2) - X.col(0);
  D.col(2) = X.col(3) - X.col(0);
  return D.determinant() / 6.0;
}

TetGeometry tet_geometry(const Mat34& X) {
  Mat3 D;
  D.col(0) = X.col(1) - X.col(0);
  D.col(1) = X.col(2) - X.col(0);
  D.col(2) = X.col(3) - X.col(0);
  TetGeometry g;
  g.volume = D.determinant() / 6.0;
  // F = Ds D⁻¹: row a−1 of D⁻¹ is ∇N_a for a = 1..3; ∇N_0 = −Σ.
  const Mat3 Dinv = D.inverse();
  g.grad_n.row(1) = Dinv.row(0);
  g.grad_n.row(2) = Dinv.row(1);
  g.grad_n.row(3) = Dinv.row(2);
  g.grad_n.row(0) = -(Dinv.row(0) + Dinv.row(1) + Dinv.row(2));
  return g;
}

Mat3 deformation_gradient(const TetGeometry& g, const Mat34& x) noexcept { return x * g.grad_n; }

namespace {

// B = ∂vec(F)/∂x: vec(F)[i + 3j] = Σ_a x_a[i] ∇N_a[j].
Eigen::Matrix<double, 9, 12> b_matrix(const TetGeometry& g) {
  Eigen::Matrix<double, 9, 12> B = Eigen::Matrix<double, 9, 12>::Zero();
  for (int a = 0; a < 4; ++a) {
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) B(i + 3 * j, 3 * a + i) = g.grad_n(a, j);
    }
  }
  return B;
}

}  // namespace

bool tet_evaluate(const material::Material& m, const TetGeometry& g, const Mat34& x,
                  material::EvalOrder order, material::PsdProjection projection, TetResult& out) {
  const Mat3 F = deformation_gradient(g, x);
  const double J = F.determinant();
  if (!(J > 0.0) || !std::isfinite(J)) return false;
  material::Stress3 s;
  material::stress(m, F, order, projection, s);
  out.energy = g.volume * s.psi;
  if (order == material::EvalOrder::Energy) return std::isfinite(out.energy);
  // ∂E/∂x_a = V P ∇N_a.
  const Mat34 grad = g.volume * s.P * g.grad_n.transpose();
  out.gradient = Eigen::Map<const Vec12>(grad.data());
  if (order == material::EvalOrder::Hessian) {
    const Eigen::Matrix<double, 9, 12> B = b_matrix(g);
    out.hessian.noalias() = g.volume * (B.transpose() * (s.dPdF * B));
  }
  return std::isfinite(out.energy);
}

void tet_dgradient_dparam(const material::Material& m, const TetGeometry& g, const Mat34& x,
                          Eigen::Ref<Eigen::MatrixXd> work3, Eigen::Ref<Eigen::MatrixXd> work9,
                          Eigen::Ref<Eigen::MatrixXd> out) {
  const Mat3 F = deformation_gradient(g, x);
  material::dP_dparam(m, F, work3, work9);
  out.noalias() = g.volume * (b_matrix(g).transpose() * work9);
}

void tet_rest_gradient_product(const material::Material& m, const TetGeometry& g, const Mat34& x,
                               const Mat34& z, Mat34& out) {
  const Mat3 F = deformation_gradient(g, x);
  const Mat3 G = z * g.grad_n;  // Z_s D_m⁻¹: the rows of grad_n sum to zero
  material::Stress3 s;
  material::stress(m, F, material::EvalOrder::Hessian, material::PsdProjection::None, s);
  const Vec9 cg = s.dPdF * Eigen::Map<const Vec9>(G.data());  // vec(C:G)
  const Mat3 A = s.P.cwiseProduct(G).sum() * Mat3::Identity() -
                 F.transpose() * Eigen::Map<const Mat3>(cg.data()) - G.transpose() * s.P;
  out.noalias() = g.volume * (A * g.grad_n.transpose());
}

Mat3 cauchy_stress(const material::Material& m, const TetGeometry& g, const Mat34& x) {
  const Mat3 F = deformation_gradient(g, x);
  material::Stress3 s;
  material::stress(m, F, material::EvalOrder::Gradient, material::PsdProjection::None, s);
  return s.P * F.transpose() / F.determinant();
}

}  // namespace palpa::tet
