// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/contact/penalty.hpp"

#include <Eigen/Dense>
#include <cassert>

namespace palpa::contact {

namespace {

// Small matrices with at most two columns (the edge/face spanning vectors).
using Span = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 2>;
using Gram = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 2, 2>;

// The projection of p on the feature's affine hull, with what its derivatives
// need. Write a = q_0 + A t with A = [q_1 − q_0, q_2 − q_0] (m − 1 columns); t
// solves the normal equations G t = Aᵀ(p − q_0), G = AᵀA, and d = p − a
// satisfies Aᵀd = 0.
struct Projection {
  Span A;
  Gram G_inv;
  Eigen::Vector3d a;
  Eigen::Vector3d d;
  Eigen::Vector3d beta;    // weights of q_0, q_1, q_2
  Eigen::Matrix3d P_perp;  // I − A G⁻¹ Aᵀ: projector onto the feature's normal space
};

Projection project(const Eigen::Vector3d& p, const FeatureGeometry& g) {
  assert(g.m >= 1 && g.m <= 3);
  Projection r;
  const int c = g.m - 1;
  r.A.resize(3, c);
  for (int j = 0; j < c; ++j) r.A.col(j) = g.q[static_cast<std::size_t>(j + 1)] - g.q[0];
  r.beta.setZero();
  if (g.stuck) {
    r.A.resize(3, 0);
    r.G_inv.resize(0, 0);
    r.beta = g.stuck_weights;
    r.a = r.beta[0] * g.q[0] + r.beta[1] * g.q[1] + r.beta[2] * g.q[2];
    r.P_perp.setIdentity();
  } else if (c == 0) {
    r.G_inv.resize(0, 0);
    r.a = g.q[0];
    r.beta[0] = 1.0;
    r.P_perp.setIdentity();
  } else {
    r.G_inv = (r.A.transpose() * r.A).inverse();
    const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 2, 1> t =
        r.G_inv * (r.A.transpose() * (p - g.q[0]));
    r.a = g.q[0] + r.A * t;
    r.beta[0] = 1.0 - t.sum();
    r.beta.segment(1, c) = t;
    r.P_perp = Eigen::Matrix3d::Identity() - r.A * r.G_inv * r.A.transpose();
  }
  r.d = p - r.a;
  return r;
}

}  // namespace

Anchor sliding_anchor(const Eigen::Vector3d& p, const FeatureGeometry& g) {
  const Projection r = project(p, g);
  return {r.a, r.beta};
}

double penalty_energy(const Eigen::Vector3d& p, const FeatureGeometry& g, double k) {
  return k * project(p, g).d.squaredNorm();
}

Eigen::Vector3d penalty_gradient(const Eigen::Vector3d& p, const FeatureGeometry& g, double k) {
  return 2.0 * k * project(p, g).d;
}

Eigen::Matrix3d penalty_hessian(const FeatureGeometry& g, double k) {
  return 2.0 * k * project(g.q[0], g).P_perp;
}

Vector12d penalty_gradient_full(const Eigen::Vector3d& p, const FeatureGeometry& g, double k) {
  const Projection r = project(p, g);
  Vector12d grad;
  grad.head<3>() = 2.0 * k * r.d;
  for (int i = 0; i < 3; ++i) grad.segment<3>(3 * (i + 1)) = -2.0 * k * r.beta[i] * r.d;
  return grad;
}

// Differentiating Aᵀd = 0 and d = p − q_0 − A t along δz = (δp, δq_0, δq_1, δq_2):
//   δt = G⁻¹ (δAᵀ d + Aᵀ u),   δd = P⊥ u − A G⁻¹ δAᵀ d,   u = δp − Σ β_i δq_i,
// with δA = [δq_1 − δq_0, δq_2 − δq_0]. As 12-column matrices: u = U δz,
// δAᵀd = W δz, δt = J_t δz, δd = J_d δz, δβ_0 = −Σ δt_j, δβ_{j+1} = δt_j.
// Then from the gradient (2k d, −2k β_i d):
//   H = 2k [ J_d ; −(β_i J_d + d J_β_i) for i = 0, 1, 2 ].
Matrix12d penalty_hessian_full(const Eigen::Vector3d& p, const FeatureGeometry& g, double k) {
  const Projection r = project(p, g);
  const int c = g.stuck ? 0 : g.m - 1;  // a stuck anchor's weights do not move
  Eigen::Matrix<double, 3, 12> U;
  U.leftCols<3>().setIdentity();
  for (int i = 0; i < 3; ++i)
    U.middleCols<3>(3 * (i + 1)) = -r.beta[i] * Eigen::Matrix3d::Identity();
  Eigen::Matrix<double, Eigen::Dynamic, 12, 0, 2, 12> W =
      Eigen::Matrix<double, Eigen::Dynamic, 12, 0, 2, 12>::Zero(c, 12);
  for (int j = 0; j < c; ++j) {
    W.block<1, 3>(j, 3) = -r.d.transpose();
    W.block<1, 3>(j, 3 * (j + 2)) = r.d.transpose();
  }
  const Eigen::Matrix<double, Eigen::Dynamic, 12, 0, 2, 12> J_t =
      r.G_inv * (W + r.A.transpose() * U);
  const Eigen::Matrix<double, 3, 12> J_d = r.P_perp * U - r.A * (r.G_inv * W);
  Eigen::Matrix<double, 3, 12> J_beta = Eigen::Matrix<double, 3, 12>::Zero();
  for (int j = 0; j < c; ++j) {
    J_beta.row(0) -= J_t.row(j);
    J_beta.row(j + 1) = J_t.row(j);
  }
  Matrix12d H;
  H.topRows<3>() = 2.0 * k * J_d;
  for (int i = 0; i < 3; ++i) {
    H.middleRows<3>(3 * (i + 1)) = -2.0 * k * (r.beta[i] * J_d + r.d * J_beta.row(i));
  }
  return H;
}

}  // namespace palpa::contact
