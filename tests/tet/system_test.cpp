// SPDX-License-Identifier: AGPL-3.0-or-later
// The static and backward-Euler systems of a tet body: derivatives against
// finite differences (with fixed DOFs, gravity and a vertex term), the patch
// test, rigid motions, reactions, and dynamics settling to the static answer.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <memory>
#include <random>

#include "common/finite_difference.hpp"
#include "common/system_derivatives.hpp"
#include "common/test_support.hpp"
#include "palpa/geometry/boundary.hpp"
#include "palpa/material/kinematics.hpp"
#include "palpa/material/models.hpp"
#include "palpa/solve/newton.hpp"
#include "palpa/tet/mesh.hpp"
#include "palpa/tet/system.hpp"

namespace palpa::tet {
namespace {

using palpa::test::dense_hessian;
using palpa::test::derivatives_match;
using palpa::test::fd_hessian;
using palpa::test::fd_gradient;

constexpr double kE = 10e3;   // [Pa]
constexpr double kNu = 0.4;

ElasticModel block_model(const Eigen::Vector3i& cells, const Eigen::Vector3d& size, double density = 1000.0) {
  BoxMesh box = make_box_mesh(Eigen::Vector3d::Zero(), size, cells);
  return ElasticModel(box.mesh, {BodyMaterial{std::make_shared<material::NeoHookean>(kE, kNu), density}});
}

std::vector<char> fix_vertices(Eigen::Index n, const std::vector<int>& vertices, std::array<bool, 3> comps = {true, true, true}) {
  std::vector<char> fixed(static_cast<std::size_t>(3 * n), 0);
  for (int v : vertices) {
    for (int c = 0; c < 3; ++c) {
      if (comps[static_cast<std::size_t>(c)]) fixed[static_cast<std::size_t>(3 * v + c)] = 1;
    }
  }
  return fixed;
}

// A test energy: ½ k |x_v − p_v|² on some vertices, plus a quartic part so its
// Hessian depends on x.
class Springs final : public Term {
 public:
  std::vector<std::pair<int, Eigen::Vector3d>> springs;
  double k = 50.0;
  double energy(const VertexState& s) const override {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(s.p.size());
    return add_gradient(s, g);
  }
  double add_gradient(const VertexState& state, Eigen::VectorXd& g) const override {
    const Eigen::VectorXd& x = state.p;
    double e = 0.0;
    for (const auto& [v, p] : springs) {
      const Eigen::Vector3d d = x.segment<3>(3 * v) - p;
      const double s = d.squaredNorm();
      e += 0.5 * k * s + 1e5 * k * s * s;
      g.segment<3>(3 * v) += k * d + 4e5 * k * s * d;
    }
    return e;
  }
  void add_blocks(const VertexState& s, PsdProjection, std::vector<VertexBlock>& blocks) const override {
    const Eigen::VectorXd& x = s.p;
    for (const auto& [v, p] : springs) {
      const Eigen::Vector3d d = x.segment<3>(3 * v) - p;
      blocks.push_back({v, v, k * Eigen::Matrix3d::Identity() + 4e5 * k * (d.squaredNorm() * Eigen::Matrix3d::Identity() + 2.0 * d * d.transpose())});
    }
  }
};

TEST(StaticSystem, GradientAndHessianMatchFiniteDifferences) {
  const ElasticModel model = block_model(Eigen::Vector3i(2, 2, 2), Eigen::Vector3d(0.02, 0.02, 0.01));
  BoxMesh box = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.02, 0.01), Eigen::Vector3i(2, 2, 2));
  StaticSystem sys(model, fix_vertices(model.num_vertices(), box.vertex_sets.at("bottom"), {false, false, true}),
                   PsdProjection::None);
  sys.set_gravity(Eigen::Vector3d(0.0, 0.0, -9.81));
  Eigen::VectorXd f = Eigen::VectorXd::Zero(model.num_dofs());
  f[3 * 20] = 0.01;
  sys.set_external_forces(f);
  Springs springs;
  springs.springs = {{26, Eigen::Vector3d(0.021, 0.019, 0.0105)}, {13, Eigen::Vector3d(0.01, 0.01, 0.004)}};
  sys.add_term(&springs);
  auto rng = palpa::test::make_rng(3);
  std::uniform_real_distribution<double> du(-5e-4, 5e-4);
  Eigen::VectorXd x(sys.num_dofs());
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = du(rng);
  Eigen::VectorXd g;
  const double e = sys.energy_gradient(x, g);
  EXPECT_DOUBLE_EQ(e, sys.energy(x));
  EXPECT_TRUE(derivatives_match(g, fd_gradient([&](const Eigen::VectorXd& v) { return sys.energy(v); }, x, 1e-6), 1e-7));
  EXPECT_TRUE(derivatives_match(dense_hessian(sys, x), fd_hessian(sys, x, 1e-6), 1e-6));
  // The pattern stays: a second call writes the same structure.
  Eigen::SparseMatrix<double> H;
  sys.hessian(x, H);
  const Eigen::Index nnz = H.nonZeros();
  sys.hessian(0.5 * x, H);
  EXPECT_EQ(H.nonZeros(), nnz);
}

// A nonlinear spring between two vertices of one tet: its Hessian couples
// them (a vertex pair), E = ¼ c (|x_a − x_b|² − L²)².
class PairSpring final : public Term {
 public:
  int a = 0, b = 0;
  double c = 1e9, L = 0.0;
  double energy(const VertexState& st) const override {
    const double s = (st.p.segment<3>(3 * a) - st.p.segment<3>(3 * b)).squaredNorm() - L * L;
    return 0.25 * c * s * s;
  }
  double add_gradient(const VertexState& st, Eigen::VectorXd& g) const override {
    const Eigen::Vector3d d = st.p.segment<3>(3 * a) - st.p.segment<3>(3 * b);
    const double s = d.squaredNorm() - L * L;
    g.segment<3>(3 * a) += c * s * d;
    g.segment<3>(3 * b) -= c * s * d;
    return energy(st);
  }
  void add_blocks(const VertexState& st, PsdProjection, std::vector<VertexBlock>& blocks) const override {
    const Eigen::VectorXd& x = st.p;
    const Eigen::Vector3d d = x.segment<3>(3 * a) - x.segment<3>(3 * b);
    const Eigen::Matrix3d K = c * ((d.squaredNorm() - L * L) * Eigen::Matrix3d::Identity() + 2.0 * d * d.transpose());
    blocks.push_back({a, a, K});
    blocks.push_back({b, b, K});
    blocks.push_back({a, b, -K});
    blocks.push_back({b, a, -K});
  }
  std::vector<std::array<int, 2>> vertex_pairs() const override { return {{a, b}}; }
};

TEST(StaticSystem, VertexPairBlocksOfATermMatchFiniteDifferences) {
  const ElasticModel model = block_model(Eigen::Vector3i(2, 2, 2), Eigen::Vector3d(0.02, 0.02, 0.01));
  BoxMesh box = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.02, 0.01), Eigen::Vector3i(2, 2, 2));
  StaticSystem sys(model, fix_vertices(model.num_vertices(), box.vertex_sets.at("bottom"), {true, true, true}),
                   PsdProjection::None);
  PairSpring spring;
  spring.a = model.mesh().T(5, 1);
  spring.b = model.mesh().T(5, 3);
  spring.L = 0.5 * (model.mesh().V.row(spring.a) - model.mesh().V.row(spring.b)).norm();
  sys.add_term(&spring);
  auto rng = palpa::test::make_rng(4);
  std::uniform_real_distribution<double> du(-5e-4, 5e-4);
  Eigen::VectorXd x(sys.num_dofs());
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = du(rng);
  EXPECT_TRUE(derivatives_match(dense_hessian(sys, x), fd_hessian(sys, x, 1e-7), 1e-6));
  // A pair of free vertices that shares no tet (two opposite top corners)
  // grows the pattern: its blocks land, and the Hessian stays exact.
  PairSpring far;
  for (Eigen::Index v = 0; v < model.num_vertices(); ++v) {
    const Eigen::RowVector3d p = model.mesh().V.row(v);
    if (p.isApprox(Eigen::RowVector3d(0.0, 0.0, 0.01))) far.a = static_cast<int>(v);
    if (p.isApprox(Eigen::RowVector3d(0.02, 0.02, 0.01))) far.b = static_cast<int>(v);
  }
  ASSERT_NE(far.a, far.b);
  const Eigen::Index before = sys.pattern().nonZeros();
  sys.add_term(&far);
  EXPECT_GT(sys.pattern().nonZeros(), before);
  far.L = spring.L;
  EXPECT_TRUE(derivatives_match(dense_hessian(sys, x), fd_hessian(sys, x, 1e-7), 1e-6));
}

TEST(StaticSystem, PatchTestReproducesAHomogeneousDeformationExactly) {
  const Eigen::Vector3d size(0.02, 0.015, 0.01);
  BoxMesh box = make_box_mesh(Eigen::Vector3d::Zero(), size, Eigen::Vector3i(4, 3, 3));
  const ElasticModel model(box.mesh, {BodyMaterial{std::make_shared<material::NeoHookean>(kE, kNu), 0.0}});
  // Every boundary vertex follows x = F X + c; the interior must follow too.
  const geometry::Boundary b = geometry::boundary_of(box.mesh);
  StaticSystem sys(model, fix_vertices(model.num_vertices(), b.vertices));
  material::Mat3 F;
  F << 1.12, 0.05, 0.0, -0.03, 0.93, 0.02, 0.01, 0.04, 1.05;
  const Eigen::Vector3d c(1e-3, -2e-3, 5e-4);
  Eigen::VectorXd u_exact(model.num_dofs());
  for (Eigen::Index v = 0; v < model.num_vertices(); ++v) {
    const Eigen::Vector3d X = box.mesh.V.row(v).transpose();
    u_exact.segment<3>(3 * v) = F * X + c - X;
  }
  sys.set_prescribed(u_exact);
  // Start from the answer disturbed by a tenth of a cell.
  Eigen::VectorXd x = sys.free_part(u_exact);
  auto rng = palpa::test::make_rng(8);
  std::uniform_real_distribution<double> du(-5e-4, 5e-4);
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += du(rng);
  NewtonOptions opt;
  opt.gradient_rel_tol = 1e-12;
  NewtonSolver newton(opt);
  const NewtonResult r = newton.solve(sys, x);
  ASSERT_TRUE(r.converged()) << r.message;
  const Eigen::VectorXd u = sys.full_displacement(x);
  EXPECT_LE((u - u_exact).cwiseAbs().maxCoeff(), 1e-10 * size.maxCoeff());
  // The energy is the volume times Ψ(F).
  material::Stress3 s;
  material::stress(*model.materials()[0].material, F, material::EvalOrder::Energy, material::PsdProjection::None, s);
  EXPECT_NEAR(model.elastic_energy(u), s.psi * size.prod(), 1e-9 * s.psi * size.prod());
  // Reactions balance: they sum to zero (no body force).
  const Eigen::VectorXd react = sys.reactions(x);
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (Eigen::Index v = 0; v < model.num_vertices(); ++v) total += react.segment<3>(3 * v);
  EXPECT_LE(total.norm(), 1e-9 * react.cwiseAbs().maxCoeff());
}

TEST(StaticSystem, RigidMotionOfTheWholeBodyHasNoEnergyAndNoForce) {
  const ElasticModel model = block_model(Eigen::Vector3i(3, 2, 2), Eigen::Vector3d(0.03, 0.02, 0.02));
  StaticSystem sys(model, std::vector<char>(static_cast<std::size_t>(model.num_dofs()), 0));
  const Eigen::Matrix3d R = Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, 1.0, -0.2).normalized()).toRotationMatrix();
  Eigen::VectorXd u(model.num_dofs());
  for (Eigen::Index v = 0; v < model.num_vertices(); ++v) {
    const Eigen::Vector3d X = model.mesh().V.row(v).transpose();
    u.segment<3>(3 * v) = R * X + Eigen::Vector3d(0.1, 0.2, -0.3) - X;
  }
  Eigen::VectorXd g;
  const double e = sys.energy_gradient(sys.free_part(u), g);
  const double mu = kE / (2.0 * (1.0 + kNu));
  EXPECT_LE(std::abs(e), 1e-12 * mu * 0.03 * 0.02 * 0.02);
  EXPECT_LE(g.cwiseAbs().maxCoeff(), 1e-9 * mu * 0.01 * 0.01 * 0.01);
}

TEST(StaticSystem, MassesAndGravityAddUp) {
  const ElasticModel model = block_model(Eigen::Vector3i(2, 3, 2), Eigen::Vector3d(0.02, 0.03, 0.01), 1100.0);
  const double m = 1100.0 * 0.02 * 0.03 * 0.01;
  EXPECT_NEAR(model.total_mass(), m, 1e-12 * m);
  const Eigen::SparseMatrix<double> M = model.consistent_mass();
  const Eigen::MatrixXd full = Eigen::MatrixXd(Eigen::SparseMatrix<double>(M.selfadjointView<Eigen::Lower>()));
  EXPECT_NEAR(full.sum(), 3.0 * m, 1e-12 * m);
  // Row sums of the consistent mass are the lumped masses.
  const Eigen::VectorXd rows = full.rowwise().sum();
  for (Eigen::Index v = 0; v < model.num_vertices(); ++v) {
    EXPECT_NEAR(rows[3 * v], model.lumped_mass()[v], 1e-12 * m);
  }
  const Eigen::VectorXd gg = model.gravity_gradient(Eigen::Vector3d(0.0, 0.0, -9.81));
  double fz = 0.0;
  for (Eigen::Index v = 0; v < model.num_vertices(); ++v) fz += gg[3 * v + 2];
  EXPECT_NEAR(fz, 9.81 * m, 1e-12 * m);
}

TEST(BackwardEuler, SettlesToTheStaticEquilibrium) {
  // A cantilever (fixed at x = 0) sagging under gravity: damped backward Euler
  // from rest must come to rest at the static answer.
  BoxMesh box = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.06, 0.01, 0.01), Eigen::Vector3i(6, 1, 1));
  const ElasticModel model(box.mesh, {BodyMaterial{std::make_shared<material::NeoHookean>(50e3, 0.3), 1000.0}});
  StaticSystem sys(model, fix_vertices(model.num_vertices(), box.vertex_sets.at("xmin")));
  sys.set_gravity(Eigen::Vector3d(0.0, 0.0, -9.81));
  NewtonOptions opt;
  opt.gradient_rel_tol = 1e-10;
  NewtonSolver newton(opt);
  Eigen::VectorXd x_static = Eigen::VectorXd::Zero(sys.num_dofs());
  ASSERT_TRUE(newton.solve(sys, x_static).converged());
  const double tip = sys.full_displacement(x_static)[3 * box.vertex_sets.at("xmax")[0] + 2];
  EXPECT_LT(tip, -1e-4);

  BackwardEulerSystem dyn(sys, 5e-3, {.mass = 20.0, .stiffness = 1e-3});
  Eigen::VectorXd x = Eigen::VectorXd::Zero(sys.num_dofs());
  Eigen::VectorXd v = Eigen::VectorXd::Zero(sys.num_dofs());
  // Steps near rest start close to their answer: an absolute tolerance (a
  // billionth of the nodal weights) instead of one relative to that start.
  NewtonOptions step_opt;
  step_opt.gradient_abs_tol = 1e-9 * model.total_mass() * 9.81 / static_cast<double>(model.num_vertices());
  step_opt.gradient_accept_tol = 10.0 * step_opt.gradient_abs_tol;
  NewtonSolver stepper(step_opt);
  double min_tip = 0.0;
  for (int step = 0; step < 400; ++step) {
    dyn.begin_step(x, v);
    Eigen::VectorXd next = x;
    ASSERT_TRUE(stepper.solve(dyn, next).converged()) << "step " << step;
    v = (next - x) / dyn.step();
    x = next;
    min_tip = std::min(min_tip, sys.full_displacement(x)[3 * box.vertex_sets.at("xmax")[0] + 2]);
  }
  // It overshoots on the way (inertia), then settles.
  EXPECT_LT(min_tip, 1.05 * tip);
  EXPECT_LE((x - x_static).cwiseAbs().maxCoeff(), 1e-3 * std::abs(tip));
  EXPECT_LE(v.cwiseAbs().maxCoeff(), 1e-3 * std::abs(tip) / dyn.step());
}

}  // namespace
}  // namespace palpa::tet
