// SPDX-License-Identifier: AGPL-3.0-or-later
// The indentation simulator against its analytic limits, its far-field and
// mesh convergence, and deep indentation (label "physics": Release only).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
#include <random>

#include "axisym/layer_reference.hpp"
#include "common/finite_difference.hpp"
#include "common/test_support.hpp"
#include "palpa/axisym/poke.hpp"
#include "axisym/poke_fixtures.hpp"
#include "palpa/core/interrupt.hpp"
#include "palpa/material/models.hpp"
#include "palpa/material/spline_material.hpp"

namespace palpa::axisym {
namespace {

using palpa::test::derivatives_match;
using namespace palpa::axisym::test;



// ---------------------------------------------------------------- analytic limits

TEST(PokePhysics, SmallDepthOnADeepLayerMatchesTheHalfSpace) {
  // Boussinesq/Sneddon: F/d = 2aE/(1 − ν²) for a frictionless punch on a
  // half-space. With D = 100 a the layer adds < 1% (κ(0.01) − 1), so the
  // force is checked against the layer's own analytic stiffness, at the
  // default mesh (level 2 extrapolated with level 1).
  for (double nu : {0.3, 0.45}) {
    const material::NeoHookean m(kE, nu);
    const double d = 1e-4 * kA;
    const double f = force_at(m, setup_for(100 * kA, 2, PunchContact::Frictionless), d);
    const double half_space = 2 * kA * kE / (1 - nu * nu);
    const double layer = palpa::test::layer_stiffness(kA, 100 * kA, kE, nu);
    RecordProperty("error_nu" + std::to_string(nu), std::to_string(f / d / layer - 1));
    EXPECT_NEAR(f / d / half_space, 1.0, 0.01) << "nu " << nu;
    EXPECT_NEAR(f / d / layer, 1.0, 0.003) << "nu " << nu;
  }
}

TEST(PokePhysics, BondedLayerMatchesHayesEtAl1972) {
  // Hayes, Keer, Herrmann & Mockros, J. Biomech. 5 (1972) 541–551: frictionless
  // punch on a layer bonded to a rigid base, P = 4aGwκ(a/h, ν)/(1 − ν); κ from
  // tests/axisym/layer_reference (checked against their Table 1 there). The
  // default mesh (level 2 extrapolated with level 1) is within 0.3%; level 2
  // alone is about 1% stiff.
  for (double nu : {0.3, 0.45, 0.49}) {
    for (double a_over_h : {0.3, 1.0, 2.0}) {
      const material::NeoHookean m(kE, nu);
      const double thickness = kA / a_over_h;
      const double d = 1e-4 * kA;
      PokeSetup s = setup_for(thickness, 2, PunchContact::Frictionless);
      const double ref = palpa::test::layer_stiffness(kA, thickness, kE, nu);
      const double error = force_at(m, s, d) / d / ref - 1;
      s.extrapolate = false;
      const double single = force_at(m, s, d) / d / ref - 1;
      RecordProperty(fmt::format("error_nu{}_aoverh{}", nu, a_over_h), fmt::format("{:.5f} (level 2 alone {:.5f})", error, single));
      EXPECT_LT(std::abs(error), 0.003) << "nu " << nu << ", a/h " << a_over_h;
      EXPECT_GT(single, 0.005) << "nu " << nu << ", a/h " << a_over_h;
    }
  }
}

TEST(PokePhysics, MatchesCalculixQuadraticElementsExtrapolated) {
  // Independent reference: CalculiX CAX8 (quadratic elements) at mesh levels
  // 1–3, Richardson-extrapolated (tests/axisym/calculix/make_reference.py),
  // stick and frictionless, small and moderate depths, against palpa's
  // default force (level 2 extrapolated with level 1) with the same
  // material (CalculiX's NEO HOOKE is palpa's neo-hookean-isochoric).
  std::ifstream in(::palpa::test::source_path("tests/axisym/calculix/cax8_reference.csv"));
  ASSERT_TRUE(in) << "tests/axisym/calculix/cax8_reference.csv";
  std::string line;
  int rows = 0;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      header = false;
      continue;
    }
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 11u) << line;
    const double a = std::stod(cells[1]), thickness = std::stod(cells[2]), nu = std::stod(cells[3]);
    const double depth = std::stod(cells[5]), reference = std::stod(cells[9]), change = std::stod(cells[10]);
    // The reference itself moved by less than a tenth of the tolerance from
    // the coarser extrapolation.
    EXPECT_LT(std::abs(change), 1e-3) << line;
    const double mu = kE / (2 * (1 + nu)), bulk = kE / (3 * (1 - 2 * nu));
    const auto m = material::IsochoricInvariant::neo_hookean(mu / 2, 2 / bulk);
    PokeSetup s;
    s.geometry.punch_radius = a;
    s.geometry.thickness = thickness;
    s.contact = parse_punch_contact(cells[4]);
    const double f = force_at(m, s, depth, 4);
    RecordProperty(fmt::format("error_{}_{}_{}mm", cells[0], cells[4], depth * 1e3), fmt::format("{:.5f}", f / reference - 1));
    EXPECT_NEAR(f / reference, 1.0, 0.003) << line;
    ++rows;
  }
  EXPECT_GE(rows, 7);
}

TEST(PokePhysics, ExtrapolatedForceConvergesAtSecondOrder) {
  // Levels 1–3 extrapolated (each with the level below) against the analytic
  // layer: the first-order error of the sharp rim cancels, so each level cuts
  // the error about fourfold (single levels: about twofold).
  const material::NeoHookean m(kE, 0.45);
  const double d = 1e-4 * kA;
  const double ref = palpa::test::layer_stiffness(kA, kA, kE, 0.45);
  std::vector<double> errors;
  for (int level : {1, 2, 3}) errors.push_back(std::abs(force_at(m, setup_for(kA, level, PunchContact::Frictionless), d) / d / ref - 1));
  RecordProperty("errors", fmt::format("{:.2e} {:.2e} {:.2e}", errors[0], errors[1], errors[2]));
  EXPECT_LT(errors[1], 0.3 * errors[0]);
  EXPECT_LT(errors[2], 0.3 * errors[1]);
  EXPECT_LT(errors[2], 1e-3);
}

TEST(PokePhysics, ExtrapolatedSensitivitiesMatchFiniteDifferences) {
  // 2 dF_L/dθ − dF_{L−1}/dθ against central differences of whole extrapolated
  // curves, deep enough for the rim to wrap (levels 1 and 0; the unit tests
  // check a single mesh).
  const material::NeoHookean nh(kE, 0.45);
  PokeSimulator sim(nh, setup_for(3 * kA, 1, PunchContact::Stick));
  ASSERT_TRUE(sim.extrapolates());
  PokeOptions o;
  o.max_depth = 0.5 * kA;
  o.steps = 5;
  o.sensitivities = true;
  const PokeCurve c = sim.run(o);
  test::expect_curve_sensitivities(sim, c, o, kE, "stick, extrapolated");
}

TEST(PokePhysics, DefaultOuterRadiusIsFarEnough) {
  // Doubling the simulated radius changes the force by less than 0.5%.
  const material::NeoHookean m(kE, 0.45);
  for (double thickness : {kA / 2.0, 3 * kA, 10 * kA}) {
    PokeSetup s = setup_for(thickness, 1, PunchContact::Stick);
    const double f = force_at(m, s, 0.1 * kA, 2);
    s.geometry.outer_radius = 2.0 * default_outer_radius(kA, thickness);
    const double f2 = force_at(m, s, 0.1 * kA, 2);
    EXPECT_NEAR(f / f2, 1.0, 0.005) << "thickness " << thickness;
  }
}

TEST(PokePhysics, SmallStrainForceIsTheSameForEveryModelWithTheSameEAndNu) {
  const double nu = 0.45;
  const material::ElasticConstants l = material::lame_from_young(kE, nu);
  const double d1 = 2.0 / l.bulk();
  const material::NeoHookean nh(kE, nu);
  const material::NeoHookean vol = material::NeoHookean::with_volume_term(kE, nu, 0.5);
  const auto iso = material::IsochoricInvariant::neo_hookean(l.mu / 2, d1);
  const auto mr = material::IsochoricInvariant::mooney_rivlin(0.3 * l.mu, 0.2 * l.mu, d1);
  const auto yeoh = material::IsochoricInvariant::yeoh(l.mu / 2, 0.1 * l.mu, 0.05 * l.mu, d1);
  const material::Ogden og({0.8 * l.mu, 0.4 * l.mu}, {3.0, -1.0}, nu);  // μ0 = ½(2.4 − 0.4) μ = μ
  const material::StVenantKirchhoff stvk(kE, nu);
  const material::Corotational corot(kE, nu);
  const PokeSetup s = setup_for(3 * kA, 1, PunchContact::Stick);
  const double d = 1e-3 * kA;
  const double ref = force_at(nh, s, d);
  EXPECT_GT(ref, 0.0);
  for (const material::Material* m : std::initializer_list<const material::Material*>{
           &vol, &iso, &mr, &yeoh, &og, &stvk, &corot}) {
    EXPECT_NEAR(force_at(*m, s, d) / ref, 1.0, 3e-3) << m->model();
  }
}

// Forces at levels 1..3 for one deep case: every level reaches the depth with
// no inverted element and no surface node inside the punch, and the force
// differences between levels shrink.
void expect_deep_convergence(const material::Material& m, PunchContact contact, double fillet) {
  const double thickness = kA / 0.3;  // d = a is also 0.3 D
  std::vector<double> forces;
  for (int level : {1, 2, 3}) {
    PokeSetup s = setup_for(thickness, level, contact);
    s.fillet_radius = fillet;
    PokeSimulator sim(m, s);
    PokeOptions o;
    o.max_depth = kA;
    o.steps = 20;
    const PokeCurve c = sim.run(o);
    const PokeSample& last = c.samples.back();
    EXPECT_NEAR(last.depth, kA, 1e-15);
    EXPECT_GT(last.min_jacobian, 0.0) << "level " << level;
    // Penetration into the punch: a small fraction of the rim cell.
    EXPECT_LT(last.max_penetration, 0.05 * sim.model().mesh().rim_cell_size) << "level " << level;
    forces.push_back(last.force);
  }
  const double d12 = std::abs(forces[1] - forces[0]);
  const double d23 = std::abs(forces[2] - forces[1]);
  ::testing::Test::RecordProperty("forces", std::to_string(forces[0]) + " " + std::to_string(forces[1]) + " " +
                               std::to_string(forces[2]));
  ::testing::Test::RecordProperty("observed_order", std::to_string(std::log2(d12 / d23)));
  EXPECT_LT(d23, 0.7 * d12) << forces[0] << " " << forces[1] << " " << forces[2];
  EXPECT_LT(d23, 0.03 * forces[2]);
}

TEST(PokePhysicsDeep, StickToDepthEqualToRadiusAndThirtyPercentOfTheLayerNu045) {
  expect_deep_convergence(material::NeoHookean(kE, 0.45), PunchContact::Stick, 0.0);
}

TEST(PokePhysicsDeep, StickToDepthEqualToRadiusAndThirtyPercentOfTheLayerNu049) {
  expect_deep_convergence(material::NeoHookean(kE, 0.49), PunchContact::Stick, 0.0);
}

TEST(PokePhysicsDeep, FrictionlessWithARoundedRimNu045) {
  expect_deep_convergence(material::NeoHookean(kE, 0.45), PunchContact::Frictionless, 0.1 * kA);
}

}  // namespace
}  // namespace palpa::axisym
