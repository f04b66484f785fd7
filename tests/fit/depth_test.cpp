// SPDX-License-Identifier: AGPL-3.0-or-later
// Layer-depth search: curves made at layer depth 5 mm with three punch radii;
// seven guesses from 3 to 9 mm, each fitted for the modulus (neo-Hookean with
// the true ν): the best guess is 5 mm and its objective is well below its
// neighbours'.
#include <gtest/gtest.h>

#include <cmath>

#include "common/test_support.hpp"
#include "fit/fit_fixtures.hpp"
#include "palpa/core/interrupt.hpp"
#include "palpa/fit/fit.hpp"
#include "palpa/material/models.hpp"

namespace palpa::fit {
namespace {

using palpa::test::ScratchDir;

// ε at the neighbouring guesses (4 and 6 mm) over ε at 5 mm.
constexpr double kNeighbourFactor = 5.0;  // measured 8.8 (6 mm) and 10.7 (4 mm)

TEST(DepthSearch, FindsTheLayerDepth) {
  ScratchDir dir;
  test::IndentationSpec spec;
  spec.true_depth = 5e-3;
  spec.layer_depth = Json{{"from", "3 mm"}, {"to", "9 mm"}, {"count", 7}};
  spec.train_radii = {2e-3, 3e-3, 4e-3};
  spec.max_depth = 1.2e-3;
  spec.points = 10;
  spec.mesh_level = 1;
  spec.salt = 7;
  const test::Synthetic data = test::write_indentation_dataset(dir.path(), material::NeoHookean(20e3, 0.45), spec);
  const Dataset d = read_dataset(data.dataset);
  ASSERT_EQ(d.layer_depths.size(), 7u);
  FitOptions o;
  o.model = "neo-hookean";
  o.modulus_only = true;
  o.depth_from = DepthFrom::WholeCurves;  // every guess fitted: the profile over all of them
  o.simulation.mesh_level = spec.mesh_level;
  o.simulation.steps = 10;
  const FitResult r = fit_dataset(d, o);
  ASSERT_EQ(r.guesses.size(), 7u);
  for (const auto& g : r.guesses) {
    RecordProperty("objective_at_" + std::to_string(static_cast<int>(std::lround(g.layer_depth * 1e3))) + "mm",
                   std::to_string(g.objective_final));
    EXPECT_TRUE(g.done);
  }
  EXPECT_EQ(r.best, 2u);
  EXPECT_NEAR(r.guesses[r.best].layer_depth, 5e-3, 1e-12);
  const double best = r.guesses[2].objective_final;
  EXPECT_GT(r.guesses[1].objective_final, kNeighbourFactor * best);
  EXPECT_GT(r.guesses[3].objective_final, kNeighbourFactor * best);
  // ε grows away from the true depth on both sides.
  for (std::size_t g = 0; g + 1 < 2; ++g) EXPECT_GT(r.guesses[g].objective_final, r.guesses[g + 1].objective_final);
  for (std::size_t g = 3; g + 1 < 7; ++g) EXPECT_LT(r.guesses[g].objective_final, r.guesses[g + 1].objective_final);
  // At the true depth the modulus comes back (E = 20 kPa within 2%).
  EXPECT_NEAR(material::small_strain_constants(*r.guesses[2].material).young(), 20e3, 0.02 * 20e3);
}

// Three frictionless punches (2, 3, 4 mm) 1.5 mm into a layer 5 mm deep,
// searched from 3 to 7 mm.
test::IndentationSpec frictionless_punches_on_5mm(int points, int mesh_level) {
  test::IndentationSpec spec;
  spec.true_depth = 5e-3;
  spec.layer_depth = Json{{"from", "3 mm"}, {"to", "7 mm"}, {"count", 5}};
  spec.train_radii = {2e-3, 3e-3, 4e-3};
  spec.max_depth = 1.5e-3;
  spec.points = points;
  spec.mesh_level = mesh_level;
  spec.contact = axisym::PunchContact::Frictionless;
  return spec;
}

TEST(DepthSearch, TheSmallIndentationsChooseTheDepthWhereTheLawCannotFollowTheDeepPart) {
  // Curves of a strongly stiffening Yeoh layer 5 mm deep, fitted with a
  // neo-Hookean (ν held at the truth's): a law that cannot follow the deep
  // part. On the small indentations (d ≤ 0.1 min(a, 3 mm): the linear
  // response, where the law matters least) the depth comes out right; fitted
  // on every point the neo-Hookean makes up for the missing stiffening with a
  // different layer. Measured: small indentations choose 5 mm (E 59.2 kPa
  // against the truth's 58.8), the whole curves 7 mm.
  ScratchDir dir;
  test::IndentationSpec spec = frictionless_punches_on_5mm(40, 1);
  spec.noise_rel = 0.002;  // a gauge good to 0.2% of its largest force (and 0.2 mN)
  spec.noise_abs = 2e-4;
  spec.salt = 5;
  const auto truth = material::IsochoricInvariant::yeoh(10e3, 8e3, 4e3, 3.0 * (1.0 - 2.0 * 0.47) / (20e3 * 1.47));
  spec.poisson = material::small_strain_constants(truth).poisson();
  const test::Synthetic data = test::write_indentation_dataset(dir.path(), truth, spec);
  const Dataset d = read_dataset(data.dataset);
  FitOptions o;
  o.model = "neo-hookean";
  o.fixed = {"nu"};
  o.simulation.mesh_level = spec.mesh_level;
  o.simulation.steps = 15;
  const FitResult small = fit_dataset(d, o);
  ASSERT_TRUE(small.small_profile.has_value());
  // (E of the small indentations' modulus: the neo-Hookean fitted on every
  // point at that depth is stiffer, buying the deep stiffening)
  const double young = small.small_profile->young[small.best];
  RecordProperty("small_depth_mm", std::to_string(small.guesses[small.best].layer_depth * 1e3));
  RecordProperty("small_young_Pa", std::to_string(young));
  EXPECT_NEAR(small.guesses[small.best].layer_depth, 5e-3, 1e-12);
  EXPECT_NEAR(young, 58.8e3, 0.03 * 58.8e3);  // E = 2μ(1 + ν), μ = 2 C10 = 20 kPa, ν = 0.47
  // Only the chosen depth is fitted on every point.
  for (std::size_t g = 0; g < small.guesses.size(); ++g) {
    EXPECT_EQ(std::isfinite(small.guesses[g].objective_final), g == small.best) << g;
  }
  const Estimate* depth = small.uncertainty.find("layer_depth");
  ASSERT_NE(depth, nullptr);
  EXPECT_LT(depth->lo, 5e-3);
  EXPECT_GT(depth->hi, 5e-3);
  o.depth_from = DepthFrom::WholeCurves;
  const FitResult whole = fit_dataset(d, o);
  RecordProperty("whole_depth_mm", std::to_string(whole.guesses[whole.best].layer_depth * 1e3));
  EXPECT_FALSE(whole.small_profile.has_value());
  EXPECT_GT(whole.guesses[whole.best].layer_depth, 5.5e-3);  // why the small indentations choose
}

// An interrupt anywhere in a depth search (the small-indentation profile runs
// stage 1 at every depth in parallel, each over its curves in parallel; then
// the chosen depth's stages) ends the fit with the interrupt, never a crash:
// no loop nested in another is cancelled behind its back.
TEST(DepthSearch, AnInterruptAnywhereEndsTheFitWithTheInterrupt) {
  ScratchDir dir;
  test::IndentationSpec spec = frictionless_punches_on_5mm(30, 0);
  spec.salt = 3;
  const test::Synthetic data = test::write_indentation_dataset(dir.path(), material::NeoHookean(20e3, 0.45), spec);
  const Dataset d = read_dataset(data.dataset);
  FitOptions o;
  o.model = "neo-hookean";
  o.fixed = {"nu"};
  o.simulation.mesh_level = spec.mesh_level;
  o.simulation.steps = 6;
  int interrupted = 0;
  for (long n : {1L, 4L, 12L, 30L, 70L, 150L, 300L}) {
    request_interrupt_at_check(n);
    try {
      (void)fit_dataset(d, o);
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::Interrupted) << "at check " << n << ": " << e.what();
      ++interrupted;
    }
    clear_interrupt();
  }
  EXPECT_GE(interrupted, 6);
  const FitResult r = fit_dataset(d, o);  // and a fit after them runs as usual
  ASSERT_TRUE(r.small_profile.has_value());
  EXPECT_NEAR(r.guesses[r.best].layer_depth, 5e-3, 1e-12);
}

}  // namespace
}  // namespace palpa::fit
