// SPDX-License-Identifier: AGPL-3.0-or-later
// The contact potential inside a System solved by Newton, wired as
// contact.hpp's usage note says (commit in prepare(), fresh detection in
// energy(), committed contacts for gradient and Hessian): loaded points settle on a box, at
// the analytic depth, and the stiffness rule hits its target penetration.

#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <vector>

#include "contact/shapes.hpp"
#include "palpa/contact/penalty_contact.hpp"
#include "palpa/contact/stiffness.hpp"
#include "palpa/solve/newton.hpp"

namespace palpa::contact {
namespace {

// N free points, each tied by a spring (stiffness s) to its rest position and
// pushed down by a force F, against an obstacle with penalty stiffness k.
class LoadedPoints : public System {
 public:
  LoadedPoints(const Obstacle& obstacle, Eigen::Matrix3Xd rest, double s, double F, double k)
      : obstacle_(obstacle), rest_(std::move(rest)), s_(s), F_(F), committed_(vertex_samples(all(rest_.cols())), k, "box") {}
  Eigen::Index num_dofs() const override { return rest_.size(); }

  double energy(const Eigen::VectorXd& x) const override {
    const auto P = points(x);
    return 0.5 * s_ * (P - rest_).squaredNorm() + F_ * P.row(2).sum() +
           committed_.detected_energy(obstacle_, P);
  }
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    const auto P = points(x);
    Eigen::Matrix3Xd G = s_ * (P - rest_);
    G.row(2).array() += F_;
    committed_.add_gradient(obstacle_, P, G);
    g = G.reshaped();
  }
  void hessian(const Eigen::VectorXd&, Eigen::SparseMatrix<double>& H) const override {
    // Lower triangles of the 3×3 diagonal blocks: a fixed pattern.
    std::vector<Eigen::Matrix3d> block(static_cast<std::size_t>(rest_.cols()),
                                       s_ * Eigen::Matrix3d::Identity());
    committed_.for_each_surface_hessian(obstacle_, [&](int point, int, const Eigen::Matrix3d& b) {
      block[static_cast<std::size_t>(point)] += b;
    });
    std::vector<Eigen::Triplet<double>> t;
    for (std::size_t i = 0; i < block.size(); ++i) {
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c <= r; ++c) {
          const auto base = 3 * static_cast<int>(i);
          t.emplace_back(base + r, base + c, block[i](r, c));
        }
      }
    }
    H.resize(num_dofs(), num_dofs());
    H.setFromTriplets(t.begin(), t.end());
  }
  void prepare(const Eigen::VectorXd& x) override {
    committed_.commit(obstacle_, points(x));
  }

  const PenaltyContact& committed() const { return committed_; }
  static Eigen::Map<const Eigen::Matrix3Xd> points(const Eigen::VectorXd& x) {
    return {x.data(), 3, x.size() / 3};
  }

 private:
  static std::vector<int> all(Eigen::Index n) {
    std::vector<int> out(static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = static_cast<int>(i);
    return out;
  }

  const Obstacle& obstacle_;
  Eigen::Matrix3Xd rest_;
  double s_, F_;
  PenaltyContact committed_;
};

TEST(ContactNewton, LoadedPointsSettleAtTheAnalyticDepthAndTheStiffnessRuleHitsItsTarget) {
  const double h = 0.05;  // box [−h, h]³
  const Obstacle box(test::cube_mesh(h), "box");
  // A 6×6 grid 1 mm above the top face, away from its edges.
  Eigen::Matrix3Xd rest(3, 36);
  for (int i = 0; i < 36; ++i)
    rest.col(i) = Eigen::Vector3d(-0.03 + 0.012 * (i % 6), -0.03 + 0.012 * (i / 6), h + 1e-3);
  // The springs alone would put the points 24 mm deep in the box (no
  // tunnelling through it in the first step); at equilibrium they carry ~5% of
  // the load.
  const double s = 20.0;  // N/m
  const double F = 0.5;   // N per point
  const double target = 3e-4;
  const double k = stiffness_for_penetration(F * 36.0, 36.0, target);
  LoadedPoints system(box, rest, s, F, k);

  NewtonOptions options;
  options.line_search = LineSearchKind::GoldenSection;  // as in the thesis, §7.3.4
  options.gradient_abs_tol = 1e-10;
  NewtonSolver solver(options);
  Eigen::VectorXd x = rest.reshaped();
  const NewtonResult result = solver.solve(system, x);
  ASSERT_TRUE(result.converged()) << result.message;
  // The contact set changes once (none → all), then Newton is exact: the
  // energy is quadratic within a Voronoi region.
  EXPECT_LE(result.iterations, 6);

  // Equilibrium of s(z0 − z) − F + 2k(h − z) = 0 for every point.
  const double z = (s * (h + 1e-3) + 2.0 * k * h - F) / (s + 2.0 * k);
  const auto P = LoadedPoints::points(x);
  for (int i = 0; i < 36; ++i) {
    EXPECT_NEAR(P(2, i), z, 1e-12) << i;
    EXPECT_NEAR(P(0, i), rest(0, i), 1e-12);
  }
  ASSERT_EQ(system.committed().size(), 36U);
  EXPECT_NEAR(system.committed().max_depth(), h - z, 1e-12);
  // The rule assumed the contact carries the whole load; the springs take 5%.
  EXPECT_NEAR(h - z, target, 0.06 * target);

  // Reaction on the box = the load the contact carries.
  const Wrench w = system.committed().obstacle_wrench(box, P, Eigen::Vector3d::Zero());
  EXPECT_NEAR(w.force.z(), -36.0 * 2.0 * k * (h - z), 1e-9);
  EXPECT_NEAR(w.force.head<2>().norm(), 0.0, 1e-9);

  // The correction rule, from a stiffness 3× too soft: the error in k falls
  // from 67% to a few % after one equilibrium, and below 0.1% after three
  // (the springs' share of the load changes with the depth, so one step is
  // not exact).
  const double k_exact = (F - s * (1e-3 + target)) / (2.0 * target);
  double k_outer = k / 3.0;
  for (int round = 0; round < 3; ++round) {
    LoadedPoints trial(box, rest, s, F, k_outer);
    Eigen::VectorXd xt = rest.reshaped();
    ASSERT_TRUE(solver.solve(trial, xt).converged());
    k_outer = corrected_stiffness(k_outer, trial.committed().max_depth(), target);
    if (round == 0) {
      EXPECT_NEAR(k_outer, k_exact, 0.03 * k_exact);
    }
  }
  EXPECT_NEAR(k_outer, k_exact, 1e-3 * k_exact);
}

}  // namespace
}  // namespace palpa::contact
