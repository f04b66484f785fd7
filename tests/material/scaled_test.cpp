// SPDX-License-Identifier: AGPL-3.0-or-later
// A scaled material is the same model with its energy times the factor, for
// every model: energy, stress and tangent at random stretches (compressed,
// stretched, inverted), the small-strain constants, and the refusals.
#include "palpa/material/scaled.hpp"

#include <gtest/gtest.h>

#include <random>

#include "model_fixtures.hpp"
#include "palpa/core/error.hpp"

namespace palpa::material {
namespace {

using test::ModelCase;

class Scaled : public ::testing::TestWithParam<ModelCase> {};

TEST_P(Scaled, EnergyStressAndTangentScaleByTheFactor) {
  const std::unique_ptr<Material> m = GetParam().make();
  const double factor = 2.7;
  const std::unique_ptr<Material> s = scaled(*m, factor);
  EXPECT_EQ(s->model(), m->model());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> stretch(0.6, 1.5);
  for (int i = 0; i < 20; ++i) {
    Vec3 lambda(stretch(rng), stretch(rng), stretch(rng));
    if (i % 5 == 4 && GetParam().inversion_safe) lambda[2] = -0.2;  // inverted
    StretchEnergy a;
    StretchEnergy b;
    m->evaluate(lambda, EvalOrder::Hessian, a);
    s->evaluate(lambda, EvalOrder::Hessian, b);
    const double scale = std::abs(a.psi) + a.grad.norm() + a.hess.norm();
    EXPECT_NEAR(b.psi, factor * a.psi, 1e-12 * factor * scale) << lambda.transpose();
    EXPECT_LE((b.grad - factor * a.grad).norm(), 1e-12 * factor * scale) << lambda.transpose();
    EXPECT_LE((b.hess - factor * a.hess).norm(), 1e-12 * factor * scale) << lambda.transpose();
  }
}

TEST_P(Scaled, WithYoungSetsTheModulusAndKeepsPoissonsRatio) {
  const std::unique_ptr<Material> m = GetParam().make();
  const ElasticConstants before = small_strain_constants(*m);
  const std::unique_ptr<Material> s = with_young(*m, 123.4e3);
  const ElasticConstants after = small_strain_constants(*s);
  EXPECT_NEAR(after.young(), 123.4e3, 1e-9 * 123.4e3);
  EXPECT_NEAR(after.poisson(), before.poisson(), 1e-12);
}

INSTANTIATE_TEST_SUITE_P(AllModels, Scaled, ::testing::ValuesIn(test::all_model_cases()),
                         [](const auto& info) { return info.param.name; });

TEST(Scaled, RefusesAFactorThatIsNotPositive) {
  const std::unique_ptr<Material> m = test::all_model_cases().front().make();
  for (double f : {0.0, -1.0, std::nan("")}) EXPECT_THROW(scaled(*m, f), Error);
  try {
    with_young(*m, -5.0);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Input);
    EXPECT_NE(std::string(e.what()).find("Young's modulus of -5 Pa"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace palpa::material
