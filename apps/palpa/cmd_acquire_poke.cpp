// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa acquire poke: force gauge + laser logs -> force–indentation curve.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <memory>
#include <optional>

#include "acquire_options.hpp"
#include "cli_common.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/acquire/output.hpp"
#include "palpa/core/error.hpp"

namespace palpa::cli {

namespace {

struct AcquirePokeArgs {
  std::string force, laser, calibration, output, unloading, plots, summary;
  std::string force_columns, laser_columns, calibration_columns;
  std::string force_window, laser_window;
  acquire::PokeOptions o;
  int points = 50;
  bool no_tare = false;
  bool overwrite = false;
};

void run_acquire_poke(AcquirePokeArgs& a) {
  if (!a.plots.empty() && !a.overwrite) require_empty_output(a.plots, {}, "--plots");
  acquire::PokeOptions o = a.o;
  set_columns(a.force_columns, "--force-columns", o.force_time, o.force_value);
  set_columns(a.laser_columns, "--laser-columns", o.laser_time, o.laser_value);
  set_columns(a.calibration_columns, "--calibration-columns", o.calibration_voltage, o.calibration_distance);
  if (!a.force_window.empty()) o.force_window = parse_window(a.force_window, "--force-window");
  if (!a.laser_window.empty()) o.laser_window = parse_window(a.laser_window, "--laser-window");
  if (a.points < 3 || static_cast<std::size_t>(a.points) > acquire::kMaxCurvePoints) {
    throw_input_error(fmt::format("{} grid points", a.points), ErrorContext{"", 0, 0, "option --points"},
                      fmt::format("3 to {}", acquire::kMaxCurvePoints));
  }
  o.points = static_cast<std::size_t>(a.points);
  o.tare = !a.no_tare;
  std::optional<std::filesystem::path> cal;
  if (!a.calibration.empty()) cal = a.calibration;
  const acquire::PokeResult r = acquire::process_poke(a.force, a.laser, cal, o);
  acquire::write_poke(r, o, a.calibration, {a.output, a.unloading, a.plots, a.summary});
  const double peak_force = r.force[r.peak];
  const double depth = r.loading.indentation.back();
  spdlog::info("acquire poke: force {} Hz, laser {} Hz, laser clock {:+.4f} s (rank correlation {:.4f}); poke {:.3f} .. "
               "{:.3f} s; {} at {}; wrote {}",
               fmt::format("{:.4g}", r.force_log.rate), fmt::format("{:.4g}", r.laser_log.rate), r.clock_shift,
               r.correlation, r.force_window.start, r.force_window.end, format_quantity(peak_force, Dimension::Force),
               format_quantity(depth, Dimension::Length), a.output);
  if (r.correlation < 0.9) {
    spdlog::warn("acquire poke: force and laser agree poorly (rank correlation {:.3f}): check that both logs hold the "
                 "same poke and look at the signals plot",
                 r.correlation);
  }
}

}  // namespace

void add_acquire_poke(CLI::App& acquire) {
  auto* cmd = acquire.add_subcommand(
      "poke",
      "Force gauge + laser logs -> force-indentation curve (indentation_m,force_N) for palpa fit.\n"
      "  palpa acquire poke --force force.csv --laser laser.csv --calibration laser-calibration.csv -o curve.csv");
  auto a = std::make_shared<AcquirePokeArgs>();
  cmd->add_option("--force", a->force, "Force gauge log (CSV: time and force columns)")->required();
  cmd->add_option("--laser", a->laser, "Laser log (CSV: time and voltage, or time and distance)")->required();
  cmd->add_option("--calibration", a->calibration, "Laser calibration table (CSV: voltage and distance, monotone)");
  cmd->add_option("-o,--output", a->output, "Loading curve (CSV indentation_m,force_N)")->required();
  cmd->add_option("--unloading", a->unloading, "Also write the unloading curve here (CSV)");
  cmd->add_option("--plots", a->plots, "Folder for signals.svg (raw vs filtered) and curve.svg");
  cmd->add_flag("--overwrite", a->overwrite,
                "Write into a non-empty --plots folder (the files palpa wrote there before and does not write "
                "again are removed)");
  cmd->add_option("--summary", a->summary, "Summary JSON (clock shift, windows, rates, maxima)");
  cmd->add_option("--force-columns", a->force_columns,
                  "Time and force columns, NAME or NAME:UNIT each (default time,force: columns time_<unit>, "
                  "force_<unit>)");
  cmd->add_option("--laser-columns", a->laser_columns,
                  "Time and laser columns (default time,voltage; e.g. t:ms,dist:mm for a distance laser)");
  cmd->add_option("--calibration-columns", a->calibration_columns,
                  "Voltage and distance columns of the calibration (default voltage,distance)");
  add_log_options(*cmd, a->o.order, a->o.cutoff, a->o.plateau, a->o.check, a->o.saturation);
  cmd->add_option("--force-window", a->force_window,
                  "Poke start and end on the force log's clock, instead of finding them (e.g. 1.9s,3.3s)");
  cmd->add_option("--laser-window", a->laser_window, "Poke start and end on the laser log's clock");
  cmd->add_option("--points", a->points, "Points of the uniform indentation grid (default 50)");
  cmd->add_flag("--no-tare", a->no_tare, "Keep the force at rest instead of subtracting it");
  declare_paths(*cmd, {"--force", "--laser", "--calibration"}, {"-o", "--unloading", "--plots", "--summary"});
  cmd->callback([a] { run_acquire_poke(*a); });
}

}  // namespace palpa::cli
