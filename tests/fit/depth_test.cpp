// SPDX-License-Identifier: AGPL-3.0-or-later
// Layer-depth search: curves made at layer depth 5 mm with three punch radii;
// seven guesses from 3 to 9 mm, each fitted for the modulus (neo-Hookean with
// the true ν): the best guess is 5 mm and its objective is well below its
// neighbours'.
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "fit/fit_fixtures.hpp"
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

}  // namespace
}  // namespace palpa::fit
