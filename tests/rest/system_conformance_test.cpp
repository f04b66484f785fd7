// SPDX-License-Identifier: AGPL-3.0-or-later
// The System contract (solve/system.hpp), checked on every term palpa sums
// (solve/term.hpp: the tet elastic energy, its deviatoric and nodal-volume
// parts, a constant load, penalty contact sampled at vertices and over the
// skin), each alone over a DOF map with held
// DOFs and over one with a rigid core, and on every system palpa builds from
// them: a tet body with gravity and surface contact (tet::StaticSystem), its
// implicit-Euler step (tet::BackwardEulerSystem), the body on its rigid core
// (body::CoreSystem) and body, deformable support and two-pass contact
// together (rest::CoupledSystem). At a point away from the equilibrium, with
// the state committed there:
//  * the gradient is the energy's derivative and the Hessian the gradient's
//    (central differences along a random direction);
//  * the Hessian holds its lower triangle only, and its pattern stays the same
//    from call to call and point to point;
//  * energy and gradient evaluated from 8 threads at once equal the serial
//    values bit for bit (no scratch shared behind const).
#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "common/test_support.hpp"
#include "palpa/body/contact_term.hpp"
#include "palpa/contact/obstacle.hpp"
#include "palpa/geometry/boundary.hpp"
#include "palpa/material/models.hpp"
#include "palpa/solve/term_system.hpp"
#include "palpa/tet/elastic_term.hpp"
#include "palpa/tet/nodal_pressure.hpp"
#include "palpa/rest/coupled.hpp"
#include "palpa/rest/rest.hpp"
#include "palpa/sim3d/run.hpp"
#include "palpa/sim3d/scene.hpp"
#include "palpa/tet/system.hpp"
#include "rest/rest_fixtures.hpp"

namespace palpa::rest {
namespace {

using namespace test;

Eigen::VectorXd random_direction(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd d(n);
  for (Eigen::Index i = 0; i < n; ++i) d[i] = u(rng);
  return d;
}

// x: a point of finite energy near which the committed state holds; `step`
// the length [m] of the differences along a unit-size random direction.
void check_conformance(System& system, const Eigen::VectorXd& x, double step, const std::string& name) {
  SCOPED_TRACE(name);
  ASSERT_EQ(x.size(), system.num_dofs());
  system.prepare(x);
  const Eigen::VectorXd d = random_direction(x.size(), 7);

  // Derivatives.
  Eigen::VectorXd g;
  const double e = system.energy_gradient(x, g);
  // The same energy both ways (summed in another order: to rounding).
  const double e_alone = system.energy(x);
  EXPECT_NEAR(e, e_alone, 1e-12 * std::abs(e));
  Eigen::VectorXd g_alone;
  system.gradient(x, g_alone);
  EXPECT_EQ((g - g_alone).cwiseAbs().maxCoeff(), 0.0);
  const double fd_e = (system.energy(x + step * d) - system.energy(x - step * d)) / (2.0 * step);
  EXPECT_NEAR(g.dot(d), fd_e, 1e-5 * std::abs(fd_e) + 1e-12);
  Eigen::SparseMatrix<double> H;
  system.hessian(x, H);
  Eigen::VectorXd gp, gm;
  system.gradient(x + step * d, gp);
  system.gradient(x - step * d, gm);
  const Eigen::VectorXd fd_hd = (gp - gm) / (2.0 * step);
  const Eigen::SparseMatrix<double> full = H.selfadjointView<Eigen::Lower>();
  EXPECT_LE((full * d - fd_hd).norm(), 1e-5 * fd_hd.norm());  // a linear term's are both zero
  EXPECT_GT(g.norm(), 0.0);

  // The lower triangle, in one pattern.
  for (int k = 0; k < H.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(H, k); it; ++it) {
      ASSERT_GE(it.row(), it.col()) << "an entry above the diagonal";
    }
  }
  const std::vector<int> outer(H.outerIndexPtr(), H.outerIndexPtr() + H.outerSize() + 1);
  const std::vector<int> inner(H.innerIndexPtr(), H.innerIndexPtr() + H.nonZeros());
  const auto same_pattern = [&](const Eigen::SparseMatrix<double>& M) {
    return M.outerSize() == H.outerSize() && M.nonZeros() == H.nonZeros() &&
           std::equal(outer.begin(), outer.end(), M.outerIndexPtr()) &&
           std::equal(inner.begin(), inner.end(), M.innerIndexPtr());
  };
  system.hessian(x + step * d, H);  // reused: values only
  EXPECT_TRUE(same_pattern(H));
  Eigen::SparseMatrix<double> fresh;
  system.hessian(x - step * d, fresh);  // built anew
  EXPECT_TRUE(same_pattern(fresh));

  // Eight threads at once, each at its own point and at x.
  std::vector<Eigen::VectorXd> points;
  std::vector<double> serial_e;
  std::vector<Eigen::VectorXd> serial_g;
  for (int t = 0; t < 8; ++t) {
    points.push_back(x + (0.5 * step * t) * d);
    Eigen::VectorXd gt;
    serial_e.push_back(system.energy_gradient(points.back(), gt));
    serial_g.push_back(gt);
  }
  std::vector<double> threaded_e(8);
  std::vector<Eigen::VectorXd> threaded_g(8);
  std::vector<double> at_x(8);
  {
    std::vector<std::thread> workers;
    for (int t = 0; t < 8; ++t) {
      workers.emplace_back([&, t] {
        const auto i = static_cast<std::size_t>(t);
        for (int repeat = 0; repeat < 3; ++repeat) {
          at_x[i] = system.energy(x);
          threaded_e[i] = system.energy_gradient(points[i], threaded_g[i]);
        }
      });
    }
    for (std::thread& w : workers) w.join();
  }
  for (std::size_t t = 0; t < 8; ++t) {
    EXPECT_EQ(threaded_e[t], serial_e[t]) << "thread " << t;
    EXPECT_EQ((threaded_g[t] - serial_g[t]).cwiseAbs().maxCoeff(), 0.0) << "thread " << t;
    EXPECT_EQ(at_x[t], e_alone) << "thread " << t;
  }
}

// A system's true Hessian as its hessian(): the derivative checks need it
// where Newton gets the projected one.
class TrueHessian final : public System {
 public:
  explicit TrueHessian(TermSystem& s) : s_(&s) {}
  Eigen::Index num_dofs() const override { return s_->num_dofs(); }
  double energy(const Eigen::VectorXd& x) const override { return s_->energy(x); }
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override { s_->gradient(x, g); }
  double energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    return s_->energy_gradient(x, g);
  }
  void hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const override {
    s_->hessian(x, PsdProjection::None, H);
  }
  void prepare(const Eigen::VectorXd& x) override { s_->prepare(x); }

 private:
  TermSystem* s_;
};

// A 12 × 12 × 6 mm block of 3 × 3 × 2 cells (ν 0.45) whose bottom is held or
// carried by a rigid core, pressed 1.5 mm into a sphere of 10 mm radius.
struct TermFixture {
  tet::BoxMesh box = tet::make_box_mesh(Eigen::Vector3d(-6e-3, -6e-3, 0.0), Eigen::Vector3d(6e-3, 6e-3, 6e-3),
                                        Eigen::Vector3i(3, 3, 2));
  tet::ElasticModel model{box.mesh, {tet::BodyMaterial{std::make_shared<material::NeoHookean>(10e3, 0.45), 1000.0}}};
  contact::Obstacle sphere{sim3d::make_sphere(10e-3, 3), "sphere"};  // lowest point at its origin
  TermFixture() { sphere.set_pose({Eigen::Matrix3d::Identity(), Eigen::Vector3d(1e-3, -0.5e-3, 4.5e-3)}); }

  DofMap held() const {
    std::vector<char> fixed(static_cast<std::size_t>(model.num_dofs()), 0);
    for (int v : box.vertex_sets.at("bottom")) fixed[static_cast<std::size_t>(3 * v + 2)] = 1;
    fixed[static_cast<std::size_t>(3 * box.vertex_sets.at("bottom")[0])] = 1;
    fixed[static_cast<std::size_t>(3 * box.vertex_sets.at("bottom")[0] + 1)] = 1;
    return DofMap(model.mesh().V, fixed);
  }
  DofMap on_core() const {
    RigidCore core{box.vertex_sets.at("bottom"), Eigen::Vector3d(1e-3, 0.0, -2e-3), {false, true, false, true, false, false}};
    return DofMap(model.mesh().V, std::vector<char>(static_cast<std::size_t>(model.num_dofs()), 0), core);
  }
};

// Each term alone: x a random displacement of up to 0.1 mm, the core moved
// 0.02 mm and turned 0.02 rad about each free axis.
void check_term(Term& term, const TermFixture& f, bool core, const std::string& name) {
  TermSystem system(core ? f.on_core() : f.held(), PsdProjection::None);
  system.add_term(&term);
  auto rng = palpa::test::make_rng(31);
  std::uniform_real_distribution<double> du(-1e-4, 1e-4);
  Eigen::VectorXd x(system.num_dofs());
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = du(rng);
  const std::vector<int>& pose = system.dof_map().core_dofs();
  for (std::size_t k = 0; k < pose.size(); ++k) {
    x[system.dof_map().num_vertex_dofs() + static_cast<Eigen::Index>(k)] = pose[k] < 3 ? 2e-5 : 0.02;
  }
  check_conformance(system, x, 1e-8, name + (core ? " on a rigid core" : " with held DOFs"));
}

TEST(SystemConformance, EveryTermAloneWithHeldDofsAndOnARigidCore) {
  const TermFixture f;
  for (const bool core : {false, true}) {
    tet::ElasticTerm elastic(f.model);
    check_term(elastic, f, core, "tet::ElasticTerm");
    tet::DeviatoricTerm deviatoric(f.model);
    check_term(deviatoric, f, core, "tet::DeviatoricTerm");
    tet::NodalVolumeTerm nodal(f.model);
    check_term(nodal, f, core, "tet::NodalVolumeTerm");
    // Stabilized, with a material per tet (a firmer, nearly incompressible
    // one on every other tet): the nodal volume change mixes both.
    Eigen::VectorXi per_tet(f.model.num_elements());
    for (Eigen::Index e = 0; e < per_tet.size(); ++e) per_tet[e] = static_cast<int>(e % 2);
    tet::ElasticModel stabilized(f.box.mesh,
                                 {f.model.materials()[0],
                                  tet::BodyMaterial{std::make_shared<material::NeoHookean>(30e3, 0.49), 1000.0}},
                                 per_tet);
    stabilized.set_element(tet::TetElement::NodalPressure, 0.3);
    tet::DeviatoricTerm stabilized_deviatoric(stabilized);
    check_term(stabilized_deviatoric, f, core, "tet::DeviatoricTerm (β 0.3)");
    tet::NodalVolumeTerm stabilized_nodal(stabilized);
    check_term(stabilized_nodal, f, core, "tet::NodalVolumeTerm (β 0.3)");
    LinearTerm gravity(f.model.gravity_gradient(Eigen::Vector3d(0.3, -0.2, -9.81)));
    check_term(gravity, f, core, "LinearTerm");
    const Eigen::MatrixX3i skin = geometry::boundary_of(f.model.mesh()).faces;
    body::ContactTerm vertices(f.sphere, f.model.mesh().V, skin, 50.0);
    check_term(vertices, f, core, "body::ContactTerm (vertices)");
    EXPECT_GT(vertices.potential().size(), 2u);
    body::ContactTerm surface(f.sphere, f.model.mesh().V, skin, 2e6, body::ContactSampling::Surface, 2);
    check_term(surface, f, core, "body::ContactTerm (surface)");
    EXPECT_GT(surface.potential().size(), 8u);
  }
}

TEST(SystemConformance, TetBodyWithGravityAndSurfaceContactAndItsImplicitStep) {
  palpa::test::ScratchDir dir;
  const auto file = dir.write("scene.json", R"({
    "palpa_scene": 1,
    "body": {"box": {"size": ["30 mm", "30 mm", "10 mm"], "cells": [10, 10, 2]},
             "materials": [{"material": {"model": "neo-hookean", "parameters": {"E": "10 kPa", "nu": 0.4}},
                            "density": "1000 kg/m^3"}],
             "fixed": [{"set": "bottom"}]},
    "gravity": ["0 m/s^2", "0 m/s^2", "-9.81 m/s^2"],
    "obstacles": [{"name": "punch", "shape": {"sphere": {"radius": "8 mm", "level": 2}},
                   "path": {"direction": [0, 0, -1], "depth": "1 mm"}}],
    "steps": 1,
    "contact": {"max_penetration": "0.05 mm", "sampling": "surface"}
  })");
  const sim3d::Scene scene = sim3d::read_scene(file);  // the simulation keeps a reference
  sim3d::Simulation sim(scene);
  sim.solve_step(1);
  ASSERT_GT(sim.contact_term(0).potential().size(), 4u);
  tet::StaticSystem& statics = sim.system();
  const Eigen::VectorXd x = sim.state() + 1e-6 * random_direction(sim.state().size(), 3);
  TrueHessian exact(statics);
  check_conformance(exact, x, 1e-8, "tet::StaticSystem");

  tet::BackwardEulerSystem step(statics, 5e-3, {20.0, 1e-3}, PsdProjection::None);
  step.begin_step(sim.state(), Eigen::VectorXd::Zero(sim.state().size()));
  check_conformance(step, x, 1e-8, "tet::BackwardEulerSystem");
}

TEST(SystemConformance, BodyOnItsRigidCore) {
  RestOptions o;
  o.core.locked = {true, true, false, false, false, true};  // sinks and tilts
  o.core.mass = 0.2;
  o.core.torque = Eigen::Vector3d(1e-3, -2e-3, 0.0);
  RestSimulation sim(hanging_block(4, 0.3, 3e-4), square_slab(0.06, 0.012, 8), o);
  sim.solve();
  ASSERT_GT(sim.contact_term().potential().size(), 8u);
  body::CoreSystem& system = sim.system();  // the true Hessian in rest
  const Eigen::VectorXd x = sim.dofs() + 2e-6 * random_direction(sim.dofs().size(), 5);
  check_conformance(system, x, 1e-8, "body::CoreSystem");
}

TEST(SystemConformance, BodyDeformableSupportAndTwoPassContact) {
  RestOptions o;
  o.core.locked = {true, true, false, false, false, true};
  o.core.mass = 0.2;
  o.core.torque = Eigen::Vector3d(1e-3, -2e-3, 0.0);
  o.deformable_support = DeformableSupport{std::make_shared<material::NeoHookean>(30e3, 0.3), 8e-3, 1e-4};
  RestSimulation sim(hanging_block(4, 0.3, 3e-4), square_slab(0.06, 0.012, 8), o);
  sim.solve();
  ASSERT_TRUE(sim.deformable_support());
  CoupledSystem& system = *sim.coupled_system();
  const Eigen::VectorXd y = sim.coupled_dofs() + 2e-6 * random_direction(system.num_dofs(), 11);
  check_conformance(system, y, 1e-8, "rest::CoupledSystem");
}

}  // namespace
}  // namespace palpa::rest
