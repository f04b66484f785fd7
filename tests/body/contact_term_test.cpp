// SPDX-License-Identifier: AGPL-3.0-or-later
// The contact term inside a tet system: gradient and Hessian against
// finite differences with the anchors on a face interior, an edge interior and
// a vertex of the obstacle (Appendix A's three cases), and the forces balance.
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "common/finite_difference.hpp"
#include "common/system_derivatives.hpp"
#include "common/test_support.hpp"
#include "palpa/geometry/boundary.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/material/models.hpp"
#include "palpa/body/area_updates.hpp"
#include "palpa/body/contact_term.hpp"
#include "palpa/tet/system.hpp"
#include "palpa/tet/mesh.hpp"

namespace palpa::body {
namespace {

using palpa::test::dense_hessian;
using palpa::test::derivatives_match;
using palpa::test::fd_hessian;
using palpa::test::fd_gradient;

constexpr double kA = 0.01;  // the notch's size [m]

// A 2a cube with the corner cube [0, a]³ cut away: its notch has reflex edges
// and a reflex vertex at (a, a, a), so points inside the solid can have a
// face, an edge or a vertex as their closest feature.
SurfaceMesh notched_cube() {
  const tet::BoxMesh box = tet::make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(2 * kA),
                                              Eigen::Vector3i(2, 2, 2));
  TetMesh m;
  m.V = box.mesh.V;
  std::vector<Eigen::Index> keep;
  for (Eigen::Index t = 0; t < box.mesh.T.rows(); ++t) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int a = 0; a < 4; ++a) c += box.mesh.V.row(box.mesh.T(t, a)).transpose() / 4.0;
    if (!(c.array() < kA).all()) keep.push_back(t);
  }
  m.T.resize(static_cast<Eigen::Index>(keep.size()), 4);
  for (std::size_t i = 0; i < keep.size(); ++i) m.T.row(static_cast<Eigen::Index>(i)) = box.mesh.T.row(keep[i]);
  const geometry::Boundary b = geometry::boundary_of(m);
  // Compact: only the boundary's vertices.
  std::vector<int> to_new(static_cast<std::size_t>(m.V.rows()), -1);
  SurfaceMesh s;
  s.V.resize(static_cast<Eigen::Index>(b.vertices.size()), 3);
  for (std::size_t i = 0; i < b.vertices.size(); ++i) {
    to_new[static_cast<std::size_t>(b.vertices[i])] = static_cast<int>(i);
    s.V.row(static_cast<Eigen::Index>(i)) = m.V.row(b.vertices[i]);
  }
  s.F.resize(b.faces.rows(), 3);
  for (Eigen::Index f = 0; f < b.faces.rows(); ++f) {
    for (int c = 0; c < 3; ++c) s.F(f, c) = to_new[static_cast<std::size_t>(b.faces(f, c))];
  }
  return s;
}

struct Case {
  const char* name;
  Eigen::Vector3d corner;  // where the body's lowest corner sits, obstacle frame [m]
  contact::Feature feature;
};

class ContactTermRegions : public ::testing::TestWithParam<Case> {};

TEST_P(ContactTermRegions, SystemDerivativesMatchFiniteDifferences) {
  const Case c = GetParam();
  // A 1 mm body cube, all of it inside the notched obstacle.
  const tet::BoxMesh box = tet::make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(1e-3),
                                              Eigen::Vector3i(1, 1, 1));
  const tet::ElasticModel model(box.mesh, {tet::BodyMaterial{std::make_shared<material::NeoHookean>(5e3, 0.3), 1000.0}});
  contact::Obstacle obstacle(notched_cube(), "notch");
  obstacle.set_pose({Eigen::Matrix3d::Identity(), -c.corner});  // obstacle frame origin at −corner
  ContactTerm term(obstacle, box.mesh.V, geometry::boundary_of(box.mesh).faces, 2e3);
  tet::StaticSystem sys(model, std::vector<char>(static_cast<std::size_t>(model.num_dofs()), 0), PsdProjection::None);
  sys.add_term(&term);
  sys.set_gravity(Eigen::Vector3d(0.0, 0.0, -9.81));
  auto rng = palpa::test::make_rng(21);
  std::uniform_real_distribution<double> du(-5e-5, 5e-5);
  Eigen::VectorXd x(sys.num_dofs());
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = du(rng);
  sys.prepare(x);
  ASSERT_EQ(term.potential().size(), 8u) << c.name;
  for (const contact::SampleContact& k : term.potential().contacts()) EXPECT_EQ(k.closest.feature, c.feature) << c.name;

  Eigen::VectorXd g;
  const double e = sys.energy_gradient(x, g);
  EXPECT_NEAR(e, sys.energy(x), 1e-12 * std::abs(e));
  EXPECT_TRUE(derivatives_match(g, fd_gradient([&](const Eigen::VectorXd& v) { return sys.energy(v); }, x, 1e-7), 1e-7))
      << c.name;
  EXPECT_TRUE(derivatives_match(dense_hessian(sys, x), fd_hessian(sys, x, 1e-7), 1e-6)) << c.name;

  // Forces: the body's contact forces and the obstacle's reaction cancel.
  const Eigen::VectorXd p = sys.positions(sys.full_displacement(x));
  const Eigen::Matrix3Xd f = term.vertex_forces(p);
  const contact::Wrench w = term.obstacle_wrench(p, Eigen::Vector3d::Zero());
  EXPECT_LE((f.rowwise().sum() + w.force).norm(), 1e-12 * w.force.norm());
  EXPECT_GT(w.force.norm(), 0.0);
}

TEST(ContactTermSurface, SystemDerivativesMatchFiniteDifferencesAndForcesBalance) {
  // The same 1 mm cube with its springs on 2 × 2 points of every skin
  // triangle (k a pressure per depth), its upper part inside the obstacle
  // above the notch's ceiling, so that its side triangles touch in part; the
  // Hessian couples each triangle's corners.
  const tet::BoxMesh box = tet::make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(1e-3),
                                              Eigen::Vector3i(2, 2, 2));
  const tet::ElasticModel model(box.mesh, {tet::BodyMaterial{std::make_shared<material::NeoHookean>(5e3, 0.3), 1000.0}});
  contact::Obstacle obstacle(notched_cube(), "notch");
  obstacle.set_pose({Eigen::Matrix3d::Identity(), -Eigen::Vector3d(0.3 * kA, 0.4 * kA, kA - 4e-4)});
  ContactTerm term(obstacle, box.mesh.V, geometry::boundary_of(box.mesh).faces, 4e6, ContactSampling::Surface, 2);
  EXPECT_FALSE(term.vertex_pairs().empty());
  tet::StaticSystem sys(model, std::vector<char>(static_cast<std::size_t>(model.num_dofs()), 0), PsdProjection::None);
  sys.add_term(&term);
  sys.set_gravity(Eigen::Vector3d(0.0, 0.0, -9.81));
  auto rng = palpa::test::make_rng(22);
  std::uniform_real_distribution<double> du(-5e-5, 5e-5);
  Eigen::VectorXd x(sys.num_dofs());
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = du(rng);
  sys.prepare(x);
  ASSERT_GT(term.potential().size(), 8u);
  ASSERT_LT(term.potential().size(), term.potential().samples().size());
  Eigen::VectorXd g;
  const double e = sys.energy_gradient(x, g);
  EXPECT_NEAR(e, sys.energy(x), 1e-12 * std::abs(e));
  EXPECT_TRUE(derivatives_match(g, fd_gradient([&](const Eigen::VectorXd& v) { return sys.energy(v); }, x, 1e-7), 1e-7));
  EXPECT_TRUE(derivatives_match(dense_hessian(sys, x), fd_hessian(sys, x, 1e-7), 1e-6));
  // The skin's nodal forces and the obstacle's reaction cancel, and each
  // vertex's pressure is its force over its share of the skin where it is
  // now.
  const Eigen::VectorXd p = sys.positions(sys.full_displacement(x));
  const Eigen::Matrix3Xd f = term.vertex_forces(p);
  const contact::Wrench w = term.obstacle_wrench(p, Eigen::Vector3d::Zero());
  EXPECT_GT(w.force.norm(), 0.0);
  EXPECT_LE((f.rowwise().sum() + w.force).norm(), 1e-12 * w.force.norm());
  const Eigen::VectorXd pressure = term.pressures(p);
  const Eigen::MatrixX3d deformed = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(p.data(), p.size() / 3, 3);
  const Eigen::VectorXd area = geometry::vertex_areas(deformed, term.faces());
  EXPECT_GT((area - geometry::vertex_areas(box.mesh.V, term.faces())).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_NEAR(pressure.dot(area), f.colwise().norm().sum(), 1e-12 * f.colwise().norm().sum());
}

TEST(AreaUpdates, FollowTheContactSetAtMostThreeTimesPerStiffness) {
  // A 1 mm cube on the notched cube's flat top, its bottom alternately all in
  // contact and in contact on one side only: every commit moves the spring
  // areas, as a rim vertex that touches and lets go does. The schedule
  // follows three times, then holds until the stiffness changes.
  const tet::BoxMesh box = tet::make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(1e-3),
                                              Eigen::Vector3i(2, 2, 2));
  const tet::ElasticModel model(box.mesh, {tet::BodyMaterial{std::make_shared<material::NeoHookean>(5e3, 0.3), 1000.0}});
  contact::Obstacle obstacle(notched_cube(), "notch");
  obstacle.set_pose({Eigen::Matrix3d::Identity(), -Eigen::Vector3d(kA, kA, 2 * kA)});
  auto term = std::make_unique<ContactTerm>(obstacle, box.mesh.V, geometry::boundary_of(box.mesh).faces, 100.0);
  tet::StaticSystem sys(model, std::vector<char>(static_cast<std::size_t>(model.num_dofs()), 0), PsdProjection::None);
  sys.add_term(term.get());
  Eigen::VectorXd all = Eigen::VectorXd::Zero(sys.num_dofs()), side = all;
  for (Eigen::Index v = 0; v < box.mesh.V.rows(); ++v) {
    all[3 * v + 2] = -1e-4;
    if (box.mesh.V(v, 0) < 0.6e-3) side[3 * v + 2] = -1e-4;
  }
  const std::vector<std::unique_ptr<ContactTerm>> terms = [&] {
    std::vector<std::unique_ptr<ContactTerm>> t;
    t.push_back(std::move(term));
    return t;
  }();
  AreaUpdates updates;
  sys.prepare(all);
  const std::size_t bottom = terms[0]->potential().size();
  EXPECT_TRUE(updates.update(terms));
  EXPECT_FALSE(updates.update(terms));  // the same contacts: nothing moved
  sys.prepare(side);
  ASSERT_LT(terms[0]->potential().size(), bottom);
  EXPECT_TRUE(updates.update(terms));
  sys.prepare(all);
  EXPECT_TRUE(updates.update(terms));
  sys.prepare(side);
  const std::vector<double> held = terms[0]->spring_area();
  EXPECT_FALSE(updates.update(terms));  // the fourth change is not followed
  EXPECT_EQ(terms[0]->spring_area(), held);
  updates.restart();
  EXPECT_TRUE(updates.update(terms));
  EXPECT_NE(terms[0]->spring_area(), held);
}

INSTANTIATE_TEST_SUITE_P(
    Voronoi, ContactTermRegions,
    ::testing::Values(Case{"face", Eigen::Vector3d(0.3 * kA, 0.4 * kA, kA + 3e-4), contact::Feature::Face},
                      Case{"edge", Eigen::Vector3d(kA + 2e-4, kA + 3e-4, 0.5 * kA), contact::Feature::Edge},
                      Case{"vertex", Eigen::Vector3d(kA + 2e-4, kA + 3e-4, kA + 2.5e-4), contact::Feature::Vertex}),
    [](const auto& param_info) { return std::string(param_info.param.name); });

}  // namespace
}  // namespace palpa::body
