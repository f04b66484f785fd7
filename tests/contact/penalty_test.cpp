// SPDX-License-Identifier: AGPL-3.0-or-later
// The sliding-anchor penalty of Appendix A: finite-difference checks of
// energy → gradient and gradient → Hessian, over the query point alone and over
// (p, q_0, q_1, q_2), in each Voronoi case (vertex, edge, face), and the
// thesis's closed forms.

#include "palpa/contact/penalty.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "common/finite_difference.hpp"

namespace palpa::contact {
namespace {

using test::derivatives_match;
using test::fd_gradient;
using test::fd_jacobian;

constexpr double kStiffness = 2.5e4;  // N/m
// Positions are ~1 cm; central differences with one Richardson step at this
// step are accurate to ~1e-9 relative for these rational functions.
constexpr double kStep = 1e-5;
constexpr double kTol = 1e-7;

const Eigen::Vector3d kQ0(0.001, -0.002, 0.0005);
const Eigen::Vector3d kQ1(0.021, 0.001, -0.001);
const Eigen::Vector3d kQ2(0.006, 0.017, 0.003);

FeatureGeometry feature(int m) {
  FeatureGeometry g;
  g.m = m;
  g.q = {kQ0, kQ1, kQ2};
  for (int i = m; i < 3; ++i) g.q[static_cast<std::size_t>(i)].setZero();
  return g;
}

// A query point in the Voronoi region of the feature, `depth` from it on the
// inner side (−normal) of the triangle (q0, q1, q2).
Eigen::Vector3d query_point(int m, double depth) {
  const Eigen::Vector3d n = (kQ1 - kQ0).cross(kQ2 - kQ0).normalized();
  const Eigen::Vector3d centre = (kQ0 + kQ1 + kQ2) / 3.0;
  switch (m) {
    case 1:  // beyond corner q0, away from the triangle
      return kQ0 + depth * (kQ0 - centre).normalized() - depth * n;
    case 2: {  // beyond the middle of edge q0–q1
      const Eigen::Vector3d mid = 0.5 * (kQ0 + kQ1);
      const Eigen::Vector3d e = (kQ1 - kQ0).normalized();
      Eigen::Vector3d out = mid - centre;
      out -= out.dot(e) * e;
      return mid + depth * out.normalized() - depth * n;
    }
    default:
      return centre - depth * n;
  }
}

Eigen::VectorXd pack(const Eigen::Vector3d& p, const FeatureGeometry& g) {
  Eigen::VectorXd z(12);
  z << p, g.q[0], g.q[1], g.q[2];
  return z;
}
FeatureGeometry unpack_feature(const Eigen::VectorXd& z, int m) {
  FeatureGeometry g;
  g.m = m;
  for (int i = 0; i < 3; ++i) g.q[static_cast<std::size_t>(i)] = z.segment<3>(3 * (i + 1));
  return g;
}

class PenaltyRegion : public ::testing::TestWithParam<int> {};

TEST_P(PenaltyRegion, QueryGradientAndHessianMatchFiniteDifferences) {
  const int m = GetParam();
  const FeatureGeometry g = feature(m);
  const Eigen::Vector3d p = query_point(m, 0.003);
  const Eigen::VectorXd x = p;
  const auto energy = [&](const Eigen::VectorXd& y) { return penalty_energy(y, g, kStiffness); };
  const auto gradient = [&](const Eigen::VectorXd& y) {
    return Eigen::VectorXd(penalty_gradient(y, g, kStiffness));
  };
  EXPECT_TRUE(derivatives_match(gradient(x), fd_gradient(energy, x, kStep), kTol));
  EXPECT_TRUE(
      derivatives_match(penalty_hessian(g, kStiffness), fd_jacobian(gradient, x, kStep), kTol));
}

TEST_P(PenaltyRegion, FullGradientAndHessianMatchFiniteDifferences) {
  const int m = GetParam();
  const FeatureGeometry g = feature(m);
  const Eigen::VectorXd z = pack(query_point(m, 0.003), g);
  const auto energy = [&](const Eigen::VectorXd& y) {
    return penalty_energy(y.head<3>(), unpack_feature(y, m), kStiffness);
  };
  const auto gradient = [&](const Eigen::VectorXd& y) {
    return Eigen::VectorXd(penalty_gradient_full(y.head<3>(), unpack_feature(y, m), kStiffness));
  };
  const Eigen::VectorXd grad = gradient(z);
  EXPECT_TRUE(derivatives_match(grad, fd_gradient(energy, z, kStep), kTol));
  const Matrix12d H = penalty_hessian_full(z.head<3>(), g, kStiffness);
  EXPECT_TRUE(derivatives_match(H, fd_jacobian(gradient, z, kStep), kTol));
  EXPECT_LT((H - H.transpose()).cwiseAbs().maxCoeff(), 1e-12 * H.cwiseAbs().maxCoeff());
  // Blocks of the vertices that do not span the feature are zero.
  for (int i = m; i < 3; ++i) {
    EXPECT_EQ(grad.segment<3>(3 * (i + 1)).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(H.middleRows<3>(3 * (i + 1)).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(H.middleCols<3>(3 * (i + 1)).cwiseAbs().maxCoeff(), 0.0);
  }
  // The p-block is the query Hessian; a rigid translation of everything
  // changes nothing (rows sum to zero over the four points).
  EXPECT_LT((H.topLeftCorner<3, 3>() - penalty_hessian(g, kStiffness)).norm(), 1e-9 * kStiffness);
  Eigen::Matrix<double, 12, 3> translation;
  for (int i = 0; i < 4; ++i) translation.middleRows<3>(3 * i).setIdentity();
  for (int i = m + 1; i < 4; ++i) translation.middleRows<3>(3 * i).setZero();
  EXPECT_LT((H * translation).cwiseAbs().maxCoeff(), 1e-9 * kStiffness);
  EXPECT_LT(std::abs(grad.reshaped(3, 4).rowwise().sum().norm()), 1e-12 * grad.norm());
}

INSTANTIATE_TEST_SUITE_P(VertexEdgeFace, PenaltyRegion, ::testing::Values(1, 2, 3),
                         [](const ::testing::TestParamInfo<int>& param_info) {
                           return std::string(param_info.param == 1
                                                  ? "Vertex"
                                                  : (param_info.param == 2 ? "Edge" : "Face"));
                         });

TEST(Penalty, AStuckAnchorIsASpringToAPointCarriedByTheFace) {
  // Weights away from the point's projection: the spring pulls tangentially
  // as well as along the normal.
  const Eigen::Vector3d beta(0.5, 0.3, 0.2);
  const auto stuck = [&](const Eigen::VectorXd& y) {
    FeatureGeometry g = unpack_feature(y, 3);
    g.stuck = true;
    g.stuck_weights = beta;
    return g;
  };
  const Eigen::VectorXd z = pack(query_point(3, 0.003) + Eigen::Vector3d(0.002, -0.001, 0.0), feature(3));
  const auto energy = [&](const Eigen::VectorXd& y) { return penalty_energy(y.head<3>(), stuck(y), kStiffness); };
  const auto gradient = [&](const Eigen::VectorXd& y) {
    return Eigen::VectorXd(penalty_gradient_full(y.head<3>(), stuck(y), kStiffness));
  };
  const Eigen::VectorXd grad = gradient(z);
  EXPECT_TRUE(derivatives_match(grad, fd_gradient(energy, z, kStep), kTol));
  const Matrix12d H = penalty_hessian_full(z.head<3>(), stuck(z), kStiffness);
  EXPECT_TRUE(derivatives_match(H, fd_jacobian(gradient, z, kStep), kTol));
  // The anchor is Σ β_i q_i, the p-block 2kI.
  const FeatureGeometry g = stuck(z);
  const Eigen::Vector3d a = beta[0] * kQ0 + beta[1] * kQ1 + beta[2] * kQ2;
  EXPECT_LT((sliding_anchor(z.head<3>(), g).point - a).norm(), 1e-15);
  EXPECT_NEAR(energy(z), kStiffness * (z.head<3>() - a).squaredNorm(), 1e-12 * energy(z));
  EXPECT_LT((penalty_hessian(g, kStiffness) - 2.0 * kStiffness * Eigen::Matrix3d::Identity()).norm(), 1e-9 * kStiffness);
  EXPECT_LT((H.topLeftCorner<3, 3>() - penalty_hessian(g, kStiffness)).norm(), 1e-9 * kStiffness);
}

TEST(Penalty, ThesisClosedForms) {
  const double k = kStiffness;
  // (A.3) vertex: 2kI.
  EXPECT_LT((penalty_hessian(feature(1), k) - 2.0 * k * Eigen::Matrix3d::Identity()).norm(),
            1e-9 * k);
  // (A.4), (A.6) edge: the anchor formula and 2k(I − eeᵀ). (A.4) as printed
  // pairs (p − p_i) with p_i; the projection pairs each endpoint's weight with
  // the distance along the edge from the other endpoint:
  // a = [((p − p_j)·(p_i − p_j)) p_i + ((p − p_i)·(p_j − p_i)) p_j] / ‖p_i − p_j‖².
  const Eigen::Vector3d e = (kQ0 - kQ1).normalized();
  EXPECT_LT(
      (penalty_hessian(feature(2), k) - 2.0 * k * (Eigen::Matrix3d::Identity() - e * e.transpose()))
          .norm(),
      1e-9 * k);
  const Eigen::Vector3d pe = query_point(2, 0.004);
  const Eigen::Vector3d thesis_edge_anchor =
      ((pe - kQ1).dot(kQ0 - kQ1) * kQ0 + (pe - kQ0).dot(kQ1 - kQ0) * kQ1) /
      (kQ0 - kQ1).squaredNorm();
  EXPECT_LT((sliding_anchor(pe, feature(2)).point - thesis_edge_anchor).norm(), 1e-17);
  // (A.7), (A.9) face: p − ((p − p1)·n)n and 2k nnᵀ.
  const Eigen::Vector3d n = (kQ1 - kQ0).cross(kQ2 - kQ0).normalized();
  EXPECT_LT((penalty_hessian(feature(3), k) - 2.0 * k * n * n.transpose()).norm(), 1e-9 * k);
  const Eigen::Vector3d pf = query_point(3, 0.004);
  EXPECT_LT((sliding_anchor(pf, feature(3)).point - (pf - (pf - kQ0).dot(n) * n)).norm(), 1e-16);
  // Energies: k·depth² in each case.
  for (int m = 1; m <= 3; ++m) {
    EXPECT_NEAR(penalty_energy(query_point(m, 0.004), feature(m), k),
                k * 2 * 0.004 * 0.004 * (m == 3 ? 0.5 : 1.0), 1e-12 * k * 1.6e-5)
        << m;
  }
}

}  // namespace
}  // namespace palpa::contact
