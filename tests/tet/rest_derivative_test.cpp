// SPDX-License-Identifier: AGPL-3.0-or-later
// Derivatives with respect to the rest positions (shape optimization by the
// adjoint method): the element kernel tet_rest_gradient_product and the
// assembled ElasticModel::rest_gradient_product against central differences
// at fixed deformed positions, and ElasticModel::set_rest_positions (geometry
// and masses as if built from the moved mesh; refused updates change nothing).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "common/finite_difference.hpp"
#include "common/test_support.hpp"
#include "palpa/core/error.hpp"
#include "palpa/material/models.hpp"
#include "palpa/tet/element.hpp"
#include "palpa/tet/mesh.hpp"
#include "palpa/tet/model.hpp"

namespace palpa::tet {
namespace {

using palpa::test::derivatives_match;
using palpa::test::fd_gradient;

constexpr double kEdge = 2e-3;       // element edge length [m]
constexpr double kYoung = 12e3;       // Young's modulus [Pa]
constexpr double kPoisson = 0.45;
// Finite-difference step relative to the size of the tet (or mesh cell), and
// the relative tolerance of the comparison: max |analytic − numeric| ≤
// 1e-6 · max |analytic| (derivatives_match, which also refuses a zero
// derivative). With the helper's Richardson step the truncation error is
// O(h⁴) and the round-off ~ 1e-16 / 1e-7, far below the tolerance.
constexpr double kRelStep = 1e-7;
constexpr double kRelTol = 1e-6;

// The materials checked: neo-Hookean and two other models with different
// tangents (Ogden with two terms, Mooney–Rivlin in isochoric invariants).
struct NamedMaterial {
  std::string name;
  std::shared_ptr<const material::Material> material;
};
std::vector<NamedMaterial> test_materials() {
  const double bulk = kYoung / (3.0 * (1.0 - 2.0 * kPoisson));  // K [Pa]
  return {
      {"neo-hookean", std::make_shared<material::NeoHookean>(kYoung, kPoisson)},
      {"ogden", std::make_shared<material::Ogden>(std::vector<double>{3e3, -0.5e3},
                                                  std::vector<double>{2.5, -2.0}, kPoisson)},
      {"mooney-rivlin", std::make_shared<material::IsochoricInvariant>(
                            material::IsochoricInvariant::mooney_rivlin(1.5e3, 0.4e3, 2.0 / bulk))},
  };
}

// max |a − n| / max(|a|, |n|), printed for the record.
double relative_error(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& numeric) {
  const double scale = std::max(analytic.cwiseAbs().maxCoeff(), numeric.cwiseAbs().maxCoeff());
  return (analytic - numeric).cwiseAbs().maxCoeff() / scale;
}

Mat34 unflatten34(const Eigen::VectorXd& v) { return Eigen::Map<const Mat34>(v.data()); }
Eigen::VectorXd flatten34(const Mat34& m) { return Eigen::Map<const Vec12>(m.data()); }

// #V×3 <-> 3N vertex-major.
Eigen::VectorXd flatten(const Eigen::MatrixX3d& V) {
  const Eigen::MatrixXd Vt = V.transpose();
  return Eigen::Map<const Eigen::VectorXd>(Vt.data(), Vt.size());
}
Eigen::MatrixX3d unflatten_rows(const Eigen::VectorXd& v) {
  return Eigen::Map<const Eigen::MatrixXd>(v.data(), 3, v.size() / 3).transpose();
}

// A well-shaped tet: a regular one of edge kEdge with its corners moved randomly by
// up to 0.1 kEdge, then rotated.
Mat34 random_rest_tet(std::mt19937_64& rng) {
  Mat34 X;
  X << 0.0, 1.0, 0.5, 0.5,  //
      0.0, 0.0, std::sqrt(3.0) / 2.0, std::sqrt(3.0) / 6.0,  //
      0.0, 0.0, 0.0, std::sqrt(2.0 / 3.0);
  std::uniform_real_distribution<double> d(-0.1, 0.1);
  for (Eigen::Index i = 0; i < X.size(); ++i) X.data()[i] += d(rng);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -1.0, 0.6).normalized()).toRotationMatrix();
  return kEdge * (R * X);
}

// Deformed corners: a random homogeneous strain of up to ~15 %, a translation
// and corner noise of up to 0.05 kEdge.
Mat34 random_deformed(const Mat34& X, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
  for (Eigen::Index i = 0; i < 9; ++i) A.data()[i] += 0.15 * d(rng);
  Mat34 x = (A * X).colwise() + Eigen::Vector3d(0.3, -0.2, 0.1) * kEdge;
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += 0.05 * kEdge * d(rng);
  return x;
}

TEST(TetRestDerivative, ElementMatchesFiniteDifferencesAtFixedDeformedCorners) {
  auto rng = palpa::test::make_rng(401);
  std::uniform_real_distribution<double> dz(-1.0, 1.0);
  for (const auto& entry : test_materials()) {
    const auto& name = entry.name;
    const auto& m = entry.material;  // a plain reference: a lambda below captures it
    for (int trial = 0; trial < 3; ++trial) {
      SCOPED_TRACE(name + ", trial " + std::to_string(trial));
      const Mat34 X = random_rest_tet(rng);
      ASSERT_GT(signed_volume(X), 0.05 * kEdge * kEdge * kEdge);  // well shaped: regular is 0.118 kEdge³
      const Mat34 x = random_deformed(X, rng);
      ASSERT_GT(deformation_gradient(tet_geometry(X), x).determinant(), 0.5);
      Mat34 z;
      for (Eigen::Index i = 0; i < z.size(); ++i) z.data()[i] = dz(rng);

      Mat34 analytic;
      tet_rest_gradient_product(*m, tet_geometry(X), x, z, analytic);
      const auto force_along_z = [&](const Eigen::VectorXd& Xv) {
        TetResult r;
        EXPECT_TRUE(tet_evaluate(*m, tet_geometry(unflatten34(Xv)), x, material::EvalOrder::Gradient,
                                 material::PsdProjection::None, r));
        return r.gradient.dot(flatten34(z));
      };
      const Eigen::VectorXd numeric = fd_gradient(force_along_z, flatten34(X), kRelStep * kEdge);
      std::cout << "  element " << name << " trial " << trial
                << ": relative error " << relative_error(flatten34(analytic), numeric) << "\n";
      EXPECT_TRUE(derivatives_match(flatten34(analytic), numeric, kRelTol));
    }
  }
}

TEST(TetRestDerivative, ElementDiffersFromTheDerivativeAtFixedDisplacement) {
  // The two shape derivatives differ by the Hessian times z; checking that it
  // is not zero here guards the test above against comparing the wrong one.
  auto rng = palpa::test::make_rng(402);
  const material::NeoHookean nh(kYoung, kPoisson);
  const Mat34 X = random_rest_tet(rng);
  const Mat34 x = random_deformed(X, rng);
  Mat34 z;
  std::uniform_real_distribution<double> dz(-1.0, 1.0);
  for (Eigen::Index i = 0; i < z.size(); ++i) z.data()[i] = dz(rng);
  Mat34 fixed_x;
  tet_rest_gradient_product(nh, tet_geometry(X), x, z, fixed_x);
  TetResult r;
  ASSERT_TRUE(tet_evaluate(nh, tet_geometry(X), x, material::EvalOrder::Hessian, material::PsdProjection::None, r));
  const Vec12 fixed_u = flatten34(fixed_x) + r.hessian * flatten34(z);
  const Mat34 u = x - X;
  const auto force_along_z = [&](const Eigen::VectorXd& Xv) {
    const Mat34 Xm = unflatten34(Xv);
    TetResult e;
    EXPECT_TRUE(tet_evaluate(nh, tet_geometry(Xm), Xm + u, material::EvalOrder::Gradient,
                             material::PsdProjection::None, e));
    return e.gradient.dot(flatten34(z));
  };
  const Eigen::VectorXd numeric = fd_gradient(force_along_z, flatten34(X), kRelStep * kEdge);
  EXPECT_TRUE(derivatives_match(fixed_u, numeric, kRelTol));
  EXPECT_GT((fixed_u - flatten34(fixed_x)).cwiseAbs().maxCoeff(), 0.1 * fixed_u.cwiseAbs().maxCoeff());
}

// A 2×1×1 box of 12 tets, alternating between two materials.
ElasticModel small_model() {
  const BoxMesh box =
      make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.01, 0.01), Eigen::Vector3i(2, 1, 1));
  const auto materials = test_materials();
  Eigen::VectorXi which(box.mesh.T.rows());
  for (Eigen::Index e = 0; e < which.size(); ++e) which[e] = static_cast<int>(e % 2);
  return ElasticModel(box.mesh,
                      {BodyMaterial{materials[0].material, 1000.0}, BodyMaterial{materials[1].material, 1100.0}},
                      which);
}

TEST(TetRestDerivative, ModelMatchesFiniteDifferencesAtFixedDeformedPositions) {
  constexpr double kCell = 0.01;  // [m]
  const ElasticModel model = small_model();
  const Eigen::Index n = model.num_dofs();
  auto rng = palpa::test::make_rng(403);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  for (int trial = 0; trial < 2; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    // A shear and a stretch plus noise of up to 0.05 cells.
    Eigen::VectorXd u(n);
    for (Eigen::Index v = 0; v < model.num_vertices(); ++v) {
      const Eigen::Vector3d X = model.mesh().V.row(v).transpose();
      u.segment<3>(3 * v) = Eigen::Vector3d(0.1 * X.z(), -0.08 * X.y(), 0.12 * X.x());
    }
    for (Eigen::Index i = 0; i < n; ++i) u[i] += 0.05 * kCell * d(rng);
    Eigen::VectorXd z(n);
    for (Eigen::Index i = 0; i < n; ++i) z[i] = d(rng);
    ASSERT_GT(model.min_jacobian(u), 0.5);

    const Eigen::VectorXd x = flatten(model.mesh().V) + u;  // held fixed
    const auto force_along_z = [&](const Eigen::VectorXd& Xv) {
      ElasticModel moved = model;
      moved.set_rest_positions(unflatten_rows(Xv));
      Eigen::VectorXd g;
      const double energy = moved.elastic_energy(x - Xv, &g);
      EXPECT_TRUE(std::isfinite(energy));
      return g.dot(z);
    };
    const Eigen::VectorXd analytic = flatten(model.rest_gradient_product(u, z));
    const Eigen::VectorXd numeric = fd_gradient(force_along_z, flatten(model.mesh().V), kRelStep * kCell);
    std::cout << "  model trial " << trial << ": relative error " << relative_error(analytic, numeric) << "\n";
    EXPECT_TRUE(derivatives_match(analytic, numeric, kRelTol));
  }
}

TEST(TetRestDerivative, ModelRefusesAnInvertedConfiguration) {
  const ElasticModel model = small_model();
  Eigen::VectorXd u = Eigen::VectorXd::Zero(model.num_dofs());
  u.segment<3>(0) = Eigen::Vector3d(0.05, 0.05, 0.05);  // vertex 0 through the box
  ASSERT_LT(model.min_jacobian(u), 0.0);
  const Eigen::VectorXd z = Eigen::VectorXd::Ones(model.num_dofs());
  EXPECT_TRUE(palpa::test::throws_error([&] { (void)model.rest_gradient_product(u, z); }, ErrorKind::Internal,
                                        {"inverted"}));
  // The model is still usable.
  EXPECT_EQ(model.rest_gradient_product(Eigen::VectorXd::Zero(model.num_dofs()), z).rows(), model.num_vertices());
}

// The box vertex nearest p.
int nearest_vertex(const ElasticModel& model, const Eigen::Vector3d& p) {
  Eigen::Index best = 0;
  (model.mesh().V.rowwise() - p.transpose()).rowwise().squaredNorm().minCoeff(&best);
  return static_cast<int>(best);
}

ElasticModel cube_model(const TetMesh& mesh) {
  return ElasticModel(mesh, {BodyMaterial{std::make_shared<material::NeoHookean>(kYoung, kPoisson), 1050.0}});
}

TEST(TetSetRestPositions, GeometryAndMassEqualThoseOfTheMovedMesh) {
  const BoxMesh box = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.02, 0.01), Eigen::Vector3i(2, 2, 2));
  ElasticModel model = cube_model(box.mesh);
  const int centre = nearest_vertex(model, Eigen::Vector3d(0.01, 0.01, 0.005));
  ASSERT_LT((model.mesh().V.row(centre) - Eigen::RowVector3d(0.01, 0.01, 0.005)).norm(), 1e-12);

  TetMesh moved = box.mesh;
  moved.V.row(centre) += Eigen::RowVector3d(1.3e-3, -0.9e-3, 0.6e-3);
  model.set_rest_positions(moved.V);
  const ElasticModel reference = cube_model(moved);

  EXPECT_EQ(model.mesh().V, moved.V);
  const double tol = 1e-14;
  double volume_change = 0.0;
  for (Eigen::Index e = 0; e < model.num_elements(); ++e) {
    const TetGeometry& a = model.geometry(e);
    const TetGeometry& b = reference.geometry(e);
    EXPECT_LE(std::abs(a.volume - b.volume), tol * b.volume) << "tet " << e;
    EXPECT_LE((a.grad_n - b.grad_n).cwiseAbs().maxCoeff(), tol * b.grad_n.cwiseAbs().maxCoeff()) << "tet " << e;
    volume_change = std::max(volume_change, std::abs(b.volume - cube_model(box.mesh).geometry(e).volume));
  }
  // The move did change the geometry, so the comparison above means something.
  EXPECT_GT(volume_change, 0.05 * (0.01 * 0.01 * 0.005 / 6.0));
  EXPECT_LE((model.lumped_mass() - reference.lumped_mass()).cwiseAbs().maxCoeff(),
            tol * reference.lumped_mass().maxCoeff());
  // (The centre's own mass is that of its fixed star, but its neighbours' change.)
  EXPECT_GT((model.lumped_mass() - cube_model(box.mesh).lumped_mass()).cwiseAbs().maxCoeff(),
            1e-3 * reference.lumped_mass().maxCoeff());
  // Total mass is that of the box: the centre stays inside it.
  EXPECT_NEAR(model.total_mass(), 1050.0 * 0.02 * 0.02 * 0.01, 1e-12 * model.total_mass());
}

TEST(TetSetRestPositions, RefusedUpdatesLeaveTheModelUnchanged) {
  const BoxMesh box = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.02, 0.01), Eigen::Vector3i(2, 2, 2));
  ElasticModel model = cube_model(box.mesh);
  const int centre = nearest_vertex(model, Eigen::Vector3d(0.01, 0.01, 0.005));
  Eigen::VectorXd volumes(model.num_elements());
  for (Eigen::Index e = 0; e < model.num_elements(); ++e) volumes[e] = model.geometry(e).volume;
  const Eigen::VectorXd mass = model.lumped_mass();

  const auto unchanged = [&] {
    Eigen::VectorXd now(model.num_elements());
    for (Eigen::Index e = 0; e < model.num_elements(); ++e) now[e] = model.geometry(e).volume;
    EXPECT_EQ(now, volumes);
    EXPECT_EQ(model.lumped_mass(), mass);
    EXPECT_EQ(model.mesh().V, box.mesh.V);
  };

  // The centre pushed out through the xmax face: some tets turn inside out.
  Eigen::MatrixX3d inverted = box.mesh.V;
  inverted.row(centre) += Eigen::RowVector3d(0.015, 0.0, 0.0);
  EXPECT_TRUE(palpa::test::throws_error([&] { model.set_rest_positions(inverted); }, ErrorKind::Solver,
                                        {"tetrahedron", "inverted or flat (volume -"}));
  unchanged();

  Eigen::MatrixX3d nan = box.mesh.V;
  nan(centre, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(palpa::test::throws_error([&] { model.set_rest_positions(nan); }, ErrorKind::Solver,
                                        {"vertex " + std::to_string(centre), "not finite"}));
  unchanged();

  const Eigen::MatrixX3d short_v = box.mesh.V.topRows(box.mesh.V.rows() - 1);
  EXPECT_TRUE(palpa::test::throws_error([&] { model.set_rest_positions(short_v); }, ErrorKind::Input,
                                        {"26 rest positions for a mesh of 27 vertices"}));
  unchanged();
}

}  // namespace
}  // namespace palpa::tet
