// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Poke logs -> force–indentation curve (thesis §3.1–3.2, `palpa acquire poke`).
//
// A force gauge logs (time, force) and a laser mounted on it logs (time,
// voltage) — or (time, distance) — each on its own clock and at its own rate.
// The laser aims at skin beside the poke, so the laser distance shrinks by
// exactly the indentation while the hand and the body move together.
//
// Steps: read and check both logs; convert the laser voltage to distance with a
// monotone calibration table; resample each log uniformly and low-pass it
// zero-phase; find the poke between the two rest plateaus in each (or take the
// windows given by hand); align the clocks (coarse: the poke starts; fine: the
// shift maximizing the rank correlation of force and minus distance, refined
// by laying the poke's pairs on one curve); resample
// both on one common clock; subtract the rest levels (linear between the
// plateaus, which removes a slow drift and the gauge's offset); take off the
// filter's second-order mixing of nearby indentations (½ F″ times the
// indentation's variance under the filter window); cut the loading part
// (start -> maximum force) and optionally the unloading part (maximum force ->
// end); put each on a uniform indentation grid by local linear fits.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "palpa/acquire/log.hpp"
#include "palpa/acquire/penalized_spline.hpp"
#include "palpa/acquire/signal.hpp"
#include "palpa/report/plot.hpp"

namespace palpa::acquire {

// A poke window given by hand: start and end [s] on one log's own clock.
struct TimeWindow {
  double start = 0.0, end = 0.0;
};

// The most points of a resampled curve (a curve is a few dozen to a few
// hundred; more than the logs hold samples would mean nothing).
inline constexpr std::size_t kMaxCurvePoints = 100000;

struct PokeOptions {
  ColumnSpec force_time{"time", ""}, force_value{"force", ""};
  ColumnSpec laser_time{"time", ""}, laser_value{"voltage", ""};
  // Calibration table columns (input: voltage, output: distance).
  ColumnSpec calibration_voltage{"voltage", ""}, calibration_distance{"distance", ""};
  int order = 4;           // Butterworth order (per pass)
  double cutoff = 5.0;     // [Hz]; a ~1 s poke has little above 2 Hz, hand tremor is 6–12 Hz
  PlateauOptions plateau;  // rest plateau: duration and tolerance
  std::optional<TimeWindow> force_window, laser_window;  // manual override
  LogCheck check;
  double saturation = 0.1;  // [s] a run this long at a log's extreme is clipping
  // Fine alignment searches this fraction of the poke's duration either side of
  // the coarse shift.
  double search = 0.25;
  std::size_t points = 50;  // uniform indentation grid points (3 to kMaxCurvePoints)
  bool tare = true;         // subtract the force's rest level
};

// A curve on a uniform indentation grid.
struct Curve {
  std::vector<double> indentation;  // [m], 0 .. max, uniform
  std::vector<double> force;        // [N]
};

struct PokeResult {
  Log force_log, laser_log;     // as read (laser values in SI: V or m)
  Signal laser_distance_raw;    // laser distance [m] on the laser's clock
  Signal force_filtered;        // uniform, filtered, force clock [N]
  Signal distance_filtered;     // uniform, filtered, laser clock [m]
  PokeWindow force_window;      // force clock; levels in N
  PokeWindow laser_window;      // laser clock; levels of minus the distance [m]
  double clock_shift = 0.0;     // laser time + shift = force time [s]
  double coarse_shift = 0.0;    // from the poke starts alone [s]
  double correlation = 0.0;     // rank correlation at the shift
  double common_rate = 0.0;     // [Hz]
  // The common clock (force clock) from the loading start to the unloading end,
  // rest levels removed.
  std::vector<double> time, indentation, force;
  std::size_t peak = 0;         // index of the maximum force in `time`
  // The raw pairs the curves come from, over the same span: each force sample
  // (force clock) with the laser's distance at its time, rest levels removed.
  // The first `pairs_peak` are the loading's; the unloading's start at the last of them.
  std::vector<double> pair_time, pair_indentation, pair_force;
  std::size_t pairs_peak = 0;
  Curve loading, unloading;
  PenalizedSpline loading_spline, unloading_spline;  // the smooth curves through the pairs
  double rest_distance = 0.0;   // laser distance at rest before the poke [m]
};

// Processes one poke. `calibration` is required when the laser column is a
// voltage and must be absent when it is a distance. Throws palpa::Error (Input)
// naming the file, line and column for every bad input (see log.hpp and
// signal.hpp) and for a laser that does not get closer during the poke.
PokeResult process_poke(const std::filesystem::path& force_log, const std::filesystem::path& laser_log,
                        const std::optional<std::filesystem::path>& calibration, const PokeOptions& options);

// `pairs` (indentation [m], force [N], any order) on the uniform grid 0..x_max
// with `points` points: a P-spline through the pairs (penalized_spline.hpp;
// quadratic data is reproduced exactly), or straight lines between them when
// there are too few for one (or too few distinct indentations). The spline,
// if any, is stored in `spline`.
Curve uniform_curve(std::span<const double> indentation, std::span<const double> force, double x_max,
                    std::size_t points, PenalizedSpline* spline = nullptr);

// Raw against filtered force and laser distance on the force clock (the laser
// shifted), with the poke windows; and the final curve(s) over the samples.
report::Figure poke_signals_figure(const PokeResult& r);
report::Figure poke_curve_figure(const PokeResult& r);

}  // namespace palpa::acquire
