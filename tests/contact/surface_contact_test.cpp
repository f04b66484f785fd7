// SPDX-License-Identifier: AGPL-3.0-or-later
// Surface contact: samples on a surface's triangles (the subdivision rule,
// area shares), a flat sheet pressed into a box (force = pressure per depth ×
// depth × area, nodal forces the consistent loads, equal and opposite on the
// obstacle), and the derivatives of the sampled potential over the surface's
// and the obstacle's vertices against finite differences.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "common/finite_difference.hpp"
#include "common/square_grid.hpp"
#include "common/test_support.hpp"
#include "contact/shapes.hpp"
#include "palpa/contact/penalty_contact.hpp"
#include "palpa/geometry/surface_operators.hpp"

namespace palpa::contact {
namespace {

using test::derivatives_match;
using test::fd_jacobian;

// A flat n×n grid of side `size` at height z, centred on the z axis.
SurfaceMesh sheet(int n, double size, double z) { return test::square_grid(n, size, Eigen::Vector3d(0.0, 0.0, z)); }

TEST(SubdivisionRule, EqualWeightsInsideTheTriangleExactForLinearFunctions) {
  for (int n = 1; n <= 4; ++n) {
    const TriangleRule r = subdivision_rule(n);
    ASSERT_EQ(r.weight.size(), static_cast<std::size_t>(n * n));
    double total = 0.0;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (std::size_t q = 0; q < r.weight.size(); ++q) {
      EXPECT_NEAR(r.barycentric[q].sum(), 1.0, 1e-15);
      EXPECT_GT(r.barycentric[q].minCoeff(), 0.0);
      total += r.weight[q];
      mean += r.weight[q] * r.barycentric[q];
    }
    EXPECT_NEAR(total, 1.0, 1e-15) << n;
    // ∫N_i / A = 1/3: a linear integrand is exact.
    EXPECT_LT((mean - Eigen::Vector3d::Constant(1.0 / 3.0)).norm(), 1e-15) << n;
  }
  // The points are distinct: two sub-triangles never share a centroid.
  const TriangleRule r = subdivision_rule(3);
  for (std::size_t a = 0; a < r.weight.size(); ++a) {
    for (std::size_t b = a + 1; b < r.weight.size(); ++b) EXPECT_GT((r.barycentric[a] - r.barycentric[b]).norm(), 0.1);
  }
  EXPECT_TRUE(test::throws_error([] { subdivision_rule(0); }, ErrorKind::Input, {"n ≥ 1"}));
}

TEST(SurfaceSamples, AreaSharesAreTheLumpedVertexAreas) {
  const SurfaceMesh m = test::sphere_mesh(0.02, 1);
  const ContactSamples s = surface_samples(m.V, m.F, subdivision_rule(2));
  ASSERT_EQ(s.size(), static_cast<std::size_t>(4 * m.F.rows()));
  Eigen::VectorXd share = Eigen::VectorXd::Zero(m.V.rows());
  for (std::size_t i = 0; i < s.size(); ++i) {
    EXPECT_EQ(s.count(i), 3);
    for (int a = 0; a < 3; ++a) share[s.vertices[i][static_cast<std::size_t>(a)]] += 2.0 * s.weights[i][a] * s.scale[i];
  }
  const Eigen::VectorXd lumped = geometry::vertex_areas(m);
  EXPECT_LT((share - lumped).cwiseAbs().maxCoeff(), 1e-12 * lumped.maxCoeff());
  SurfaceMesh flat = sheet(1, 0.01, 0.0);
  flat.V.row(3) = flat.V.row(0);  // a triangle without area
  EXPECT_TRUE(test::throws_error([&] { surface_samples(flat.V, flat.F, subdivision_rule(1)); }, ErrorKind::Input,
                                 {"no area"}));
}

TEST(SurfaceContact, AFlatSheetPressedIntoABoxCarriesPressureTimesArea) {
  // A 12 mm sheet 0.2 mm below the top face of a 2 cm box: every sample at
  // depth δ, so the pressure is k_p δ everywhere and the force k_p δ A.
  const double kp = 5e7, depth = 2e-4, size = 0.012;  // Pa/m, m, m
  const Obstacle box(test::cube_mesh(0.01), "box");
  const SurfaceMesh s = sheet(6, size, 0.01 - depth);
  const Eigen::Matrix3Xd x = s.V.transpose();
  PenaltyContact contact(surface_samples(s.V, s.F, subdivision_rule(2)), kp, "box");
  contact.commit(box, x);
  ASSERT_EQ(contact.size(), contact.samples().size());
  EXPECT_NEAR(contact.max_depth(), depth, 1e-15);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  Eigen::Matrix3Xd g = Eigen::Matrix3Xd::Zero(3, box.vertices().rows());
  contact.add_forces(box, x, f, g);
  const Eigen::Vector3d total = f.rowwise().sum();
  EXPECT_NEAR(total.z(), kp * depth * size * size, 1e-12 * kp * depth * size * size);
  EXPECT_LT(total.head<2>().norm(), 1e-12 * total.z());
  // Equal and opposite: the box's vertices carry −Σ f.
  EXPECT_LT((g.rowwise().sum() + total).norm(), 1e-12 * total.norm());
  const Wrench w = contact.obstacle_wrench(box, x, Eigen::Vector3d::Zero());
  EXPECT_LT((w.force + total).norm(), 1e-12 * total.norm());
  // Each vertex's force is the consistent load of the uniform pressure: its
  // lumped area times k_p δ (the sheet's corners and edges too).
  const Eigen::VectorXd area = geometry::vertex_areas(s);
  for (Eigen::Index v = 0; v < x.cols(); ++v) {
    EXPECT_NEAR(f(2, v), kp * depth * area[v], 1e-9 * kp * depth * area[v]) << v;
  }
  EXPECT_NEAR(contact.energy(box, x), 0.5 * kp * depth * depth * size * size, 1e-12 * kp * depth * depth * size * size);
  EXPECT_NEAR(contact.detected_energy(box, x), contact.energy(box, x), 1e-12 * contact.energy(box, x));
}

TEST(SurfaceContact, DerivativesOverTheSurfaceAndTheObstacleMatchFiniteDifferences) {
  // A bent sheet inside a sphere (anchors on faces, edges and vertices of
  // the sphere), moved away from where it was committed so that the anchors
  // slide: the gradient and the whole Hessian over both surfaces.
  const SurfaceMesh sphere = test::sphere_mesh(0.03, 1);
  const Obstacle obstacle(sphere, "sphere");
  SurfaceMesh s = sheet(2, 0.03, 0.0);
  for (Eigen::Index v = 0; v < s.V.rows(); ++v) s.V(v, 2) = 0.2 * s.V(v, 0) * s.V(v, 0) / 0.03 + 0.004;
  PenaltyContact contact(surface_samples(s.V, s.F, subdivision_rule(2)), 4e7, "sphere");
  Eigen::Matrix3Xd x = s.V.transpose();
  contact.commit(obstacle, x);
  ASSERT_GT(contact.size(), 20U);
  auto rng = test::make_rng(31);
  std::normal_distribution<double> jitter(0.0, 2e-4);
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += jitter(rng);

  const Eigen::Index np = x.size(), nq = sphere.V.size();
  const auto split = [&](const Eigen::VectorXd& z, Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& q) {
    p = Eigen::Map<const Eigen::Matrix3Xd>(z.data(), 3, x.cols());
    q = Eigen::Map<const Eigen::Matrix3Xd>(z.data() + np, 3, sphere.V.rows());
  };
  const auto moved = [&](const Eigen::Matrix3Xd& q) {
    Obstacle o(sphere, "sphere");
    o.set_vertices(q.transpose());
    return o;
  };
  const auto energy = [&](const Eigen::VectorXd& z) {
    Eigen::Matrix3Xd p, q;
    split(z, p, q);
    return contact.energy(moved(q), p);
  };
  const auto gradient = [&](const Eigen::VectorXd& z) {
    Eigen::Matrix3Xd p, q;
    split(z, p, q);
    const Obstacle o = moved(q);
    Eigen::Matrix3Xd gp = Eigen::Matrix3Xd::Zero(3, p.cols()), gq = Eigen::Matrix3Xd::Zero(3, q.cols());
    contact.add_gradient(o, p, gp);
    contact.add_obstacle_gradient(o, p, gq);
    Eigen::VectorXd g(np + nq);
    g << gp.reshaped(), gq.reshaped();
    return g;
  };
  Eigen::VectorXd z(np + nq);
  const Eigen::Matrix3Xd q0 = sphere.V.transpose();
  z << x.reshaped(), q0.reshaped();
  const Eigen::VectorXd g = gradient(z);
  EXPECT_TRUE(derivatives_match(g, test::fd_gradient(energy, z, 1e-7), 1e-7));

  Eigen::MatrixXd H(np + nq, np + nq);
  for (Eigen::Index j = 0; j < np + nq; ++j) {
    Eigen::Matrix3Xd vp, vq;
    split(Eigen::VectorXd::Unit(np + nq, j), vp, vq);
    Eigen::Matrix3Xd hp = Eigen::Matrix3Xd::Zero(3, x.cols()), hq = Eigen::Matrix3Xd::Zero(3, q0.cols());
    contact.add_hessian_product(obstacle, x, vp, vq, hp, hq);
    H.col(j) << hp.reshaped(), hq.reshaped();
  }
  EXPECT_TRUE(derivatives_match(H, fd_jacobian(gradient, z, 1e-7), 1e-6));
  // The stencils' blocks assemble to the same matrix.
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(np + nq, np + nq);
  contact.for_each_stencil_hessian(obstacle, x, [&](const Stencil& st, const Matrix12d& K) {
    const auto row = [&](int slot) { return st.on_surface(slot) ? 3 * st.vertex(slot) : np + 3 * st.vertex(slot); };
    for (int a = 0; a < st.slots(); ++a) {
      for (int b = 0; b < st.slots(); ++b) S.block<3, 3>(row(a), row(b)) += st.block(K, a, b);
    }
  });
  EXPECT_LT((S - H).cwiseAbs().maxCoeff(), 1e-9 * H.cwiseAbs().maxCoeff());
  // The surface blocks: the positive semi-definite part a Newton step uses.
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(np, np);
  contact.for_each_surface_hessian(obstacle, [&](int a, int b, const Eigen::Matrix3d& B) {
    P.block<3, 3>(3 * a, 3 * b) += B;
  });
  EXPECT_LT((P - H.topLeftCorner(np, np)).cwiseAbs().maxCoeff(), 1e-9 * P.cwiseAbs().maxCoeff());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(P).eigenvalues().minCoeff(), -1e-9 * P.norm());
}

}  // namespace
}  // namespace palpa::contact
