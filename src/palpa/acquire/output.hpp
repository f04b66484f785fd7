// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The files `palpa acquire` writes from its results: curve and depth tables,
// summaries, plots and pressure maps. Each write_* writes every file it is
// given or none (one OutputBatch; a plots or map folder it created goes again
// on failure); empty paths are not written.

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "palpa/acquire/poke.hpp"
#include "palpa/acquire/pressure.hpp"
#include "palpa/acquire/ultrasound.hpp"
#include "palpa/core/json.hpp"
#include "palpa/io/csv.hpp"

namespace palpa::acquire {

// indentation_m,force_N under one comment line: a `palpa fit` curve file.
CsvTable curve_table(const Curve& c, const std::string& comment);

struct PokeFiles {
  std::filesystem::path curve;      // the loading curve (required)
  std::filesystem::path unloading;  // the unloading curve
  std::filesystem::path plots;      // folder: signals.svg, curve.svg
  std::filesystem::path summary;    // JSON
};

// Rates, windows, clock shift, rest distance, maxima and the curves' smoothing.
// `calibration` is the calibration file as given (empty: none).
Json poke_summary(const PokeResult& r, const PokeOptions& o, const std::string& calibration);
void write_poke(const PokeResult& r, const PokeOptions& o, const std::string& calibration, const PokeFiles& files);

struct UltrasoundFiles {
  std::filesystem::path depths;       // time_s,force_N,<name>_depth_m... (required)
  std::filesystem::path depth_table;  // a table this location's row goes into (with `position`)
  std::filesystem::path plots;        // folder: depths.svg
  std::filesystem::path summary;      // JSON
};

// The depth table's row: where, and which interface's rest depth is depth_m.
struct DepthRow {
  std::array<double, 3> position{};  // [m]
  std::size_t main_interface = 0;
  CsvTable existing;  // the table as it is (empty: a new one)
};

Json ultrasound_summary(const UltrasoundResult& r, const UltrasoundOptions& o);
void write_ultrasound(const UltrasoundResult& r, const UltrasoundOptions& o, const UltrasoundFiles& files,
                      const std::optional<DepthRow>& row);

// Per sensor location: trimmed readings, reference, pressure and distance.
CsvTable pressure_location_table(const PressureMap& m);
// `method` names the interpolation as the user chose it.
Json pressure_summary(const SurfaceMesh& mesh, const PressureMap& m, const PressureOptions& o,
                      const std::filesystem::path& mesh_file, const std::filesystem::path& locations_file,
                      const std::filesystem::path& samples_file, const std::string& method);
// The folder `out`: pressure.ply, pressure.vtu, locations.csv, summary.json.
void write_pressure_map(const SurfaceMesh& mesh, const PressureMap& m, const Json& summary,
                        const std::filesystem::path& out);

}  // namespace palpa::acquire
