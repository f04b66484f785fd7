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

// A 4 mm flat punch 0.5 mm into a 10 mm layer, frictionless or stuck to the
// surface it presses, 3D against the axisymmetric solver (thesis §6.3.3,
// Fig. 6.7). The 3D body is a quarter of
// the axisymmetric layer itself (R = 22.57 mm, the area of a 40 × 40 mm block,
// free side wall): its cells are the layer's graded (r, z) grid at the same
// mesh level swept around the axis, with a ring of nodes on the punch's rim,
// and springs on surface samples; the two models then differ by their
// elements only, and the axisymmetric force at level 4 is the reference
// (levels 4 and 5 agree within 0.1%).
struct PunchRow {
  double reference = 0.0;
  std::vector<double> force;  // 3D, by level
};

PunchRow flat_punch(double nu, axisym::PunchContact contact, int levels, const char* element = "linear",
                    int first_level = 0) {
  const double d = 5e-4;
  const bool stick = contact == axisym::PunchContact::Stick;
  const material::NeoHookean nh(10e3, nu);
  axisym::PokeSetup setup;
  setup.geometry = {4e-3, 10e-3, 22.57e-3};
  setup.contact = contact;
  setup.mesh_level = 4;
  axisym::PokeSimulator poke(nh, setup);
  axisym::PokeOptions po;
  po.max_depth = d;
  po.steps = 2;
  PunchRow row;
  row.reference = poke.run(po).samples.back().force;

  ScratchDir dir;
  for (int level = first_level; level < levels; ++level) {
    PunchScene p;
    p.body = fmt::format(R"("cylinder": {{"radius": "22.57 mm", "height": "10 mm", "rim": "4 mm", "level": {},
                                          "segments": 48, "sector": "90 deg"}}, "element": "{}")",
                         level, element);
    p.fixed = R"([{"set": "bottom"}, {"set": "sector_start", "components": "y"},
                  {"set": "sector_end", "components": "x"}])";
    p.material = fmt::format(R"({{"model": "neo-hookean", "parameters": {{"E": "10 kPa", "nu": {}}}}})", nu);
    p.shape = R"({"cylinder": {"radius": "4 mm", "height": "10 mm", "segments": 48}})";
    p.depth = "0.5 mm";
    p.steps = 2;
    p.contact = fmt::format(R"({{"max_penetration": "0.002 mm", "sampling": "surface", "subdivisions": 2,
                                 "friction": "{}"}})",
                            stick ? "stick" : "frictionless");
    const Curve c = simulate(read_scene(write_punch_scene(dir, p, fmt::format("level{}.json", level))));
    row.force.push_back(4.0 * c.force.back());
    EXPECT_LE(c.max_penetration, 0.002e-3);
    std::printf("[sim3d] %s, %s, nu %.2f, level %d: F = %.5g N vs axisymmetric %.5g N: %+.2f%%, %.1f s\n",
                element, stick ? "stick" : "frictionless", nu, level, row.force.back(), row.reference,
                100.0 * (row.force.back() / row.reference - 1.0), c.seconds);
  }
  return row;
}

TEST(Indentation3d, FlatPunchOnTheAxisymmetricGridSweptApproachesTheAxisymmetricForce) {
  // Linear tets are stiffer than the axisymmetric quads on the same grid and,
  // at ν 0.3, converge from above (measured at levels 0, 1, 2: frictionless
  // +11.2%, +7.3%, +3.7%; stick +11.0%, +4.2%, +1.6%; level 2 takes 2.5
  // minutes and is left to bench/).
  for (const auto contact : {axisym::PunchContact::Frictionless, axisym::PunchContact::Stick}) {
    const bool stick = contact == axisym::PunchContact::Stick;
    const PunchRow row = flat_punch(0.3, contact, 2);
    const double e0 = row.force[0] / row.reference - 1.0, e1 = row.force[1] / row.reference - 1.0;
    EXPECT_GT(e1, 0.0) << stick;
    EXPECT_LT(e1, stick ? 0.05 : 0.08) << stick;
    EXPECT_LT(e1, (stick ? 0.45 : 0.7) * e0) << stick;
  }
  // ν 0.45, frictionless: linear tets lock (+20% at level 0), and refined the
  // error changes sign (measured +20.4%, +0.5%, −2.7% at levels 0, 1, 2): it is
  // one-signed again only with an element that does not lock.
  const PunchRow firm = flat_punch(0.45, axisym::PunchContact::Frictionless, 2);
  const double e0 = firm.force[0] / firm.reference - 1.0, e1 = firm.force[1] / firm.reference - 1.0;
  EXPECT_LT(std::abs(e1), 0.03);
  EXPECT_LT(std::abs(e1), 0.25 * std::abs(e0));
}

TEST(Indentation3d, NearlyIncompressibleLayerLocksWithLinearTetsNotWithNodalPressure) {
  // ν 0.49, frictionless, level 0: the linear tet is 53% stiff, the
  // nodal-pressure tet 6.3% (measured). Refined it turns soft (level 1:
  // −4.7%, level 2: −6.7%, against linear +9.2% at level 1), in 2.5× the
  // linear tet's time per level: the figures are in bench/.
  const PunchRow linear = flat_punch(0.49, axisym::PunchContact::Frictionless, 1, "linear");
  const PunchRow averaged = flat_punch(0.49, axisym::PunchContact::Frictionless, 1, "nodal-pressure");
  EXPECT_GT(linear.force[0] / linear.reference - 1.0, 0.4);
  EXPECT_LT(std::abs(averaged.force[0] / averaged.reference - 1.0), 0.08);
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
