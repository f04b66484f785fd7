// SPDX-License-Identifier: AGPL-3.0-or-later
// Indentation of a soft block in 3D against what it must match: the
// axisymmetric simulator for a cylinder at the block's centre (thesis §6.3.3,
// Fig. 6.7), a square indenter's monotone force with bounded penetration and no
// inverted element, and local poking against the full mesh (§5.5).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fmt/format.h>

#include "common/test_support.hpp"
#include "palpa/axisym/poke.hpp"
#include "palpa/material/models.hpp"
#include "palpa/sim3d/run.hpp"
#include "scene_fixtures.hpp"

namespace palpa::sim3d {
namespace {

using palpa::test::ScratchDir;
using test::PunchScene;
using test::write_punch_scene;

struct Curve {
  std::vector<double> force;
  double seconds = 0.0;
  int min_contacts = 0;
  double max_penetration = 0.0;
  double min_det_f = 1.0;
};

Curve simulate(const Scene& s) {
  const auto t0 = std::chrono::steady_clock::now();
  Simulation sim(s);
  Curve c;
  c.min_contacts = 1 << 30;
  for (int k = 1; k <= s.steps; ++k) {
    const StepRecord r = sim.solve_step(k);
    c.force.push_back(r.obstacles[0].indentation_force);
    c.min_contacts = std::min(c.min_contacts, r.obstacles[0].contacts);
    c.max_penetration = std::max(c.max_penetration, r.obstacles[0].max_penetration);
    c.min_det_f = std::min(c.min_det_f, r.min_det_f);
  }
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return c;
}

TEST(Indentation3d, CylinderApproachesTheAxisymmetricForceAsMeshesRefine) {
  // A quarter of a 50 × 50 × 10 mm block (symmetry planes x = 0, y = 0), a
  // frictionless 5 mm punch 0.5 mm deep; the axisymmetric layer has the
  // block's area (R = 28.2 mm).
  const double d = 5e-4;
  const material::NeoHookean nh(10e3, 0.3);
  axisym::PokeSetup setup;
  setup.geometry = {5e-3, 10e-3, 50e-3 / std::sqrt(std::numbers::pi)};
  setup.contact = axisym::PunchContact::Frictionless;
  setup.mesh_level = 3;
  axisym::PokeSimulator poke(nh, setup);
  axisym::PokeOptions po;
  po.max_depth = d;
  po.steps = 2;
  const double reference = poke.run(po).samples.back().force;

  ScratchDir dir;
  std::vector<double> errors, forces;
  for (const char* cells : {"[10, 10, 4]", "[20, 20, 8]"}) {
    PunchScene p;
    p.size_mm = R"(["25 mm", "25 mm", "10 mm"])";
    p.cells = cells;
    p.shape = R"({"cylinder": {"radius": "5 mm", "height": "10 mm", "segments": 96}})";
    p.depth = "0.5 mm";
    p.steps = 2;
    p.contact = R"({"max_penetration": "0.002 mm"})";
    std::string text = test::punch_scene_json(p);
    // The quarter block: x, y ≥ 0 with the two symmetry planes on rollers.
    text.replace(text.find(R"("fixed": [{"set": "bottom"}])"), 28,
                 R"("fixed": [{"set": "bottom"}, {"set": "xmin", "components": "x"}, {"set": "ymin", "components": "y"}])");
    const auto file = dir.write(fmt::format("quarter{}.json", errors.size()), text);
    // The box is centred: move it to x, y ≥ 0 (its vertex sets move along).
    Scene s = read_scene(file);
    s.mesh.V.col(0).array() += 0.0125;
    s.mesh.V.col(1).array() += 0.0125;
    const Curve c = simulate(s);
    const double quarter = 4.0 * c.force.back();
    forces.push_back(quarter);
    errors.push_back(std::abs(quarter - reference) / reference);
    std::printf("[sim3d] cells %s: F = %.5g N (x4) vs axisymmetric %.5g N: %.2f%%, %.1f s\n", cells, quarter,
                reference, 100.0 * errors.back(), c.seconds);
  }
  // Node-to-surface contact sees the punch through the nodes under it, so the
  // 3D force converges from below at first order in the cell size (measured:
  // 26% at 2.5 mm cells, 10.5% at 1.25 mm). Extrapolating the two levels at
  // first order lands within 5% of the axisymmetric force.
  EXPECT_LT(forces[0], forces[1]);
  EXPECT_LT(forces[1], reference);
  EXPECT_LT(errors[1], 0.5 * errors[0]);
  EXPECT_LT(errors[1], 0.12);
  const double extrapolated = 2.0 * forces[1] - forces[0];
  std::printf("[sim3d] first-order extrapolation: %.5g N (%.2f%% from the axisymmetric force)\n", extrapolated,
              100.0 * (extrapolated - reference) / reference);
  EXPECT_NEAR(extrapolated, reference, 0.06 * reference);
}

TEST(Indentation3d, SquareIndenterForceIsMonotoneWithBoundedPenetration) {
  ScratchDir dir;
  PunchScene p;
  p.size_mm = R"(["30 mm", "30 mm", "10 mm"])";
  p.cells = "[12, 12, 4]";
  p.shape = R"({"box": {"size": ["8 mm", "8 mm", "5 mm"], "divisions": 4}})";
  p.depth = "3 mm";
  p.steps = 6;
  p.contact = R"({"max_penetration": "0.02 mm"})";
  const Curve c = simulate(read_scene(write_punch_scene(dir, p)));
  for (std::size_t i = 1; i < c.force.size(); ++i) EXPECT_GT(c.force[i], c.force[i - 1]) << i;
  EXPECT_GT(c.force.front(), 0.0);
  EXPECT_LE(c.max_penetration, 0.02e-3);
  EXPECT_GT(c.min_det_f, 0.0);
  EXPECT_GE(c.min_contacts, 9);
}

TEST(Indentation3d, LocalPokeMatchesTheFullBlock) {
  // A 4 mm punch 1 mm into an 80 × 80 × 10 mm block: the full block vs the
  // tets within 10 mm of the punch with the cut held fixed.
  ScratchDir dir;
  PunchScene p;
  p.size_mm = R"(["80 mm", "80 mm", "10 mm"])";
  p.cells = "[32, 32, 4]";
  p.shape = R"({"cylinder": {"radius": "4 mm", "height": "10 mm", "segments": 48}})";
  p.depth = "1 mm";
  p.steps = 2;
  p.contact = R"({"max_penetration": "0.01 mm"})";
  const Curve full = simulate(read_scene(write_punch_scene(dir, p)));
  p.extra = R"(, "local": {"margin": "10 mm"})";
  const Scene ls = read_scene(write_punch_scene(dir, p, "local.json"));
  Simulation probe(ls);
  const double kept = static_cast<double>(probe.model().num_elements()) / static_cast<double>(ls.mesh.T.rows());
  const Curve local = simulate(ls);
  const double error = std::abs(local.force.back() - full.force.back()) / full.force.back();
  std::printf("[sim3d] local poke: %.1f%% of the tets, force %.5g vs %.5g N (%.2f%%), %.2f s vs %.2f s\n",
              100.0 * kept, local.force.back(), full.force.back(), 100.0 * error, local.seconds, full.seconds);
  EXPECT_LT(kept, 0.3);
  EXPECT_LT(error, 0.05);
}

}  // namespace
}  // namespace palpa::sim3d
