// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Ultrasound depth picks -> tissue interface depths (thesis §3.2–3.4, Fig. 3.4,
// Table 3.1; `palpa acquire ultrasound`).
//
// The ultrasound probe is mounted on the force gauge; its image has time along
// x and depth below the skin along y. On the image one picks control points
// (time, depth) along each tissue interface (fat/muscle, muscle/bone); a
// Catmull–Rom spline through them gives the interface's depth at any time. The
// force log gives the poke (rest plateaus, start, maximum); the two clocks are
// aligned by a given offset, refined by the rank correlation of force and the
// first interface's compression. Results: each interface's depth at rest (the
// fat depth, the distance to the bone) and its depth against force while
// loading.

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "palpa/acquire/log.hpp"
#include "palpa/acquire/poke.hpp"
#include "palpa/acquire/signal.hpp"
#include "palpa/report/plot.hpp"

namespace palpa::acquire {

// A Catmull–Rom spline y(t) through (t_i, y_i): the cubic Hermite curve whose
// tangent at each inner point is (y_{i+1} − y_{i−1}) / (t_{i+1} − t_{i−1}) and
// at the ends the one-sided slope. It passes through every point, reproduces
// straight lines exactly (and parabolas exactly between inner points of evenly
// spaced data). t strictly increasing, at least 2 points (programmer errors).
class CatmullRom {
 public:
  CatmullRom(std::vector<double> t, std::vector<double> y);
  // y at t; outside [t_first, t_last] the straight line along the end tangent.
  double operator()(double t) const;
  double t_first() const noexcept { return t_.front(); }
  double t_last() const noexcept { return t_.back(); }

 private:
  std::vector<double> t_, y_, slope_;
};

// The picks of one interface.
struct InterfacePicks {
  std::string name;         // "fat", "bone", ...
  std::string file;
  std::vector<double> t;    // [s], ultrasound clock, strictly increasing
  std::vector<double> depth;  // [m] below the skin, >= 0
};

// Reads picks (CSV, columns time and depth: `time_s,depth_mm` or as the specs
// say). Throws palpa::Error (Input) naming file, line and column for fewer than
// 2 picks, times not strictly increasing, a negative depth.
InterfacePicks read_interface_picks(const std::string& name, const std::filesystem::path& path,
                                    const ColumnSpec& time, const ColumnSpec& depth);

struct UltrasoundOptions {
  ColumnSpec force_time{"time", ""}, force_value{"force", ""};
  ColumnSpec pick_time{"time", ""}, pick_depth{"depth", ""};
  int order = 4;
  double cutoff = 5.0;  // [Hz] force low-pass
  PlateauOptions plateau;
  std::optional<TimeWindow> force_window;
  LogCheck check;
  double saturation = 0.1;  // [s]
  double offset = 0.0;      // ultrasound time + offset = force time [s] (start guess)
  bool align = true;        // refine the offset by rank correlation
  double search = 0.5;      // ± this around the offset [s]
  bool tare = true;
};

struct UltrasoundResult {
  Log force_log;
  Signal force_filtered;
  PokeWindow force_window;
  std::vector<InterfacePicks> interfaces;
  double clock_shift = 0.0;   // ultrasound time + shift = force time [s]
  double correlation = 0.0;   // rank correlation (0 when not aligned)
  std::vector<double> rest_depth;  // per interface, mean over the rest before the poke [m]
  // Loading (poke start -> maximum force) on the force log's uniform clock.
  std::vector<double> time, force;
  std::vector<std::vector<double>> depth;  // per interface, at `time` [m]
};

// Throws palpa::Error (Input) naming the interface and both time ranges when
// its picks do not cover the loading part or any of the rest before it, and
// everything read_log / detect_poke throw.
UltrasoundResult process_ultrasound(const std::filesystem::path& force_log,
                                    const std::vector<std::pair<std::string, std::filesystem::path>>& interfaces,
                                    const UltrasoundOptions& options);

// A table of rest depths at measured locations (thesis Table 3.1), the depth
// samples `palpa mesh` reads: columns x_m,y_m,z_m (the location on the body
// scan), depth_m (the interface chosen to shape the soft layer, usually the
// bone distance) and <name>_depth_m for every interface. Returns `existing`
// (may be empty: no columns) with the row for `position` [m] added, or replaced
// when a row has that position already. Throws palpa::Error (Input) naming the
// table's file when its columns differ.
CsvTable add_depth_row(const CsvTable& existing, const std::array<double, 3>& position,
                       const std::vector<std::string>& names, const std::vector<double>& rest_depth,
                       std::size_t main_interface);

// Depth against force per interface.
report::Figure ultrasound_figure(const UltrasoundResult& r);

}  // namespace palpa::acquire
