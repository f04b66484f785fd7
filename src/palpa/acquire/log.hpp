// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Raw device logs as CSV files (io/csv.hpp): which columns to read, in which
// units, and the checks every log gets before processing.
//
// A column is named by a spec "NAME" or "NAME:UNIT":
//  - "NAME:UNIT" reads the column NAME exactly and scales it by UNIT ("Force:gf",
//    "t:ms"), for logs whose header has no units;
//  - "NAME" reads the column NAME if it carries its unit after its last
//    underscore ("time_ms", "force_N"), or else the single column whose base name
//    is NAME ("time" finds time_ms).
// Units must be of the quantity's kind (a force column in gf, N, kN, ...).

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "palpa/acquire/signal.hpp"
#include "palpa/core/units.hpp"
#include "palpa/io/csv.hpp"

namespace palpa::acquire {

struct ColumnSpec {
  std::string name;  // column name or base name
  std::string unit;  // "" : from the column name
};

// "force" -> {force, ""}; "Force:gf" -> {Force, gf}. Throws palpa::Error
// (Input) naming `option` for an empty name or unit, or an unknown unit.
ColumnSpec parse_column_spec(std::string_view text, const std::string& option);
// "time_s,force_N" -> two specs (exactly `count` comma-separated specs).
std::vector<ColumnSpec> parse_column_specs(std::string_view text, std::size_t count, const std::string& option);

// One resolved column.
struct Column {
  std::string name;       // the column's name in the file
  Dimension dimension{};  // the kind of its unit (one of the allowed ones)
  std::vector<double> si; // values in SI
};

// Reads the column of `table` that `spec` names, as SI values. `allowed` lists
// the kinds the quantity may have (a laser column: voltage or length). Throws
// palpa::Error (Input) naming the file and column: no such column (listing
// those present), several columns with that base name, a unit that is unknown
// or of another kind.
Column read_column(const CsvTable& table, const ColumnSpec& spec, std::span<const Dimension> allowed,
                   const std::string& role);

struct LogCheck {
  // A time step longer than this many median steps is a gap in the recording.
  double max_gap_steps = 5.0;
  // At least this many samples.
  std::size_t min_samples = 10;
};

// A time-stamped log: the time column and one value column.
struct Log {
  std::string file;
  Column time;
  Column value;
  Signal signal;        // (time, value) in SI
  double rate = 0.0;    // 1 / median time step [Hz]
  std::vector<std::size_t> lines;  // file line of each sample, for messages
};

// Reads `path` and checks it: at least min_samples rows, strictly increasing
// time (an error names the line and both times), no gap longer than
// max_gap_steps median steps (naming the line, the times and the gap). NaN and
// non-numbers are refused by the CSV reader with file, line and column.
Log read_log(const std::filesystem::path& path, const ColumnSpec& time, const ColumnSpec& value,
             std::span<const Dimension> value_kinds, const std::string& role, const LogCheck& check = {});

// Throws palpa::Error (Input) when `log` has a run of identical samples lasting
// at least `min_duration` [s] (and >= 3 samples) at its maximum
// (Extreme::Max) or minimum: the sensor was saturated (clipped). The message
// names the file, the line of the run's first sample, the value and the run's
// length.
void check_not_clipped(const Log& log, Extreme extreme, double min_duration);

// A table mapping one quantity monotonically onto another, interpolated
// linearly (a laser's voltage -> distance).
class Calibration {
 public:
  Calibration() = default;
  // x strictly monotone (increasing or decreasing) and y strictly monotone;
  // `file` names the table in messages. Throws palpa::Error (Input) naming the
  // file and line of the first sample that breaks monotonicity, and for fewer
  // than 2 rows.
  Calibration(std::vector<double> x, std::vector<double> y, std::string file, std::vector<std::size_t> lines = {});

  // y at x; palpa::Error (Input) if x is outside the table (naming `where`).
  double operator()(double x, const std::string& where) const;
  double x_min() const noexcept;
  double x_max() const noexcept;
  const std::string& file() const noexcept { return file_; }

 private:
  std::vector<double> x_, y_;  // x increasing
  std::string file_;
};

// Reads a calibration CSV with columns `from` and `to` (column specs) in SI,
// e.g. voltage_V and distance_mm: voltage [V] -> distance [m].
Calibration read_calibration(const std::filesystem::path& path, const ColumnSpec& from, Dimension from_kind,
                             const ColumnSpec& to, Dimension to_kind);

}  // namespace palpa::acquire
