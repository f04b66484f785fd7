// SPDX-License-Identifier: AGPL-3.0-or-later
// The optimizer's longer runs (Release build, label physics): the cushion on
// a rigid slab lowers φ at every iteration, carries the load and keeps its
// mirror symmetry; on a foam slab the rest shape is designed too; a run
// resumed from its checkpoint ends where the uninterrupted one ends; a
// design started from a baseline is placed as the baseline's score is.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/test_support.hpp"
#include "design_fixtures.hpp"
#include "palpa/core/json.hpp"
#include "palpa/design/scene.hpp"
#include "palpa/mesh/surface_check.hpp"

namespace palpa::design {
namespace {

using namespace fixture;

TEST(DesignOptimizer, LowersTheScoreMonotonicallyAndStillCarriesTheLoad) {
  // The cushion, hanging 6 mm lower in the middle, on a flat slab: the
  // pressure peaks under its centre until the slab is hollowed out.
  const SurfaceMesh s = slab(15);
  const DesignResult r = cushion_design(s, DesignMethod::ConjugateGradient, 12, 0);
  ASSERT_EQ(r.iterations, 12) << r.stop.detail;
  EXPECT_EQ(r.stop.termination, Termination::IterationLimit) << r.stop.detail;
  EXPECT_EQ(r.final.phi, r.history.back().phi);
  EXPECT_LT(r.final.zeta, 0.5 * r.initial.zeta);
  EXPECT_LT(r.final.body().score.body_smoothed.maxCoeff(), 0.8 * r.initial.body().score.body_smoothed.maxCoeff());
  EXPECT_GT(r.final.body().score.body_contacts, r.initial.body().score.body_contacts);
  // The optimized slab still carries the load.
  EXPECT_LT(r.final.body().rest.balance_error, 0.005);
  EXPECT_NEAR(r.final.body().rest.contact_force.z(), -r.final.body().rest.load.z(), 0.005 * std::abs(r.final.body().rest.load.z()));
  // Only the design region moved, along its normals (vertical here).
  const Eigen::MatrixX3d moved = r.final.support - s.V;
  EXPECT_LT(moved.leftCols(2).cwiseAbs().maxCoeff(), 1e-15);
  // Symmetry: body and slab are their own mirror images in the plane x = y
  // (the tet mesh's Kuhn cubes and the slab's diagonals included), and the
  // optimized slab stays so. Not to rounding: where a contact point lies on
  // the mirror plane at a convex edge, its two triangles tie as the closest
  // feature and the one taken is a matter of numbering; over 12 iterations
  // that leaves about 3% (an optimizer blind to symmetry would leave O(1)).
  EXPECT_LT(mirror_asymmetry(s, moved), 0.08);
}

TEST(DesignOptimizer, ShapesADeformableSupportToo) {
  // The cushion on a firm foam slab (E 200 kPa, ten times the body's):
  // L-BFGS over the slab's rest shape. The foam already spreads the load
  // and its own vertices press back on the body's skin, so there is less to
  // gain than on the rigid slab (20% in 6 iterations against 48%; the
  // gradient still matches differences at the end).
  const SurfaceMesh s = foam_slab(15);
  const DesignResult r = cushion_design(s, DesignMethod::Lbfgs, 6, 0, 200e3);
  ASSERT_GE(r.iterations, 3) << r.stop.detail;
  // L-BFGS stops by its function tolerance (at iteration 5), told apart from
  // its other tests by the figures of its last iteration.
  EXPECT_EQ(r.stop.termination, Termination::Converged) << r.stop.detail;
  EXPECT_LT(r.final.zeta, 0.9 * r.initial.zeta);
  EXPECT_LT(r.final.body().score.body_smoothed.maxCoeff(), r.initial.body().score.body_smoothed.maxCoeff());
  // Body, slab and ground balance: the contact carries the load and the
  // slab's base carries the contact.
  const double load = std::abs(r.final.body().rest.load.z());
  EXPECT_LT(r.final.body().rest.balance_error, 0.005);
  EXPECT_NEAR(r.final.body().rest.support_base_force.z(), load, 0.005 * load);
  EXPECT_GT(r.final.body().rest.support_max_displacement, 1e-4);
  EXPECT_GT(r.final.body().rest.support_min_det_f, 0.5);
  // Only the top moved, vertically.
  const Eigen::MatrixX3d moved = r.final.support - s.V;
  EXPECT_LT(moved.leftCols(2).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_GT(moved.col(2).cwiseAbs().maxCoeff(), 1e-5);
}

TEST(DesignOptimizer, ResumesExactlyFromItsCheckpoint) {
  const SurfaceMesh s = slab();
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "palpa_design_resume";
  std::filesystem::create_directories(dir);
  DesignOptions o;
  o.method = DesignMethod::ConjugateGradient;
  o.checkpoint = dir / "checkpoint.json";
  std::filesystem::remove(o.checkpoint);
  o.max_iterations = 4;
  DesignResult straight;
  {
    DesignOptions a = o;
    a.checkpoint.clear();
    ShapeOptimizer opt(on_linear_tets(block()), s, options(), top_inside(s), a);
    straight = opt.run();
  }
  ASSERT_EQ(straight.iterations, 4) << straight.stop.detail;
  {
    DesignOptions a = o;
    a.max_iterations = 2;
    ShapeOptimizer opt(on_linear_tets(block()), s, options(), top_inside(s), a);
    EXPECT_EQ(opt.run().iterations, 2);
  }
  DesignOptions b = o;
  b.resume = true;
  ShapeOptimizer opt(on_linear_tets(block()), s, options(), top_inside(s), b);
  const DesignResult resumed = opt.run();
  EXPECT_TRUE(resumed.resumed);
  EXPECT_EQ(resumed.iterations, 4);
  ASSERT_EQ(resumed.history.size(), straight.history.size());
  EXPECT_EQ(resumed.final.phi, straight.final.phi);
  EXPECT_EQ((resumed.final.support - straight.final.support).cwiseAbs().maxCoeff(), 0.0);
  // A checkpoint of another design is refused.
  DesignOptions c = b;
  c.normal_only = true;
  ShapeOptimizer other(on_linear_tets(block()), s, options(), top_inside(s), c);
  EXPECT_THROW(other.run(), Error);
  std::filesystem::remove_all(dir);
}

TEST(DesignScene, AStartFromABaselineIsPlacedAsItsScoreIsPlaced) {
  // The chair from its default start, the thesis's negative image (§7.5.1:
  // pressed 5 cm, the rim smoothed). The deep press brings the body's clipped
  // faces below the block's top, whose creases the remesh once left as
  // zero-area caps and folded triangles: the hollow must be a clean closed
  // surface. The body, sunk into it with its clearance, has skin vertices
  // inside the smoothed hollow's walls; the baseline's score lifts it clear,
  // and so does the start (once refused as starting inside "the support",
  // the scene's box).
  const std::filesystem::path file = test::source_path("examples/design/chair/scene.json");
  const Json doc = read_json_file(file);
  ASSERT_EQ(doc["design"]["start"], "negative image 5 cm (thesis)");
  const DesignScene s = read_design_scene(doc, file, false);
  EXPECT_NEAR(s.start_lift, 2.28e-3, 0.05e-3);  // the case it must handle (the baseline's score: 2.28 mm)
  EXPECT_EQ(rest::lift_clear_of(s.rest.body, s.rest.support, -s.rest.options.gravity, 0.0), 0.0);
  EXPECT_NE(s.rest.options.support_name.find("the baseline 'negative image 5 cm (thesis)'"), std::string::npos)
      << s.rest.options.support_name;
  const SurfaceMesh& hollow = s.rest.support;
  EXPECT_NO_THROW(mesh::check_closed_surface(hollow, "the negative image"));
  // The block's top stays at z = 0 (Taubin's inflating step lifts the rim by
  // well under a millimetre); the hollow's floor lies the press and the 2 mm
  // clearance below the top (the body first touches the flat top at its
  // lowest point), to the remesh's sagitta.
  EXPECT_NEAR(hollow.V.col(2).maxCoeff(), 0.0, 1e-3);
  double deepest = 0.0;
  for (Eigen::Index i = 0; i < hollow.V.rows(); ++i) {
    // Inside the block's footprint (500 mm square about y = −80 mm), above
    // its bottom: the hollow and the top.
    const bool inside = std::abs(hollow.V(i, 0)) < 0.24 && std::abs(hollow.V(i, 1) + 0.08) < 0.24 &&
                        hollow.V(i, 2) > -0.19;
    if (inside) deepest = std::min(deepest, hollow.V(i, 2));
  }
  EXPECT_NEAR(deepest, -0.052, 2e-3);
}

}  // namespace
}  // namespace palpa::design
