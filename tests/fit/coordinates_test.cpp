// SPDX-License-Identifier: AGPL-3.0-or-later
// The coordinates a fit moves in: the start reproduces the material, dθ/dx
// matches central differences, and the start lies inside the bounds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "palpa/core/error.hpp"
#include "palpa/fit/coordinates.hpp"
#include "palpa/material/models.hpp"
#include "palpa/material/spline_material.hpp"

namespace palpa::fit {
namespace {

using material::Material;

std::vector<std::shared_ptr<Material>> materials() {
  using namespace material;
  const Ogden og({5e3, 0.4e3}, {1.5, 6.0}, 0.47);
  return {std::make_shared<NeoHookean>(17e3, 0.45),
          std::make_shared<NeoHookean>(NeoHookean::with_volume_term(17e3, 0.3, 0.3)),
          std::make_shared<IsochoricInvariant>(IsochoricInvariant::neo_hookean(6e3, 2e-5)),
          std::make_shared<IsochoricInvariant>(IsochoricInvariant::mooney_rivlin(5e3, 1e3, 2e-5)),
          std::make_shared<IsochoricInvariant>(IsochoricInvariant::yeoh(6e3, 0.5e3, 0.1e3, 2e-6)),
          std::make_shared<Ogden>(og),
          std::make_shared<SplineMaterial>(SplineMaterial::from_model(og))};
}

// Central differences of θ(x), step h in every coordinate (x is O(1)).
Eigen::MatrixXd central_differences(const Coordinates& c, const Eigen::VectorXd& x, double h) {
  Eigen::MatrixXd j(c.theta(x).size(), c.size());
  for (Eigen::Index i = 0; i < c.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    j.col(i) = (c.theta(xp) - c.theta(xm)) / (2.0 * h);
  }
  return j;
}

TEST(FitCoordinates, TheStartIsTheMaterialAndTheJacobianMatchesDifferences) {
  // Tolerances: θ(start) to 1e-12 relative (one multiplication and division
  // per parameter); dθ/dx to 1e-6 of the column's size with h = 1e-5 (central
  // differences of smooth maps of O(1) coordinates: truncation ~h², rounding
  // ~1e-16/h).
  for (const auto& m : materials()) {
    const double mu0 = material::small_strain_constants(*m).mu;
    const Coordinates c(*m, {}, mu0);
    const Eigen::VectorXd x0 = c.start();
    ASSERT_EQ(x0.size(), m->num_params()) << m->model();
    EXPECT_TRUE(c.theta(x0).isApprox(m->params(), 1e-12)) << m->model() << ": " << c.theta(x0).transpose();
    for (Eigen::Index i = 0; i < c.size(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      EXPECT_LT(c.lower()[k], x0[i]) << m->model() << " coordinate " << i;
      EXPECT_GT(c.upper()[k], x0[i]) << m->model() << " coordinate " << i;
    }
    // At the start and at a point moved off it.
    for (const double shift : {0.0, 0.03}) {
      const Eigen::VectorXd x = x0 + Eigen::VectorXd::Constant(x0.size(), shift);
      const Eigen::MatrixXd exact = c.dtheta_dx(x);
      const Eigen::MatrixXd fd = central_differences(c, x, 1e-5);
      for (Eigen::Index i = 0; i < c.size(); ++i) {
        EXPECT_LE((exact.col(i) - fd.col(i)).norm(), 1e-6 * fd.col(i).norm() + 1e-300)
            << m->model() << " coordinate " << i << " (" << m->param_info(c.param(i)).name << ") shift " << shift
            << "\nexact " << exact.col(i).transpose() << "\nfd    " << fd.col(i).transpose();
      }
    }
  }
}

// ν of the material at x.
double poisson_at(const Material& m, const Coordinates& c, const Eigen::VectorXd& x) {
  auto probe = m.clone();
  probe->set_params(c.theta(x));
  return material::small_strain_constants(*probe).poisson();
}

TEST(FitCoordinates, PoissonsRatioStaysInsideItsRangeInEveryModel) {
  // Far out in the logistic coordinate ν approaches the ends without reaching
  // them; in the models with D1 the same coordinate sets D1 so that the
  // material's small-strain ν is the coordinate's. Tolerance 1e-9 on ν: ν is
  // recovered from the rest Hessian of a material with K/μ up to 5000.
  const PoissonRange range{0.45, 0.4999};
  for (const auto& m : materials()) {
    if (m->model() == "spline" || m->model() == "neo-hookean-volume") continue;
    const Coordinates c(*m, {}, material::small_strain_constants(*m).mu, range);
    Eigen::Index nu = -1;
    for (Eigen::Index i = 0; i < c.size(); ++i) nu = c.is_poisson(i) ? i : nu;
    ASSERT_GE(nu, 0) << m->model();
    const Eigen::VectorXd x0 = c.start();
    // (a start on or beyond an end is moved inside by 1e-4 of the range)
    const double inside = 1e-4 * (range.hi - range.lo);
    EXPECT_NEAR(poisson_at(*m, c, x0),
                std::clamp(material::small_strain_constants(*m).poisson(), range.lo + inside, range.hi - inside), 1e-9)
        << m->model();
    for (const double xn : {-40.0, -3.0, 0.0, 3.0, 40.0}) {
      Eigen::VectorXd x = x0;
      x[nu] = xn;
      const double v = poisson_at(*m, c, x);
      EXPECT_GE(v, range.lo - 1e-9) << m->model() << " x " << xn;
      EXPECT_LE(v, range.hi + 1e-9) << m->model() << " x " << xn;
      EXPECT_NEAR(v, range.lo + (range.hi - range.lo) / (1.0 + std::exp(-xn)), 1e-9) << m->model() << " x " << xn;
    }
  }
  // A start outside the range is moved inside it.
  const material::NeoHookean loose(10e3, 0.3);
  const Coordinates c(loose, {}, 4e3, range);
  EXPECT_NEAR(c.theta(c.start())[1], 0.45, 1e-4 * 0.05 + 1e-12);
  // A held ν is what the start has, whatever the range.
  const Coordinates held(loose, {"nu"}, 4e3, range);
  EXPECT_EQ(held.theta(held.start())[1], 0.3);
  EXPECT_THROW(Coordinates(loose, {}, 4e3, PoissonRange{0.3, 0.5}), Error);
  EXPECT_THROW(Coordinates(loose, {}, 4e3, PoissonRange{0.4, 0.3}), Error);
}

TEST(FitCoordinates, FixingNuInAModelWithD1HoldsNuAndD1FollowsTheModuli) {
  const auto yeoh = material::IsochoricInvariant::yeoh(6e3, 0.5e3, 0.1e3, 2e-6);
  const double nu0 = material::small_strain_constants(yeoh).poisson();
  const Coordinates held(yeoh, {"nu"}, 12e3);
  ASSERT_EQ(held.size(), 3);  // C10, C20, C30
  Eigen::VectorXd x = held.start();
  x[0] *= 1.7;
  EXPECT_NEAR(poisson_at(yeoh, held, x), nu0, 1e-9);
  EXPECT_NEAR(held.theta(x)[3], 2e-6 / 1.7, 1e-9 * 2e-6);
  // --fix D1 holds D1 itself: ν then changes with the moduli.
  const Coordinates d1(yeoh, {"D1"}, 12e3);
  ASSERT_EQ(d1.size(), 3);
  x = d1.start();
  x[0] *= 1.7;
  EXPECT_EQ(d1.theta(x)[3], 2e-6);
  EXPECT_LT(poisson_at(yeoh, d1, x), nu0 - 1e-4);
  // Models without D1 or ν have no "nu" to fix.
  const auto spline = material::SplineMaterial::from_model(material::NeoHookean(10e3, 0.45));
  EXPECT_THROW(Coordinates(spline, {"nu"}, 3e3), Error);
}

TEST(FitCoordinates, FixedParametersAreHeldAndUnknownNamesRefused) {
  const material::Ogden og({5e3, 0.4e3}, {1.5, 6.0}, 0.47);
  const Coordinates c(og, {"nu", "alpha[1]"}, 3e3);
  ASSERT_EQ(c.size(), 3);
  Eigen::VectorXd x = c.start();
  x *= 1.1;
  const Eigen::VectorXd t = c.theta(x);
  EXPECT_EQ(t[og.num_params() - 1], 0.47);  // nu
  EXPECT_THROW(Coordinates(og, {"E"}, 3e3), Error);
  EXPECT_THROW(Coordinates(material::NeoHookean(10e3, 0.3), {"E", "nu"}, 3e3), Error);
}

}  // namespace
}  // namespace palpa::fit
