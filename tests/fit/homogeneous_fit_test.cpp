// SPDX-License-Identifier: AGPL-3.0-or-later
// Fits to homogeneous stress–stretch curves (closed form, no FEM): the model
// the data was made with is recovered; a spline fits far better than the
// modulus alone.
#include <gtest/gtest.h>

#include <cmath>

#include "common/test_support.hpp"
#include "fit/fit_fixtures.hpp"
#include "palpa/fit/fit.hpp"
#include "palpa/material/models.hpp"

namespace palpa::fit {
namespace {

using material::LoadCase;
using palpa::test::ScratchDir;

constexpr double kNoiseRel = 0.005;  // σ = 0.5% of the largest |stress| ...
constexpr double kNoiseAbs = 20.0;   // ... + 20 Pa

test::Curve homogeneous(const material::Material& m, LoadCase lc, double from, double to, int points,
                        std::uint64_t salt) {
  test::Curve c;
  for (int k = 0; k < points; ++k) c.x.push_back(from + (to - from) * k / (points - 1));
  const auto s = material::homogeneous_curve_sensitivity(m, lc, c.x);
  for (const auto& p : s.points) c.y.push_back(p.nominal);
  test::add_noise(c.y, kNoiseRel, kNoiseAbs, salt);
  return c;
}

// Uniaxial (compression and tension) and equibiaxial training curves and a
// uniaxial validation curve of `truth`, as a dataset in `dir`. The stretches
// stay inside the default spline knot ranges (single stretches 0.5–2, products
// 0.4–2.5), beyond which a spline continues as a parabola and cannot follow a
// stiffening material.
Dataset write_homogeneous_dataset(const ScratchDir& dir, const material::Material& truth, double poisson) {
  test::write_stress_csv(dir / "uni.csv", LoadCase::Uniaxial, homogeneous(truth, LoadCase::Uniaxial, 0.7, 1.95, 18, 1));
  test::write_stress_csv(dir / "bi.csv", LoadCase::Equibiaxial,
                         homogeneous(truth, LoadCase::Equibiaxial, 1.05, 1.4, 12, 2));
  test::write_stress_csv(dir / "uni2.csv", LoadCase::Uniaxial,
                         homogeneous(truth, LoadCase::Uniaxial, 0.8, 1.8, 10, 3));
  const Json d{{"palpa_dataset", 1},
               {"test", "homogeneous"},
               {"poisson", poisson},
               {"curves", Json::array({Json{{"file", "uni.csv"}, {"load_case", "uniaxial"}, {"role", "train"}},
                                      Json{{"file", "bi.csv"}, {"load_case", "equibiaxial"}, {"role", "train"}},
                                      Json{{"file", "uni2.csv"}, {"load_case", "uniaxial"}, {"role", "validate"}}})}};
  write_json_file(dir / "dataset.json", d);
  return read_dataset(dir / "dataset.json");
}

FitOptions options(const std::string& model) {
  FitOptions o;
  o.model = model;
  o.max_iterations = 200;
  o.function_tolerance = 1e-10;
  return o;
}

double relative(double fitted, double truth) { return std::abs(fitted / truth - 1.0); }

TEST(HomogeneousFit, RecoversYeoh) {
  ScratchDir dir;
  const auto truth = material::IsochoricInvariant::yeoh(12e3, 0.6e3, 0.15e3, 5.10204e-6);  // ν = 0.47
  const Dataset d = write_homogeneous_dataset(dir, truth, 0.47);
  const FitResult r = fit_dataset(d, options("yeoh"));
  ASSERT_EQ(r.guesses.size(), 1u);
  const GuessResult& g = r.guesses[0];
  ASSERT_TRUE(g.done);
  const Eigen::VectorXd t = g.material->params();  // C10, C20, C30, D1
  RecordProperty("C10", std::to_string(t[0]));
  RecordProperty("C20", std::to_string(t[1]));
  RecordProperty("C30", std::to_string(t[2]));
  RecordProperty("iterations", g.iterations);
  EXPECT_LT(relative(t[0], 12e3), 0.02) << t.transpose();
  EXPECT_LT(relative(t[1], 0.6e3), 0.15) << t.transpose();
  EXPECT_LT(relative(t[2], 0.15e3), 0.10) << t.transpose();
  EXPECT_LT(g.objective_final, 0.1 * g.objective_stage1);
}

TEST(HomogeneousFit, RecoversMooneyRivlin) {
  ScratchDir dir;
  const auto truth = material::IsochoricInvariant::mooney_rivlin(8e3, 2e3, 2.013e-6);  // ν ≈ 0.49
  const Dataset d = write_homogeneous_dataset(dir, truth, 0.49);
  const FitResult r = fit_dataset(d, options("mooney-rivlin"));
  const GuessResult& g = r.guesses.at(0);
  const Eigen::VectorXd t = g.material->params();  // C10, C01, D1
  RecordProperty("C10", std::to_string(t[0]));
  RecordProperty("C01", std::to_string(t[1]));
  EXPECT_LT(relative(t[0], 8e3), 0.03) << t.transpose();
  EXPECT_LT(relative(t[1], 2e3), 0.10) << t.transpose();
  // Small-strain shear modulus 2 (C10 + C01) = 20 kPa.
  EXPECT_LT(relative(material::small_strain_constants(*g.material).mu, 20e3), 0.02);
}

TEST(HomogeneousFit, SplineBeatsTheModulusStage) {
  // Mooney–Rivlin data; the spline's shape stage with Levenberg–Marquardt (and
  // the default curvature regularization) lowers ε more than a hundredfold
  // from stage 1 (measured 1.18e8 -> 8.5e5 Pa² in 18 iterations) and predicts
  // the validation curve within a few noise levels. Nonlinear CG gets there
  // far more slowly (measured 1.7e7 after 60 iterations): checked as "at
  // least 3x below stage 1".
  ScratchDir dir;
  const auto truth = material::IsochoricInvariant::mooney_rivlin(8e3, 2e3, 2.013e-6);
  const Dataset d = write_homogeneous_dataset(dir, truth, 0.49);
  FitOptions o = options("spline");
  o.max_iterations = 60;
  o.optimizer = Optimizer::LevenbergMarquardt;
  const FitResult r = fit_dataset(d, o);
  const GuessResult& g = r.guesses.at(0);
  RecordProperty("lm_objective_stage1", std::to_string(g.objective_stage1));
  RecordProperty("lm_objective_final", std::to_string(g.objective_final));
  EXPECT_LT(g.objective_final, 0.02 * g.objective_stage1);
  // Validation curve within a few noise levels.
  const auto pred = predict_curves(d, g.layer_depth, *g.material, o.simulation);
  const MeasuredCurve& v = d.curves[2];
  double largest = 0.0;
  for (double y : v.y) largest = std::max(largest, std::abs(y));
  EXPECT_LT(rms_error(v, pred[2]), 3.0 * (kNoiseRel * largest + kNoiseAbs));

  o.optimizer = Optimizer::Nlcg;
  const GuessResult cg = fit_dataset(d, o).guesses.at(0);
  RecordProperty("nlcg_objective_final", std::to_string(cg.objective_final));
  EXPECT_LT(cg.objective_final, cg.objective_stage1 / 3.0);
}

TEST(HomogeneousFit, ModulusOnlyIsTheLeastSquaresScale) {
  // Neo-Hookean data with the dataset's ν: stage 1 alone recovers E.
  ScratchDir dir;
  const material::NeoHookean truth(23e3, 0.45);
  const Dataset d = write_homogeneous_dataset(dir, truth, 0.45);
  FitOptions o = options("neo-hookean");
  o.modulus_only = true;
  const FitResult r = fit_dataset(d, o);
  const GuessResult& g = r.guesses.at(0);
  EXPECT_EQ(g.stop_reason, "modulus only");
  EXPECT_NEAR(g.modulus_scale, 2.3, 0.01 * 2.3);
  EXPECT_LT(relative(material::small_strain_constants(*g.material).young(), 23e3), 0.01);
  EXPECT_LT(g.objective_stage1, 0.01 * g.objective_initial);
}

}  // namespace
}  // namespace palpa::fit
