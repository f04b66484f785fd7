// SPDX-License-Identifier: AGPL-3.0-or-later
// Fits to homogeneous stress–stretch curves (closed form, no FEM): the model
// the data was made with is recovered; a spline fits far better than the
// modulus alone.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

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
  EXPECT_EQ(g.stop.detail, "modulus only");
  EXPECT_EQ(g.stop.termination, Termination::Converged);
  EXPECT_NEAR(g.modulus_scale, 2.3, 0.01 * 2.3);
  EXPECT_LT(relative(material::small_strain_constants(*g.material).young(), 23e3), 0.01);
  EXPECT_LT(g.objective_stage1, 0.01 * g.objective_initial);
}

// RMS error [Pa] of `m` over the curves of one role.
double rms_of_role(const Dataset& d, const material::Material& m, CurveRole role) {
  const auto pred = predict_curves(d, d.layer_depths.at(0), m, SimulationOptions{});
  double sq = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < d.curves.size(); ++i) {
    if (d.curves[i].role != role) continue;
    sq += sum_of_squares(d.curves[i], pred[i]);
    n += compared_points(d.curves[i], pred[i]);
  }
  return std::sqrt(sq / static_cast<double>(n));
}

// D1 of a Yeoh or Mooney–Rivlin material with shear modulus mu and ν.
double compliance(double mu, double nu) { return 3.0 * (1.0 - 2.0 * nu) / (mu * (1.0 + nu)); }

TEST(HomogeneousFit, EcoflexWithDefaultsMatchesThePublishedFits) {
  // The bundled Ecoflex 00-30 data (measured; trains on tests A1 and A2,
  // validates on B1) against the fits its source publishes for the same
  // material (incompressible; evaluated here with ν = 0.4999, which changes
  // their RMS errors by under 1%). The source fitted all ten of its tests,
  // B1 among them; palpa's fits see A1 and A2 only.
  //
  // Measured with the defaults (ν kept in 0.45–0.4999, the Ogden starts): RMS
  // error train / validate [kPa], palpa against the published parameters:
  //   yeoh     1.39 / 1.90   against 2.41 / 1.33
  //   ogden 1  3.29 / 3.24   against 3.70 / 2.92
  //   ogden 2  0.63 / 1.59   against 2.61 / 1.55
  // Training: at or below the published fit's RMS. Validation: within 10% for
  // Ogden-2; Yeoh and Ogden-1 fitted to A alone predict B1 worse than fits
  // that saw B1 (bounds 1.5× and 1.15× of the published, measured 1.43× and
  // 1.11×). ν at or above 0.45 in every fit.
  const Dataset d = read_dataset(palpa::test::source_path("examples/fit/ecoflex30/dataset-homogeneous.json"));
  struct Case {
    const char* model;
    int terms;
    std::shared_ptr<material::Material> published;
    double validate_factor;
  };
  const double nu = 0.4999;
  const std::vector<Case> cases{
      {"yeoh", 0,
       std::make_shared<material::IsochoricInvariant>(material::IsochoricInvariant::yeoh(
           14.6899960308889e3, -0.1943757158057544e3, 0.3107486648843412e3, compliance(2 * 14.6899960308889e3, nu))),
       1.5},
      {"ogden", 1,
       std::make_shared<material::Ogden>(std::vector{14.202303878777826e3}, std::vector{3.9700359985056353}, nu),
       1.15},
      {"ogden", 2,
       std::make_shared<material::Ogden>(std::vector{0.11597852052455487e3, 21.929799010391598e3},
                                         std::vector{10.61399087811772, 2.6050267697526204}, nu),
       1.10}};
  for (const Case& c : cases) {
    FitOptions o;
    o.model = c.model;
    if (c.terms > 0) o.ogden_terms = c.terms;
    const GuessResult g = fit_dataset(d, o).guesses.at(0);
    const std::string name = std::string(c.model) + (c.terms ? std::to_string(c.terms) : "");
    const double train = rms_of_role(d, *g.material, CurveRole::Train);
    const double validate = rms_of_role(d, *g.material, CurveRole::Validate);
    const double train_published = rms_of_role(d, *c.published, CurveRole::Train);
    const double validate_published = rms_of_role(d, *c.published, CurveRole::Validate);
    RecordProperty(name + "_rms_train_Pa", std::to_string(train));
    RecordProperty(name + "_rms_validate_Pa", std::to_string(validate));
    RecordProperty(name + "_published_rms_train_Pa", std::to_string(train_published));
    RecordProperty(name + "_published_rms_validate_Pa", std::to_string(validate_published));
    EXPECT_LE(train, train_published) << name;
    EXPECT_LE(validate, c.validate_factor * validate_published) << name;
    EXPECT_GE(material::small_strain_constants(*g.material).poisson(), 0.45) << name;
  }
}

TEST(HomogeneousFit, EcoflexCompressionBetweenFrictionlessPlatensIsTheHomogeneousFit) {
  // The shipped compression dataset (platen travel against force, the same
  // tests as the stress–stretch curves): between frictionless platens the
  // sample is in homogeneous uniaxial stress, so the compression fit is the
  // stress fit scaled by the area π R² — the same parameters (to the
  // optimizer's tolerance: E within 0.1%) and the RMS error times the area
  // (the force and stress files come from the same rows of the source:
  // within 1%). It used to stop at 55.8% compression in the FEM.
  const Dataset force = read_dataset(palpa::test::source_path("examples/fit/ecoflex30/dataset.json"));
  const Dataset stress = read_dataset(palpa::test::source_path("examples/fit/ecoflex30/dataset-homogeneous.json"));
  FitOptions o;
  o.model = "yeoh";
  const GuessResult gf = fit_dataset(force, o).guesses.at(0);
  const GuessResult gs = fit_dataset(stress, o).guesses.at(0);
  const double ef = material::small_strain_constants(*gf.material).young();
  const double es = material::small_strain_constants(*gs.material).young();
  EXPECT_NEAR(ef, es, 1e-3 * es);
  const double area = std::numbers::pi * 25e-3 * 25e-3;
  const double rms_force = rms_of_role(force, *gf.material, CurveRole::Train);
  const double rms_stress = rms_of_role(stress, *gs.material, CurveRole::Train);
  RecordProperty("rms_force_N", std::to_string(rms_force));
  RecordProperty("rms_stress_times_area_N", std::to_string(rms_stress * area));
  EXPECT_NEAR(rms_force, rms_stress * area, 0.01 * rms_stress * area);
}

TEST(HomogeneousFit, StageTwoNeverStartsWorseThanStageOne) {
  // Stage 2 starts at stage 1's material projected into the model (the same
  // material where the model contains the neo-Hookean); where a model has
  // several starts, the one it goes on from is the best after a few
  // iterations. Either way its first ε is at most stage 1's (up to the
  // rounding of the projection, 1e-9).
  const Dataset d = read_dataset(palpa::test::source_path("examples/fit/ecoflex30/dataset-homogeneous.json"));
  for (const char* model :
       {"neo-hookean", "neo-hookean-volume", "neo-hookean-isochoric", "mooney-rivlin", "yeoh", "ogden", "spline"}) {
    for (const int terms : {1, 2, 3}) {
      if (terms > 1 && std::string(model) != "ogden") continue;
      FitOptions o;
      o.model = model;
      o.ogden_terms = terms;
      o.max_iterations = 3;
      for (const int starts : {1, 0}) {
        o.starts = starts;
        const GuessResult g = fit_dataset(d, o).guesses.at(0);
        ASSERT_FALSE(g.history.empty()) << model;
        EXPECT_LE(g.history.front().objective, g.objective_stage1 * (1.0 + 1e-9))
            << model << " terms " << terms << " starts " << starts;
      }
    }
  }
}

}  // namespace
}  // namespace palpa::fit
