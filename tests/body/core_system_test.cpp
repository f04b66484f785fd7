// SPDX-License-Identifier: AGPL-3.0-or-later
// The layer + rigid core system: the exponential map and its Jacobian, the
// coupled gradient (exact at any pose) and Hessian (exact at the committed
// pose) against finite differences, rigid motions of the whole body, locked
// DOFs, bad input.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <memory>
#include <random>

#include "common/finite_difference.hpp"
#include "common/test_support.hpp"
#include "palpa/body/core_system.hpp"
#include "palpa/material/models.hpp"
#include "palpa/tet/mesh.hpp"

namespace palpa::body {
namespace {

using palpa::test::derivatives_match;
using palpa::test::fd_gradient;
using palpa::test::fd_jacobian;

TEST(So3, ExponentialAndLeftJacobian) {
  const Eigen::Vector3d w(0.3, -0.7, 0.45);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  EXPECT_LE((exp_so3(w) - R).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LE((exp_so3(Eigen::Vector3d(1e-9, 0, 0)) - Eigen::Matrix3d::Identity()).norm(), 2e-9);
  // exp(ω + δ) = exp(J_l(ω) δ) exp(ω) + O(δ²).
  const Eigen::Vector3d d(1e-6, -2e-6, 0.5e-6);
  const Eigen::Matrix3d lhs = exp_so3(w + d);
  const Eigen::Matrix3d rhs = exp_so3(left_jacobian_so3(w) * d) * exp_so3(w);
  EXPECT_LE((lhs - rhs).cwiseAbs().maxCoeff(), 1e-11);
}

// A spring energy on some vertices (a stand-in for contact).
class Springs final : public Term {
 public:
  std::vector<std::pair<int, Eigen::Vector3d>> springs;
  double k = 30.0;
  double energy(const VertexState& s) const override {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(s.p.size());
    return add_gradient(s, g);
  }
  double add_gradient(const VertexState& s, Eigen::VectorXd& g) const override {
    const Eigen::VectorXd& x = s.p;
    double e = 0.0;
    for (const auto& [v, p] : springs) {
      const Eigen::Vector3d d = x.segment<3>(3 * v) - p;
      e += 0.5 * k * d.squaredNorm();
      g.segment<3>(3 * v) += k * d;
    }
    return e;
  }
  void add_blocks(const VertexState&, PsdProjection, std::vector<VertexBlock>& b) const override {
    for (const auto& [v, p] : springs) b.push_back({v, v, k * Eigen::Matrix3d::Identity()});
  }
};

struct Layer {
  tet::BoxMesh box;
  std::unique_ptr<tet::ElasticModel> model;
  CoreSpec core;
};

// A 20 × 20 × 10 mm block whose bottom face is attached to the core.
Layer make_layer() {
  Layer l;
  l.box = tet::make_box_mesh(Eigen::Vector3d(-0.01, -0.01, 0.0), Eigen::Vector3d(0.01, 0.01, 0.01),
                             Eigen::Vector3i(2, 2, 2));
  l.model = std::make_unique<tet::ElasticModel>(
      l.box.mesh, std::vector<tet::BodyMaterial>{{std::make_shared<material::NeoHookean>(8e3, 0.35), 1000.0}});
  l.core.attached = l.box.vertex_sets.at("bottom");
  l.core.mass = 0.05;
  l.core.centre = Eigen::Vector3d(0.001, -0.002, -0.005);
  l.core.force = Eigen::Vector3d(0.01, -0.02, -0.1);
  l.core.torque = Eigen::Vector3d(1e-4, 2e-4, -1e-4);
  return l;
}

// x with the core moved by (t, ω) and every free vertex carried along rigidly.
Eigen::VectorXd rigidly_moved(const CoreSystem& sys, const Layer& l, const Eigen::Vector3d& t, const Eigen::Vector3d& w) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(sys.num_dofs());
  std::size_t k = 0;
  for (int c = 0; c < 6; ++c) {
    if (l.core.locked[static_cast<std::size_t>(c)]) continue;
    x[sys.num_vertex_dofs() + static_cast<Eigen::Index>(k++)] = c < 3 ? t[c] : w[c - 3];
  }
  const Eigen::Matrix3d R = exp_so3(w);
  const TetMesh& mesh = l.model->mesh();
  std::vector<char> attached(static_cast<std::size_t>(mesh.V.rows()), 0);
  for (int v : l.core.attached) attached[static_cast<std::size_t>(v)] = 1;
  Eigen::Index i = 0;
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
    if (attached[static_cast<std::size_t>(v)]) continue;
    const Eigen::Vector3d X = mesh.V.row(v).transpose();
    x.segment<3>(i) = l.core.centre + t + R * (X - l.core.centre) - X;
    i += 3;
  }
  return x;
}

class CoreDerivatives : public ::testing::TestWithParam<bool> {};

TEST_P(CoreDerivatives, GradientAnywhereAndHessianAtTheCommittedPose) {
  const bool lock_some = GetParam();
  Layer l = make_layer();
  if (lock_some) l.core.locked = {true, true, false, true, false, true};  // vertical + pitch only
  CoreSystem sys(*l.model, l.core, PsdProjection::None);
  sys.set_gravity(Eigen::Vector3d(0.0, 0.0, -9.81));
  Springs springs;
  springs.springs = {{l.box.vertex_sets.at("top")[4], Eigen::Vector3d(0.0, 0.001, 0.0085)},
                     {l.box.vertex_sets.at("bottom")[2], Eigen::Vector3d(0.0, 0.0, -0.001)}};  // an attached one
  sys.add_term(&springs);
  auto rng = palpa::test::make_rng(17);
  std::uniform_real_distribution<double> du(-4e-4, 4e-4);
  const auto jitter = [&](Eigen::VectorXd x) {
    for (Eigen::Index i = 0; i < sys.num_vertex_dofs(); ++i) x[i] += du(rng);
    return x;
  };
  // Commit a rotated pose, then evaluate away from it (ω' ≠ 0): the gradient
  // is exact there too.
  const Eigen::VectorXd x0 = jitter(rigidly_moved(sys, l, Eigen::Vector3d(0.002, -0.001, 0.003), Eigen::Vector3d(0.2, 0.3, -0.25)));
  sys.prepare(x0);
  const Eigen::VectorXd x1 = jitter(rigidly_moved(sys, l, Eigen::Vector3d(0.003, 0.0, 0.002), Eigen::Vector3d(0.3, 0.15, -0.1)));
  const auto energy = [&](const Eigen::VectorXd& v) { return sys.energy(v); };
  Eigen::VectorXd g1;
  sys.gradient(x1, g1);
  EXPECT_TRUE(derivatives_match(g1, fd_gradient(energy, x1, 1e-7), 1e-7));

  // The Hessian at the committed pose.
  const Eigen::VectorXd x2 = x1;
  sys.prepare(x2);
  Eigen::SparseMatrix<double> H;
  sys.hessian(x2, H);
  const Eigen::MatrixXd dense = Eigen::MatrixXd(Eigen::SparseMatrix<double>(H.selfadjointView<Eigen::Lower>()));
  const auto grad = [&](const Eigen::VectorXd& v) {
    Eigen::VectorXd g;
    sys.gradient(v, g);
    return g;
  };
  EXPECT_TRUE(derivatives_match(dense, fd_jacobian(grad, x2, 1e-7), 1e-6));
  // Committing did not move anything: same positions and energy.
  EXPECT_NEAR(sys.energy(x2), energy(x1), 1e-12 * std::abs(energy(x1)));
  // The pattern is the same at another point.
  const Eigen::Index nnz = H.nonZeros();
  sys.hessian(x0, H);
  EXPECT_EQ(H.nonZeros(), nnz);
}

INSTANTIATE_TEST_SUITE_P(Locks, CoreDerivatives, ::testing::Values(false, true),
                         [](const auto& param_info) { return param_info.param ? "some_locked" : "all_free"; });

TEST(CoreSystem, RigidMotionOfBodyAndCoreHasNoElasticForce) {
  Layer l = make_layer();
  l.core.mass = 0.0;
  l.core.force.setZero();
  l.core.torque.setZero();
  CoreSystem sys(*l.model, l.core);
  // Rotate and move the core; put every free vertex where the same rigid
  // motion takes it.
  Eigen::VectorXd x = Eigen::VectorXd::Zero(sys.num_dofs());
  const Eigen::Vector3d t(0.003, -0.001, 0.002), w(0.4, -0.3, 0.9);
  x.tail(6) << t, w;
  const Eigen::Matrix3d R = exp_so3(w);
  const Eigen::VectorXd u_core = sys.full_displacement(x);
  Eigen::Index k = 0;
  const TetMesh& mesh = l.model->mesh();
  std::vector<char> attached(static_cast<std::size_t>(mesh.V.rows()), 0);
  for (int v : l.core.attached) attached[static_cast<std::size_t>(v)] = 1;
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
    if (attached[static_cast<std::size_t>(v)]) continue;
    const Eigen::Vector3d X = mesh.V.row(v).transpose();
    x.segment<3>(k) = l.core.centre + t + R * (X - l.core.centre) - X;
    k += 3;
  }
  ASSERT_EQ(k, sys.num_vertex_dofs());
  Eigen::VectorXd g;
  const double e = sys.energy_gradient(x, g);
  EXPECT_LE(std::abs(e), 1e-14);
  EXPECT_LE(g.cwiseAbs().maxCoeff(), 1e-10);
  // The attached vertices followed the core exactly.
  for (int v : l.core.attached) {
    const Eigen::Vector3d X = mesh.V.row(v).transpose();
    EXPECT_LE((X + u_core.segment<3>(3 * v) - (l.core.centre + t + R * (X - l.core.centre))).norm(), 1e-15);
  }
}

TEST(CoreSystem, RefusesACoreWithoutAttachedVerticesOrAnythingToMove) {
  Layer l = make_layer();
  CoreSpec none = l.core;
  none.attached.clear();
  EXPECT_TRUE(palpa::test::throws_error([&] { CoreSystem s(*l.model, none); }, ErrorKind::Input, {"no attached vertices"}));
  CoreSpec bad = l.core;
  bad.attached.push_back(10000);
  EXPECT_TRUE(palpa::test::throws_error([&] { CoreSystem s(*l.model, bad); }, ErrorKind::Input, {"attached vertex 10000"}));
  CoreSpec all = l.core;
  all.attached.clear();
  for (Eigen::Index v = 0; v < l.model->num_vertices(); ++v) all.attached.push_back(static_cast<int>(v));
  all.locked = {true, true, true, true, true, true};
  EXPECT_TRUE(palpa::test::throws_error([&] { CoreSystem s(*l.model, all); }, ErrorKind::Input, {"every core DOF is locked"}));
}

}  // namespace
}  // namespace palpa::body
