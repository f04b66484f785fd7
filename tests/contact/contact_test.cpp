// SPDX-License-Identifier: AGPL-3.0-or-later
// Batch detection; the penalty-contact potential's energy, gradient and
// Hessian (finite differences, over the points and the obstacle's vertices),
// force and torque balance on both sides, excluded features; the stiffness
// rule and its controller.

#include "palpa/contact/contact.hpp"
#include "palpa/contact/penalty_contact.hpp"
#include "palpa/contact/stiffness.hpp"

#include <cmath>
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
  PenaltyContact set(vertex_samples(s.which), kPenalty, "torus");
  set.commit(s.obstacle, s.points);
  ASSERT_GT(set.size(), 100U);
  std::size_t c = 0;
  int kinds[3] = {0, 0, 0};
  for (int i : s.which) {
    const ClosestPoint cp = s.obstacle.closest_point(s.points.col(i));
    if (!cp.inside) continue;
    ASSERT_LT(c, set.size());
    const SampleContact& contact = set.contacts()[c++];
    EXPECT_EQ(s.which[static_cast<std::size_t>(contact.sample)], i);
    EXPECT_EQ(contact.closest.distance, cp.distance);
    EXPECT_EQ(contact.closest.vertices, cp.vertices);
    ++kinds[static_cast<int>(cp.feature)];
  }
  EXPECT_EQ(c, set.size());
  EXPECT_GT(kinds[0] + kinds[1], 0);
  // Every column a sample: more contacts.
  std::vector<int> columns(static_cast<std::size_t>(s.points.cols()));
  std::iota(columns.begin(), columns.end(), 0);
  PenaltyContact all(vertex_samples(columns), kPenalty, "torus");
  all.commit(s.obstacle, s.points);
  EXPECT_GT(all.size(), set.size());
}

TEST(ContactDetection, ReusesItsStorage) {
  Scene s;
  PenaltyContact set(vertex_samples(s.which), kPenalty, "torus");
  set.commit(s.obstacle, s.points);
  const SampleContact* data = set.contacts().data();
  const std::size_t n = set.size();
  for (int repeat = 0; repeat < 3; ++repeat) set.commit(s.obstacle, s.points);
  EXPECT_EQ(set.contacts().data(), data);
  EXPECT_EQ(set.size(), n);
}

TEST(ContactDetection, DetectedEnergyEqualsCommittedEnergyAtThePreparedPoint) {
  Scene s;
  PenaltyContact set(vertex_samples(s.which), kPenalty, "torus");
  set.commit(s.obstacle, s.points);
  const double detected = set.detected_energy(s.obstacle, s.points);
  EXPECT_GT(detected, 0.0);
  EXPECT_NEAR(set.energy(s.obstacle, s.points), detected, 1e-12 * detected);
  double sum = 0.0;
  for (const SampleContact& c : set.contacts())
    sum += kPenalty * c.closest.distance * c.closest.distance;
  EXPECT_NEAR(sum, detected, 1e-12 * detected);
  EXPECT_GT(set.max_depth(), 0.0);
  EXPECT_LE(set.max_depth(), 0.015);
}

TEST(ContactCommitted, GradientAndHessianMatchFiniteDifferencesAwayFromThePreparedPoint) {
  Scene s(400);
  PenaltyContact set(vertex_samples(s.which), kPenalty, "torus");
  set.commit(s.obstacle, s.points);
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
  for (const SampleContact& c : set.contacts()) {
    for (int k = 0; k < 3; ++k) dofs.push_back(3 * s.which[static_cast<std::size_t>(c.sample)] + k);
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
    return set.energy(s.obstacle, as_points(expand(r)));
  };
  const auto gradient = [&](const Eigen::VectorXd& r) {
    Eigen::Matrix3Xd g = Eigen::Matrix3Xd::Zero(3, s.points.cols());
    set.add_gradient(s.obstacle, as_points(expand(r)), g);
    return restrict(g.reshaped());
  };
  const Eigen::VectorXd r = restrict(x);
  EXPECT_TRUE(derivatives_match(gradient(r), fd_gradient(energy, r, 1e-6), 1e-7));
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(r.size(), r.size());
  Eigen::Index c = 0;
  set.for_each_surface_hessian(s.obstacle, [&](int a, int b, const Eigen::Matrix3d& block) {
    const int point = s.which[static_cast<std::size_t>(set.contacts()[static_cast<std::size_t>(c)].sample)];
    EXPECT_EQ(a, point);
    EXPECT_EQ(b, point);
    H.block<3, 3>(3 * c, 3 * c) = block;
    ++c;
  });
  EXPECT_TRUE(derivatives_match(H, fd_jacobian(gradient, r, 1e-6), 1e-7));
}

// A small sphere as a deformable obstacle and three points inside it,
// committed.
struct SphereScene {
  SurfaceMesh sphere = test::sphere_mesh(0.03, 1);
  Obstacle obstacle{sphere, "sphere"};
  Eigen::Matrix3Xd points{3, 3};
  PenaltyContact contact{vertex_samples(std::vector<int>{0, 1, 2}), kPenalty, "sphere"};

  SphereScene() {
    points << 0.025, -0.01, 0.0,  //
        0.003, 0.02, -0.027,      //
        0.01, 0.015, 0.005;
    contact.commit(obstacle, points);
  }
};

TEST(ContactCommitted, ObstacleGradientMatchesFiniteDifferences) {
  // The energy as a function of the sphere's vertices (world = body here),
  // with the committed features.
  const SphereScene s;
  ASSERT_EQ(s.contact.size(), 3U);
  const auto energy = [&](const Eigen::VectorXd& v) {
    Obstacle o = Obstacle(s.sphere, "sphere");
    o.set_vertices(Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
        v.data(), s.sphere.V.rows(), 3));
    return s.contact.energy(o, s.points);
  };
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> rows = s.sphere.V;
  const Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(rows.data(), rows.size());
  Eigen::Matrix3Xd grad = Eigen::Matrix3Xd::Zero(3, s.sphere.V.rows());
  s.contact.add_obstacle_gradient(s.obstacle, s.points, grad);
  EXPECT_TRUE(derivatives_match(grad.reshaped(), fd_gradient(energy, v, 1e-6), 1e-7));
}

TEST(ContactCommitted, StencilHessianProductMatchesFiniteDifferences) {
  // The whole Hessian over the points and the obstacle's vertices, as a
  // product, against finite differences of both gradients: what the coupled
  // support and the shape derivative use.
  const SphereScene s;
  ASSERT_EQ(s.contact.size(), 3U);
  const Eigen::Index np = s.points.size(), nq = s.sphere.V.size();
  const auto split = [&](const Eigen::VectorXd& z, Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& q) {
    p = Eigen::Map<const Eigen::Matrix3Xd>(z.data(), 3, s.points.cols());
    q = Eigen::Map<const Eigen::Matrix3Xd>(z.data() + np, 3, s.sphere.V.rows());
  };
  const auto gradient = [&](const Eigen::VectorXd& z) {
    Eigen::Matrix3Xd p, q;
    split(z, p, q);
    Obstacle o = Obstacle(s.sphere, "sphere");
    o.set_vertices(q.transpose());
    Eigen::Matrix3Xd gp = Eigen::Matrix3Xd::Zero(3, p.cols()), gq = Eigen::Matrix3Xd::Zero(3, q.cols());
    s.contact.add_gradient(o, p, gp);
    s.contact.add_obstacle_gradient(o, p, gq);
    Eigen::VectorXd g(np + nq);
    g << gp.reshaped(), gq.reshaped();
    return g;
  };
  Eigen::VectorXd z(np + nq);
  const Eigen::Matrix3Xd q0 = s.sphere.V.transpose();
  z << s.points.reshaped(), q0.reshaped();
  const Eigen::MatrixXd fd = fd_jacobian(gradient, z, 1e-7);
  Eigen::MatrixXd H(np + nq, np + nq);
  for (Eigen::Index j = 0; j < np + nq; ++j) {
    Eigen::VectorXd e = Eigen::VectorXd::Unit(np + nq, j);
    Eigen::Matrix3Xd vp, vq;
    split(e, vp, vq);
    Eigen::Matrix3Xd hp = Eigen::Matrix3Xd::Zero(3, s.points.cols()), hq = Eigen::Matrix3Xd::Zero(3, q0.cols());
    s.contact.add_hessian_product(s.obstacle, s.points, vp, vq, hp, hq);
    H.col(j) << hp.reshaped(), hq.reshaped();
  }
  EXPECT_TRUE(derivatives_match(H, fd, 1e-6));
  // The point side alone (a rigid obstacle's response): the same rows.
  Eigen::Matrix3Xd hp = Eigen::Matrix3Xd::Zero(3, s.points.cols()), none(3, 0);
  const Eigen::Matrix3Xd vp = Eigen::Matrix3Xd::Ones(3, s.points.cols());
  s.contact.add_hessian_product(s.obstacle, s.points, vp, none, hp, none);
  EXPECT_TRUE(derivatives_match(Eigen::VectorXd(hp.reshaped()), Eigen::VectorXd(H.topLeftCorner(np, np) * vp.reshaped()), 1e-12));
}

TEST(ContactCommitted, ExcludedFeaturesAreNoContacts) {
  // Two points under a cube's top face; flag the corners of the face's
  // triangles under one of them: that point is no contact, in the trial
  // energy as in the committed set.
  const Obstacle box(test::cube_mesh(0.01), "box");
  Eigen::Matrix3Xd points(3, 2);
  points << 0.002, -0.002, 0.003, -0.003, 0.0098, 0.0097;
  PenaltyContact all(vertex_samples(std::vector<int>{0, 1}), kPenalty, "box");
  all.commit(box, points);
  ASSERT_EQ(all.size(), 2U);
  std::vector<char> excluded(static_cast<std::size_t>(box.vertices().rows()), 0);
  for (int i = 0; i < feature_size(all.contacts()[0].closest.feature); ++i) {
    excluded[static_cast<std::size_t>(all.contacts()[0].closest.vertices[static_cast<std::size_t>(i)])] = 1;
  }
  PenaltyContact some(vertex_samples(std::vector<int>{0, 1}), kPenalty, "box");
  some.set_excluded(excluded);
  some.commit(box, points);
  const bool shared = std::any_of(all.contacts()[1].closest.vertices.begin(),
                                  all.contacts()[1].closest.vertices.end(),
                                  [&](int v) { return v >= 0 && excluded[static_cast<std::size_t>(v)] != 0; });
  ASSERT_EQ(some.size(), shared ? 0U : 1U);
  if (!shared) EXPECT_EQ(some.contacts()[0].sample, 1);
  EXPECT_NEAR(some.detected_energy(box, points), some.energy(box, points), 1e-12 * all.energy(box, points));
  EXPECT_LT(some.detected_energy(box, points), all.detected_energy(box, points));
}

TEST(ContactForces, BalanceForceAndTorque) {
  Scene s;
  PenaltyContact set(vertex_samples(s.which), kPenalty, "torus");
  set.commit(s.obstacle, s.points);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, s.points.cols());
  Eigen::Matrix3Xd on_obstacle = Eigen::Matrix3Xd::Zero(3, s.obstacle.vertices().rows());
  set.add_forces(s.obstacle, s.points, f, on_obstacle);
  const Eigen::Vector3d about(0.003, -0.02, 0.01);
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < f.cols(); ++i) {
    force += f.col(i);
    torque += (s.points.col(i) - about).cross(f.col(i));
  }
  const Wrench w = set.obstacle_wrench(s.obstacle, s.points, about);
  EXPECT_GT(w.force.norm(), 0.0);
  EXPECT_LT((w.force + force).norm(), 1e-12 * f.colwise().norm().sum());
  EXPECT_LT((w.torque + torque).norm(), 1e-12 * 0.1 * f.colwise().norm().sum());
  EXPECT_GT(w.torque.norm(), 0.0);
  // The reaction is also what the obstacle's vertices feel: −∂E/∂q.
  Eigen::Matrix3Xd gq = Eigen::Matrix3Xd::Zero(3, s.obstacle.vertices().rows());
  set.add_obstacle_gradient(s.obstacle, s.points, gq);
  EXPECT_EQ(on_obstacle, -gq);
  Eigen::Vector3d vertex_torque = Eigen::Vector3d::Zero();
  for (Eigen::Index v = 0; v < gq.cols(); ++v) {
    vertex_torque += (s.obstacle.world_vertex(static_cast<int>(v)) - about).cross(-gq.col(v));
  }
  EXPECT_LT((-gq.rowwise().sum() - w.force).norm(), 1e-12 * w.force.norm());
  EXPECT_LT((vertex_torque - w.torque).norm(), 1e-10 * w.torque.norm());
  // Forces push out: each points from the point to its anchor.
  for (const SampleContact& c : set.contacts()) {
    const int point = s.which[static_cast<std::size_t>(c.sample)];
    EXPECT_GT(f.col(point).dot(c.closest.point - s.points.col(point)), 0.0);
  }
}

TEST(ContactForces, PressureOnAFlatFace) {
  // A point 0.2 mm below the top face of a 2 cm cube: force 2kδ up.
  const Obstacle box(test::cube_mesh(0.01), "box");
  Eigen::Matrix3Xd points(3, 2);
  points << 0.001, 0.5, 0.002, 0.5, 0.0098, 0.5;  // the second is far outside
  PenaltyContact set(vertex_samples(std::vector<int>{0, 1}), kPenalty, "box");
  set.commit(box, points);
  ASSERT_EQ(set.size(), 1U);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, 2), none(3, 0);
  set.add_forces(box, points, f, none);
  EXPECT_NEAR(f(2, 0), 2.0 * kPenalty * 2e-4, 1e-12);
  EXPECT_LT(f.col(0).head<2>().norm(), 1e-12 * f(2, 0));
  EXPECT_EQ(f.col(1).norm(), 0.0);
  // Per-point spring factors scale the force.
  PenaltyContact scaled(vertex_samples(std::vector<int>{0, 1}), kPenalty, "box");
  scaled.set_scale({0.5, 3.0});
  scaled.commit(box, points);
  Eigen::Matrix3Xd g = Eigen::Matrix3Xd::Zero(3, 2);
  scaled.add_forces(box, points, g, none);
  EXPECT_NEAR(g(2, 0), 0.5 * f(2, 0), 1e-15);
  EXPECT_TRUE(test::throws_error([&] { scaled.set_stiffness(0.0); }, ErrorKind::Input, {"box", "stiffness"}));
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
  // A pressure E/10 on a vertex of area A at the target depth.
  EXPECT_NEAR(2.0 * stiffness_for_pressure(1e3, 4e-6, 2e-4) * 2e-4 / 4e-6, 1e3, 1e-9);
}

TEST(ContactStiffness, ControllerKeepsKInsideTheBandAndCorrectsOutside) {
  StiffnessPolicy band;
  band.target = 3e-4;
  StiffnessController c(band);
  const double k = 2e4;
  EXPECT_EQ(c.next(k, 3e-4), k);
  EXPECT_EQ(c.next(k, 0.86 * 3e-4), k);
  EXPECT_TRUE(c.accepts(1.14 * 3e-4));
  EXPECT_FALSE(c.accepts(1.2 * 3e-4));
  EXPECT_NEAR(c.next(k, 6e-4), 2.0 * k, 1e-9 * k);
  EXPECT_NEAR(c.next(k, 1.5e-4), 0.5 * k, 1e-9 * k);
  EXPECT_NEAR(c.next(k, 1.0), 10.0 * k, 1e-9 * k);  // clamped
  // Only raising, 10% beyond the proportional rule: any depth up to the target passes.
  StiffnessPolicy raise = band;
  raise.low = 0.0;
  raise.high = 1.0;
  raise.overshoot = 1.1;
  StiffnessController r(raise);
  EXPECT_EQ(r.next(k, 1e-5), k);
  EXPECT_EQ(r.next(k, 0.0), k);
  EXPECT_NEAR(r.next(k, 6e-4), 2.2 * k, 1e-9 * k);
  band.target = 0.0;
  EXPECT_TRUE(test::throws_error([&] { StiffnessController bad(band); }, ErrorKind::Input, {"target penetration"}));
}

TEST(ContactStiffness, ExponentFromTwoSolvesLandsAGrowingContactInFewSolves) {
  // depth = C·k^−α: a flat punch (α = 1), a sphere on a plane (½).
  const auto depth = [](double k, double alpha) { return 3e-4 * std::pow(k / 1e6, -alpha); };
  for (const double alpha : {1.0, 0.5, 0.7}) {
    EXPECT_NEAR(penetration_exponent(1e5, depth(1e5, alpha), 4e5, depth(4e5, alpha), 9.0), alpha, 1e-12);
  }
  EXPECT_EQ(penetration_exponent(1e5, 1e-3, 4e5, 1e-3, 0.5), 0.25);  // no change in depth: clamped
  EXPECT_EQ(penetration_exponent(1e5, 1e-3, 1.005e5, 9e-4, 0.5), 0.5);  // k too close to tell
  EXPECT_EQ(penetration_exponent(1e5, 0.0, 4e5, 9e-4, 0.5), 0.5);
  // Under α = ½ the proportional rule undershoots; the square lands at once.
  EXPECT_NEAR(corrected_stiffness(1e6, 6e-4, 3e-4, 10.0, 0.5), 4e6, 1e-3);

  // From 10× too deep, a contact with α = 0.6: the proportional rule needs
  // five solves, the measured exponent three.
  const auto solves = [&](StiffnessPolicy policy) {
    StiffnessController c(policy);
    double k = 1e6 / std::pow(10.0, 1.0 / 0.6);
    int n = 1;
    for (; !c.accepts(depth(k, 0.6)) && n < 20; ++n) k = c.next(k, depth(k, 0.6));
    return n;
  };
  StiffnessPolicy proportional;
  EXPECT_EQ(solves(proportional), 5);
  StiffnessPolicy measured;
  measured.exponent = 0.5;
  measured.measure_exponent = true;
  EXPECT_EQ(solves(measured), 3);
  // restart() forgets: the same pair no longer informs the next correction.
  StiffnessController c(measured);
  c.next(1e6, depth(1e6, 1.0) * 10.0);
  c.restart();
  EXPECT_NEAR(c.next(2e6, 6e-4), 8e6, 1e-3);
}

}  // namespace
}  // namespace palpa::contact
