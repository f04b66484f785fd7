// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Shared set-up of the indentation tests: a 2 mm punch on a 10 kPa layer.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/finite_difference.hpp"
#include "palpa/axisym/poke.hpp"

namespace palpa::axisym::test {

inline constexpr double kE = 10e3;  // Young's modulus [Pa]
inline constexpr double kA = 2e-3;  // punch radius [m]

inline PokeSetup setup_for(double thickness, int level, PunchContact contact) {
  PokeSetup s;
  s.geometry.punch_radius = kA;
  s.geometry.thickness = thickness;
  s.mesh_level = level;
  s.contact = contact;
  return s;
}

// The force at `depth` reached in `steps` increments [N].
inline double force_at(const material::Material& m, const PokeSetup& s, double depth, int steps = 1) {
  PokeSimulator sim(m, s);
  PokeOptions o;
  o.max_depth = depth;
  o.steps = steps;
  return sim.run(o).samples.back().force;
}

// Checks the curve's dF/dθ (c, run with sensitivities by `sim`) against
// central differences of whole curves, for about six parameters spread over
// θ; h = 1e-5 of the parameter (moduli: at least of `modulus`). Leaves `sim`
// at the original parameters.
inline void expect_curve_sensitivities(PokeSimulator& sim, const PokeCurve& c, PokeOptions o, double modulus,
                                       const std::string& what) {
  const material::Material& m = sim.model().material();
  o.sensitivities = false;
  const Eigen::VectorXd theta = m.params();
  for (Eigen::Index k = 0; k < theta.size(); k += std::max<Eigen::Index>(1, theta.size() / 6)) {
    const double h = 1e-5 * std::max(std::abs(theta[k]), m.param_info(k).dimension == Dimension::Pressure ? modulus : 1.0);
    std::vector<double> fp;
    std::vector<double> fm;
    for (double sign : {1.0, -1.0}) {
      Eigen::VectorXd t = theta;
      t[k] += sign * h;
      sim.set_material_params(t);
      const PokeCurve cc = sim.run(o);
      for (const auto& sample : cc.samples) (sign > 0 ? fp : fm).push_back(sample.force);
    }
    sim.set_material_params(theta);
    Eigen::VectorXd analytic(static_cast<Eigen::Index>(c.samples.size()));
    Eigen::VectorXd numeric(analytic.size());
    for (std::size_t i = 0; i < c.samples.size(); ++i) {
      analytic[static_cast<Eigen::Index>(i)] = c.samples[i].dforce_dparams[k];
      numeric[static_cast<Eigen::Index>(i)] = (fp[i] - fm[i]) / (2 * h);
    }
    const double scale = std::abs(theta[k]) > 0 ? std::abs(theta[k]) : 1.0;
    EXPECT_TRUE(palpa::test::derivatives_match(analytic * scale, numeric * scale, 1e-4,
                                               palpa::test::ZeroPolicy::MayBeZero, 1e-3 * c.samples.back().force))
        << what << ", " << m.model() << " parameter " << m.param_info(k).name;
  }
}

}  // namespace palpa::axisym::test

namespace palpa::axisym::test {

// A cylindrical sample between two plates (radius, height [m]).
inline PokeSetup compression_setup(double radius, double height, int level, PunchContact platens) {
  PokeSetup s;
  s.test = PokeTest::Compression;
  s.geometry.punch_radius = radius;
  s.geometry.thickness = height;
  s.mesh_level = level;
  s.contact = platens;
  return s;
}

}  // namespace palpa::axisym::test
