// SPDX-License-Identifier: AGPL-3.0-or-later
// Recovery: curves simulated from a known material with seeded noise
// (σ = 0.5% of the largest force + 1 mN), two training radii and one
// validation radius; the fit with the same model recovers the small-strain
// Young's modulus within 2% and predicts the validation curve within the noise
// (RMS error ≤ 1.5 σ).
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "fit/fit_fixtures.hpp"
#include "palpa/fit/fit.hpp"
#include "palpa/material/models.hpp"

namespace palpa::fit {
namespace {

using palpa::test::ScratchDir;

constexpr double kYoungTolerance = 0.02;
constexpr double kValidationNoiseFactor = 1.5;

struct Recovery {
  double young = 0.0;
  double validation_rms = 0.0;
  double validation_sigma = 0.0;
  GuessResult guess;
};

Recovery recover(const material::Material& truth, const std::string& model, double max_depth) {
  ScratchDir dir;
  test::IndentationSpec spec;
  spec.true_depth = 10e-3;
  spec.layer_depth = "10 mm";
  spec.train_radii = {2e-3, 4e-3};
  spec.validate_radii = {3e-3};
  spec.max_depth = max_depth;
  spec.points = 12;
  spec.mesh_level = 0;
  spec.salt = 5;
  const test::Synthetic data = test::write_indentation_dataset(dir.path(), truth, spec);
  const Dataset d = read_dataset(data.dataset);
  FitOptions o;
  o.model = model;
  o.optimizer = Optimizer::LevenbergMarquardt;
  o.simulation.mesh_level = spec.mesh_level;
  o.simulation.steps = 10;
  o.max_iterations = 20;
  const FitResult r = fit_dataset(d, o);
  Recovery out;
  out.guess = r.guesses.at(0);
  out.young = material::small_strain_constants(*out.guess.material).young();
  const auto pred = predict_curves(d, out.guess.layer_depth, *out.guess.material, o.simulation);
  out.validation_rms = rms_error(d.curves[2], pred[2]);
  out.validation_sigma = data.sigma[2];
  return out;
}

void report(const Recovery& r, double true_young) {
  ::testing::Test::RecordProperty("young_Pa", std::to_string(r.young));
  ::testing::Test::RecordProperty("young_rel_error", std::to_string(r.young / true_young - 1.0));
  ::testing::Test::RecordProperty("validation_rms_over_sigma", std::to_string(r.validation_rms / r.validation_sigma));
  ::testing::Test::RecordProperty("iterations", r.guess.iterations);
  ::testing::Test::RecordProperty("evaluations", r.guess.evaluations);
  ::testing::Test::RecordProperty("objective_stage1", std::to_string(r.guess.objective_stage1));
  ::testing::Test::RecordProperty("objective_final", std::to_string(r.guess.objective_final));
}

TEST(Recovery, NeoHookean) {
  const material::NeoHookean truth(20e3, 0.45);
  const Recovery r = recover(truth, "neo-hookean", 1.5e-3);
  report(r, 20e3);
  EXPECT_NEAR(r.young, 20e3, kYoungTolerance * 20e3);
  EXPECT_LE(r.validation_rms, kValidationNoiseFactor * r.validation_sigma);
  EXPECT_LE(r.guess.objective_final, r.guess.objective_stage1);
}

TEST(Recovery, Ogden) {
  const material::Ogden truth({6e3, 0.3e3}, {1.8, 7.0}, 0.45);
  const double young = material::small_strain_constants(truth).young();  // 18.7 kPa
  const Recovery r = recover(truth, "ogden", 2.5e-3);
  report(r, young);
  EXPECT_NEAR(r.young, young, kYoungTolerance * young);
  EXPECT_LE(r.validation_rms, kValidationNoiseFactor * r.validation_sigma);
  EXPECT_LT(r.guess.objective_final, r.guess.objective_stage1);
}

}  // namespace
}  // namespace palpa::fit
