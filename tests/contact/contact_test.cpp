// SPDX-License-Identifier: AGPL-3.0-or-later
// Batch detection, the committed contact set's energy/gradient/Hessian (finite
// differences), force and torque balance, pressures and the stiffness rule.

#include "palpa/contact/contact.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <numeric>

#include "common/finite_difference.hpp"
#include "common/test_support.hpp"
#include "contact/shapes.hpp"

namespace palpa::contact {
namespace {

using test::derivatives_match;
using test::fd_gradient;
using test::fd_jacobian;

constexpr double kPenalty = 1e4;  // N/m

// A torus obstacle (concave and convex regions, all three feature kinds),
// posed, and random points around it.
struct Scene {
  Obstacle obstacle{test::torus_mesh(0.04, 0.015, 24, 12), "torus"};
  Eigen::Matrix3Xd points;
  std::vector<int> which;

  explicit Scene(int n = 4000) {
    Pose pose;
    pose.R =
        Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.2, 1.0, -0.3).normalized()).toRotationMatrix();
    pose.t = Eigen::Vector3d(0.01, 0.02, -0.005);
    obstacle.set_pose(pose);
    auto rng = test::make_rng(20);
    std::uniform_real_distribution<double> u(-0.06, 0.06);
    points.resize(3, n);
    for (int i = 0; i < n; ++i) {
      const double ux = u(rng), uy = u(rng), uz = u(rng);  // drawn in order on every compiler
      points.col(i) = pose.t + Eigen::Vector3d(ux, uy, 0.4 * uz);
    }
    for (int i = 0; i < n; i += 2) which.push_back(i);  // every other point may touch
  }
};

TEST(ContactDetection, FindsExactlyThePointsInside) {
  Scene s;
  ContactSet set;
  set.detect(s.obstacle, s.points, s.which);
  ASSERT_GT(set.size(), 100U);
  std::size_t c = 0;
  int kinds[3] = {0, 0, 0};
  for (int i : s.which) {
    const ClosestPoint cp = s.obstacle.closest_point(s.points.col(i));
    if (!cp.inside) continue;
    ASSERT_LT(c, set.size());
    const Contact& contact = set.contacts()[c++];
    EXPECT_EQ(contact.point, i);
    EXPECT_EQ(contact.closest.distance, cp.distance);
    EXPECT_EQ(contact.closest.vertices, cp.vertices);
    ++kinds[static_cast<int>(cp.feature)];
  }
  EXPECT_EQ(c, set.size());
  EXPECT_GT(kinds[0] + kinds[1], 0);
  // detect() without a list: all columns.
  ContactSet all;
  all.detect(s.obstacle, s.points);
  EXPECT_GT(all.size(), set.size());
}

TEST(ContactDetection, ReusesItsStorage) {
  Scene s;
  ContactSet set;
  set.detect(s.obstacle, s.points, s.which);
  const Contact* data = set.contacts().data();
  const std::size_t n = set.size();
  for (int repeat = 0; repeat < 3; ++repeat) set.detect(s.obstacle, s.points, s.which);
  EXPECT_EQ(set.contacts().data(), data);
  EXPECT_EQ(set.size(), n);
}

TEST(ContactDetection, DetectedEnergyEqualsCommittedEnergyAtThePreparedPoint) {
  Scene s;
  ContactSet set;
  set.detect(s.obstacle, s.points, s.which);
  const double detected = detected_energy(s.obstacle, s.points, s.which, kPenalty);
  EXPECT_GT(detected, 0.0);
  EXPECT_NEAR(set.energy(s.obstacle, s.points, kPenalty), detected, 1e-12 * detected);
  double sum = 0.0;
  for (const Contact& c : set.contacts())
    sum += kPenalty * c.closest.distance * c.closest.distance;
  EXPECT_NEAR(sum, detected, 1e-12 * detected);
  EXPECT_GT(set.max_depth(), 0.0);
  EXPECT_LE(set.max_depth(), 0.015);
}

TEST(ContactCommitted, GradientAndHessianMatchFiniteDifferencesAwayFromThePreparedPoint) {
  Scene s(400);
  ContactSet set;
  set.detect(s.obstacle, s.points, s.which);
  ASSERT_GT(set.size(), 5U);
  // Evaluate at moved points: the anchors slide on the committed features.
  auto rng = test::make_rng(21);
  std::normal_distribution<double> jitter(0.0, 5e-4);
  Eigen::Matrix3Xd moved = s.points;
  for (Eigen::Index i = 0; i < moved.size(); ++i) moved.data()[i] += jitter(rng);
  const Eigen::VectorXd x = moved.reshaped();
  const auto as_points = [&](const Eigen::VectorXd& y) {
    return Eigen::Map<const Eigen::Matrix3Xd>(y.data(), 3, y.size() / 3);
  };
  // Only the contact points' coordinates matter: check those.
  std::vector<Eigen::Index> dofs;
  for (const Contact& c : set.contacts()) {
    for (int k = 0; k < 3; ++k) dofs.push_back(3 * c.point + k);
  }
  const auto restrict = [&](const Eigen::VectorXd& full) {
    Eigen::VectorXd r(static_cast<Eigen::Index>(dofs.size()));
    for (std::size_t j = 0; j < dofs.size(); ++j) r[static_cast<Eigen::Index>(j)] = full[dofs[j]];
    return r;
  };
  const auto expand = [&](const Eigen::VectorXd& r) {
    Eigen::VectorXd full = x;
    for (std::size_t j = 0; j < dofs.size(); ++j) full[dofs[j]] = r[static_cast<Eigen::Index>(j)];
    return full;
  };
  const auto energy = [&](const Eigen::VectorXd& r) {
    return set.energy(s.obstacle, as_points(expand(r)), kPenalty);
  };
  const auto gradient = [&](const Eigen::VectorXd& r) {
    Eigen::Matrix3Xd g = Eigen::Matrix3Xd::Zero(3, s.points.cols());
    set.add_gradient(s.obstacle, as_points(expand(r)), kPenalty, g);
    return restrict(g.reshaped());
  };
  const Eigen::VectorXd r = restrict(x);
  EXPECT_TRUE(derivatives_match(gradient(r), fd_gradient(energy, r, 1e-6), 1e-7));
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(r.size(), r.size());
  for (std::size_t c = 0; c < set.size(); ++c) {
    H.block<3, 3>(3 * static_cast<Eigen::Index>(c), 3 * static_cast<Eigen::Index>(c)) =
        hessian_block(s.obstacle, set.contacts()[c], kPenalty);
  }
  EXPECT_TRUE(derivatives_match(H, fd_jacobian(gradient, r, 1e-6), 1e-7));
}

TEST(ContactCommitted, ObstacleGradientMatchesFiniteDifferences) {
  // A small sphere as a deformable obstacle: the energy as a function of its
  // vertices (world = body here), with the committed features.
  const SurfaceMesh sphere = test::sphere_mesh(0.03, 1);
  Obstacle obstacle(sphere, "sphere");
  Eigen::Matrix3Xd points(3, 3);
  points << 0.025, -0.01, 0.0,  //
      0.003, 0.02, -0.027,      //
      0.01, 0.015, 0.005;
  ContactSet set;
  set.detect(obstacle, points);
  ASSERT_EQ(set.size(), 3U);
  const auto energy = [&](const Eigen::VectorXd& v) {
    Obstacle o = Obstacle(sphere, "sphere");
    o.set_vertices(Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
        v.data(), sphere.V.rows(), 3));
    return set.energy(o, points, kPenalty);
  };
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> rows = sphere.V;
  const Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(rows.data(), rows.size());
  Eigen::Matrix3Xd grad = Eigen::Matrix3Xd::Zero(3, sphere.V.rows());
  set.add_obstacle_gradient(obstacle, points, kPenalty, grad);
  EXPECT_TRUE(derivatives_match(grad.reshaped(), fd_gradient(energy, v, 1e-6), 1e-7));
}

TEST(ContactForces, BalanceForceAndTorque) {
  Scene s;
  ContactSet set;
  set.detect(s.obstacle, s.points, s.which);
  Eigen::Matrix3Xd f;
  set.forces(s.obstacle, s.points, kPenalty, f);
  ASSERT_EQ(f.cols(), s.points.cols());
  const Eigen::Vector3d about(0.003, -0.02, 0.01);
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < f.cols(); ++i) {
    force += f.col(i);
    torque += (s.points.col(i) - about).cross(f.col(i));
  }
  const Wrench w = set.obstacle_wrench(s.obstacle, s.points, kPenalty, about);
  EXPECT_GT(w.force.norm(), 0.0);
  EXPECT_LT((w.force + force).norm(), 1e-12 * f.colwise().norm().sum());
  EXPECT_LT((w.torque + torque).norm(), 1e-12 * 0.1 * f.colwise().norm().sum());
  EXPECT_GT(w.torque.norm(), 0.0);
  // The reaction is also what the obstacle's vertices feel: −∂E/∂q.
  Eigen::Matrix3Xd gq = Eigen::Matrix3Xd::Zero(3, s.obstacle.vertices().rows());
  set.add_obstacle_gradient(s.obstacle, s.points, kPenalty, gq);
  Eigen::Vector3d vertex_torque = Eigen::Vector3d::Zero();
  for (Eigen::Index v = 0; v < gq.cols(); ++v) {
    vertex_torque += (s.obstacle.world_vertex(static_cast<int>(v)) - about).cross(-gq.col(v));
  }
  EXPECT_LT((-gq.rowwise().sum() - w.force).norm(), 1e-12 * w.force.norm());
  EXPECT_LT((vertex_torque - w.torque).norm(), 1e-10 * w.torque.norm());
  // Forces push out: each points from the point to its anchor.
  for (const Contact& c : set.contacts()) {
    EXPECT_GT(f.col(c.point).dot(c.closest.point - s.points.col(c.point)), 0.0);
  }
}

TEST(ContactForces, PressureOnAFlatFace) {
  // A point 0.2 mm below the top face of a 2 cm cube: force 2kδ up.
  const Obstacle box(test::cube_mesh(0.01), "box");
  Eigen::Matrix3Xd points(3, 2);
  points << 0.001, 0.5, 0.002, 0.5, 0.0098, 0.5;  // the second is far outside
  ContactSet set;
  set.detect(box, points);
  ASSERT_EQ(set.size(), 1U);
  Eigen::Matrix3Xd f;
  set.forces(box, points, kPenalty, f);
  EXPECT_NEAR(f(2, 0), 2.0 * kPenalty * 2e-4, 1e-12);
  EXPECT_LT(f.col(0).head<2>().norm(), 1e-12 * f(2, 0));
  EXPECT_EQ(f.col(1).norm(), 0.0);
  const Eigen::VectorXd p = pressures(f, Eigen::Vector2d(1e-6, 0.0));
  EXPECT_NEAR(p[0], 2.0 * kPenalty * 2e-4 / 1e-6, 1e-6);
  EXPECT_EQ(p[1], 0.0);
}

TEST(ContactStiffness, RuleAndCorrection) {
  // 100 N shared by 50 points at 0.3 mm each.
  const double k = stiffness_for_penetration(100.0, 50.0, 3e-4);
  EXPECT_NEAR(k, 100.0 / (2.0 * 50.0 * 3e-4), 1e-9);
  // Check against the model it assumes: n points of a flat face, each carrying
  // load/n, sit at the target depth.
  EXPECT_NEAR((100.0 / 50.0) / (2.0 * k), 3e-4, 1e-15);
  EXPECT_NEAR(corrected_stiffness(k, 6e-4, 3e-4), 2.0 * k, 1e-9 * k);
  EXPECT_NEAR(corrected_stiffness(k, 1.5e-4, 3e-4), 0.5 * k, 1e-9 * k);
  EXPECT_NEAR(corrected_stiffness(k, 1.0, 3e-4), 10.0 * k, 1e-9 * k);
  EXPECT_NEAR(corrected_stiffness(k, 1e-9, 3e-4, 4.0), 0.25 * k, 1e-9 * k);
  EXPECT_EQ(corrected_stiffness(k, 0.0, 3e-4), k);
  EXPECT_TRUE(test::throws_error([] { stiffness_for_penetration(100.0, 0.0, 3e-4); },
                                 ErrorKind::Input, {"contact stiffness", "0 contact points"}));
}

}  // namespace
}  // namespace palpa::contact
