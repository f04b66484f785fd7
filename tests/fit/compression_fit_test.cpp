// SPDX-License-Identifier: AGPL-3.0-or-later
// Plate compression between frictionless platens is homogeneous uniaxial
// compression: data from the closed form F = π R² |P11(1 − d/H)| of a known
// neo-Hookean, with noise, fitted by simulating the compression test.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/test_support.hpp"
#include "fit/fit_fixtures.hpp"
#include "palpa/core/units.hpp"
#include "palpa/fit/fit.hpp"
#include "palpa/material/models.hpp"

namespace palpa::fit {
namespace {

using palpa::test::ScratchDir;

constexpr double kRadius = 10e-3;
constexpr double kHeight = 10e-3;

test::Curve closed_form(const material::Material& m, double max_travel, int points, std::uint64_t salt) {
  test::Curve c;
  for (int k = 1; k <= points; ++k) c.x.push_back(max_travel * k / points);
  std::vector<double> stretch;
  for (double d : c.x) stretch.push_back(1.0 - d / kHeight);
  const auto s = material::homogeneous_curve_sensitivity(m, material::LoadCase::Uniaxial, stretch);
  for (const auto& p : s.points) c.y.push_back(std::numbers::pi * kRadius * kRadius * std::abs(p.nominal));
  test::add_noise(c.y, 0.005, 1e-3, salt);
  return c;
}

TEST(CompressionFit, RecoversYoungsModulusFromFrictionlessPlatens) {
  ScratchDir dir;
  const material::NeoHookean truth(20e3, 0.45);
  test::write_force_csv(dir / "c1.csv", closed_form(truth, 3e-3, 10, 21));
  test::write_force_csv(dir / "c2.csv", closed_form(truth, 2.5e-3, 8, 22));
  const Json j{{"palpa_dataset", 1},
               {"test", "compression"},
               {"sample_radius", "10 mm"},
               {"sample_height", "10 mm"},
               {"contact", "frictionless"},
               {"poisson", 0.45},
               {"curves", Json::array({Json{{"file", "c1.csv"}, {"role", "train"}},
                                       Json{{"file", "c2.csv"}, {"role", "validate"}}})}};
  write_json_file(dir / "dataset.json", j);
  const Dataset d = read_dataset(dir / "dataset.json");
  FitOptions o;
  o.model = "neo-hookean";
  o.simulation.mesh_level = 0;
  o.simulation.steps = 10;
  o.max_iterations = 20;
  const FitResult r = fit_dataset(d, o);
  const GuessResult& g = r.guesses.at(0);
  const double young = material::small_strain_constants(*g.material).young();
  const double young1 = material::small_strain_constants(*g.stage1_material).young();
  RecordProperty("young_stage1_Pa", std::to_string(young1));
  RecordProperty("young_Pa", std::to_string(young));
  RecordProperty("poisson", std::to_string(material::small_strain_constants(*g.material).poisson()));
  EXPECT_NEAR(young1, 20e3, 0.01 * 20e3);
  EXPECT_NEAR(young, 20e3, 0.01 * 20e3);
  EXPECT_LE(g.objective_final, g.objective_stage1 * (1.0 + 1e-6));
  // The homogeneous simulation reproduces the closed form: the validation
  // curve's RMS error is at the noise level (σ = 0.5% of 2 N + 1 mN ≈ 11 mN).
  const auto pred = predict_curves(d, g.layer_depth, *g.material, o.simulation);
  EXPECT_LT(rms_error(d.curves[1], pred[1]), 0.02);
}

}  // namespace
}  // namespace palpa::fit
