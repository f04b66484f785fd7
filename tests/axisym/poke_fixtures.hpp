#pragma once
// Shared set-up of the indentation tests: a 2 mm punch on a 10 kPa layer.

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
