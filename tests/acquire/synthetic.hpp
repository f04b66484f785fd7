// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Synthetic poke recordings made from a known force–indentation curve, the way
// the devices of thesis §3.2 would log them: a force gauge and a laser, each
// on its own clock and at its own rate, with sensor noise, a slow drift of each
// reading, hand tremor in the true indentation, and the rest–poke–rest protocol
// of §3.1. Used by the tests and to make examples/acquire.

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "palpa/geometry/mesh.hpp"

namespace palpa::test {

struct SyntheticPoke {
  // The known curve: F(δ) = stiffness·δ + hardening·δ² of the true indentation
  // δ [m] (a preload keeps the "just touching" rest in contact).
  double stiffness = 400.0;    // [N/m]
  double hardening = 2.0e5;    // [N/m²]
  double preload = 0.1e-3;     // δ at rest [m]
  double depth = 5e-3;         // poke depth beyond the rest [m]
  // Protocol [s, true time]: rest, smooth ramp down, smooth ramp up, rest.
  double rest_before = 2.0, ramp_in = 0.6, ramp_out = 0.6, rest_after = 2.0;
  // Devices.
  double force_rate = 200.0;       // [Hz]
  double laser_rate = 1000.0;      // [Hz]
  double force_clock = 0.0;        // force time = true time + this [s]
  double laser_clock = 12.345;     // laser time = true time + this [s]
  double force_lead = 0.3;         // the force log starts this long before the laser log [s]
  double force_noise = 0.01;       // [N] standard deviation
  double laser_noise = 5e-6;       // [m] standard deviation of the distance
  double force_drift = 0.005;      // [N/s]
  double laser_drift = 20e-6;      // [m/s]
  double tremor = 30e-6;           // hand tremor amplitude in δ [m]
  double tremor_hz = 9.0;
  double laser_rest = 60e-3;       // laser distance at rest [m]
  std::uint64_t seed = 1;

  double total() const { return rest_before + ramp_in + ramp_out + rest_after; }
  // The poke's depth beyond the rest at true time t [m] (no tremor).
  double poke(double t) const;
  // The curve the processing must recover: F(x) = F(preload + x) − F(preload).
  double expected_force(double x) const;
  // True time of the maximum force.
  double peak_time() const { return rest_before + ramp_in; }
};

struct SyntheticLogs {
  std::string force_csv;        // time_s,force_N
  std::string laser_csv;        // time_s,voltage_V
  std::string calibration_csv;  // voltage_V,distance_mm (monotone, 21 rows)
};

SyntheticLogs make_poke_logs(const SyntheticPoke& p);

// Ultrasound picks of one tissue interface during the poke of `p`: depth below
// the skin = rest_depth − share·poke(t) (the interface takes `share` of the
// indentation), picked at 0.5, 1.0, 1.5, 1.9 s, every 0.1 s from 2.0 to 3.2 s,
// and at 3.5, 4.0, 4.5 s (true time), written on a clock `clock` ahead:
// time_s,depth_mm.
std::string make_interface_picks(const SyntheticPoke& p, double rest_depth, double share, double clock);
// The true depth of such an interface at true time t [m].
double interface_depth(const SyntheticPoke& p, double rest_depth, double share, double t);

// The laser calibration used: distance = 30 mm + 8 mm/V·V + 0.3 mm/V²·V², V in 0..10 V,
// as a 21-row table (the logs invert the table itself, so it is exact).
std::vector<double> calibration_volts();
std::vector<double> calibration_metres();

// An n×n-cell square grid in the plane z = 0, side `size` [m], centred at the
// origin (two triangles per cell, counter-clockwise seen from +z).
SurfaceMesh plate(int n, double size);
// The mesh as OBJ text (coordinates in metres).
std::string obj_text(const SurfaceMesh& mesh);

// Pressure-sensor recordings: `samples` readings per location of
// ratio(position) × posture_i, and the reference sensor reading posture_i
// (posture_i = 1 + 0.2 sin(1.7 i): the subject leans differently at each
// location), each with a symmetric deterministic ripple of ±`ripple` relative
// (ten levels, so the trimmed means are exact) plus Gaussian noise of `noise`
// relative (0: none).
struct SyntheticPressure {
  std::vector<Eigen::Vector3d> positions;  // [m]
  std::function<double(const Eigen::Vector3d&)> ratio;
  std::size_t samples = 600;
  double ripple = 0.01;
  double noise = 0.0;
  std::uint64_t seed = 1;
  int digits = 17;  // significant digits written
};
// locations.csv (location,x_mm,y_mm,z_mm; ids 1..n).
std::string pressure_locations_csv(const SyntheticPressure& s);
// samples.csv (location,reading_V,reference_V; locations one after another).
std::string pressure_samples_csv(const SyntheticPressure& s);

}  // namespace palpa::test
