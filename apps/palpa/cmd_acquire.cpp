// palpa acquire: raw measurements -> the curves and maps the rest of palpa
// reads (thesis ch. 3, §7.6): poke logs -> force–indentation curve, ultrasound
// picks -> tissue depths, pressure-sensor samples -> pressure map.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <memory>
#include <optional>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/acquire/poke.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/json.hpp"
#include "palpa/core/text.hpp"
#include "palpa/io/csv.hpp"

namespace palpa::cli {

namespace {

// "1.9s,3.3s" -> a window on a log's clock.
acquire::TimeWindow parse_window(const std::string& text, const std::string& option) {
  const auto parts = split(text, ',');
  const ErrorContext where{"", 0, 0, "option " + option};
  if (parts.size() != 2) {
    throw_input_error(fmt::format("'{}' is not a time window", text), where, "START,END such as 1.9s,3.3s");
  }
  return {parse_quantity(parts[0], Dimension::Time, where), parse_quantity(parts[1], Dimension::Time, where)};
}

void set_columns(const std::string& text, const std::string& option, acquire::ColumnSpec& time,
                 acquire::ColumnSpec& value) {
  if (text.empty()) return;
  const auto specs = acquire::parse_column_specs(text, 2, option);
  time = specs[0];
  value = specs[1];
}

CsvTable curve_table(const acquire::Curve& c, const std::string& comment) {
  CsvTable t;
  t.add_comment(comment);
  t.add_column("indentation_m", c.indentation);
  t.add_column("force_N", c.force);
  return t;
}

Json window_json(const acquire::PokeWindow& w) {
  return Json{{"start_s", w.start},
              {"peak_s", w.peak},
              {"end_s", w.end},
              {"manual", w.manual},
              {"rest_before_s", {w.before.t0, w.before.t1}},
              {"rest_after_s", {w.after.t0, w.after.t1}}};
}

struct PokeArgs {
  std::string force, laser, calibration, output, unloading, plots, summary;
  std::string force_columns, laser_columns, calibration_columns;
  std::string force_window, laser_window;
  acquire::PokeOptions o;
  int points = 50;
  bool no_tare = false;
};

void run_acquire_poke(PokeArgs& a) {
  acquire::PokeOptions o = a.o;
  set_columns(a.force_columns, "--force-columns", o.force_time, o.force_value);
  set_columns(a.laser_columns, "--laser-columns", o.laser_time, o.laser_value);
  set_columns(a.calibration_columns, "--calibration-columns", o.calibration_voltage, o.calibration_distance);
  if (!a.force_window.empty()) o.force_window = parse_window(a.force_window, "--force-window");
  if (!a.laser_window.empty()) o.laser_window = parse_window(a.laser_window, "--laser-window");
  if (a.points < 3) {
    throw_input_error(fmt::format("{} grid points", a.points), ErrorContext{"", 0, 0, "option --points"}, "at least 3");
  }
  o.points = static_cast<std::size_t>(a.points);
  o.tare = !a.no_tare;
  std::optional<std::filesystem::path> cal;
  if (!a.calibration.empty()) cal = a.calibration;
  const acquire::PokeResult r = acquire::process_poke(a.force, a.laser, cal, o);

  const std::string source = fmt::format("palpa acquire poke: {} + {}", a.force, a.laser);
  OutputBatch batch;
  batch.add(a.output) << format_csv(curve_table(r.loading, source + "; loading (start -> maximum force)"));
  if (!a.unloading.empty()) {
    batch.add(a.unloading) << format_csv(curve_table(r.unloading, source + "; unloading (maximum force -> end)"));
  }
  if (!a.plots.empty()) {
    ensure_directory(a.plots);
    batch.add(std::filesystem::path(a.plots) / "signals.svg") << report::render_svg(acquire::poke_signals_figure(r));
    batch.add(std::filesystem::path(a.plots) / "curve.svg") << report::render_svg(acquire::poke_curve_figure(r));
  }
  const double peak_force = r.force[r.peak];
  const double depth = r.loading.indentation.back();
  if (!a.summary.empty()) {
    Json s{{"force_log", {{"file", a.force}, {"column", r.force_log.value.name}, {"samples", r.force_log.signal.size()},
                          {"rate_Hz", r.force_log.rate}, {"poke", window_json(r.force_window)}}},
           {"laser_log", {{"file", a.laser}, {"column", r.laser_log.value.name}, {"samples", r.laser_log.signal.size()},
                          {"rate_Hz", r.laser_log.rate}, {"poke", window_json(r.laser_window)}}},
           {"calibration", a.calibration},
           {"filter", {{"type", "Butterworth low-pass, forward-backward"}, {"order", o.order}, {"cutoff_Hz", o.cutoff}}},
           {"clock_shift_s", r.clock_shift},
           {"coarse_clock_shift_s", r.coarse_shift},
           {"rank_correlation", r.correlation},
           {"common_rate_Hz", r.common_rate},
           {"rest_distance_m", r.rest_distance},
           {"max_force_N", peak_force},
           {"max_indentation_m", depth},
           {"points", o.points}};
    batch.add(a.summary) << s.dump(2) << "\n";
  }
  batch.commit();
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

void add_acquire_poke(CLI::App& acquire) {
  auto* cmd = acquire.add_subcommand(
      "poke",
      "Force gauge + laser logs -> force-indentation curve (indentation_m,force_N) for palpa fit.\n"
      "  palpa acquire poke --force force.csv --laser laser.csv --calibration laser-calibration.csv -o curve.csv");
  auto a = std::make_shared<PokeArgs>();
  cmd->add_option("--force", a->force, "Force gauge log (CSV: time and force columns)")->required();
  cmd->add_option("--laser", a->laser, "Laser log (CSV: time and voltage, or time and distance)")->required();
  cmd->add_option("--calibration", a->calibration, "Laser calibration table (CSV: voltage and distance, monotone)");
  cmd->add_option("-o,--output", a->output, "Loading curve (CSV indentation_m,force_N)")->required();
  cmd->add_option("--unloading", a->unloading, "Also write the unloading curve here (CSV)");
  cmd->add_option("--plots", a->plots, "Folder for signals.svg (raw vs filtered) and curve.svg");
  cmd->add_option("--summary", a->summary, "Summary JSON (clock shift, windows, rates, maxima)");
  cmd->add_option("--force-columns", a->force_columns,
                  "Time and force columns, NAME or NAME:UNIT each (default time,force: columns time_<unit>, "
                  "force_<unit>)");
  cmd->add_option("--laser-columns", a->laser_columns,
                  "Time and laser columns (default time,voltage; e.g. t:ms,dist:mm for a distance laser)");
  cmd->add_option("--calibration-columns", a->calibration_columns,
                  "Voltage and distance columns of the calibration (default voltage,distance)");
  add_quantity_option(*cmd, "--cutoff", a->o.cutoff, Dimension::Frequency,
                      "Low-pass cut-off (default 5 Hz: keeps a ~1 s poke, removes tremor and noise)");
  cmd->add_option("--order", a->o.order, "Butterworth order per pass (default 4)")->check(CLI::Range(1, 12));
  add_quantity_option(*cmd, "--rest", a->o.plateau.min_duration, Dimension::Time,
                      "Shortest rest plateau before and after the poke (default 1 s)");
  cmd->add_option("--rest-tolerance", a->o.plateau.tolerance,
                  "A plateau stays within this fraction of the poke's amplitude (default 0.05)")
      ->check(CLI::Range(1e-4, 0.5));
  cmd->add_option("--force-window", a->force_window,
                  "Poke start and end on the force log's clock, instead of finding them (e.g. 1.9s,3.3s)");
  cmd->add_option("--laser-window", a->laser_window, "Poke start and end on the laser log's clock");
  cmd->add_option("--max-gap", a->o.check.max_gap_steps,
                  "A time step longer than this many median steps is a gap (error; default 5)")
      ->check(CLI::Range(1.5, 1e6));
  add_quantity_option(*cmd, "--saturation", a->o.saturation, Dimension::Time,
                      "Identical samples at a log's extreme for this long mean a clipped sensor (default 0.1 s)");
  cmd->add_option("--points", a->points, "Points of the uniform indentation grid (default 50)");
  cmd->add_flag("--no-tare", a->no_tare, "Keep the force at rest instead of subtracting it");
  cmd->callback([a] { run_acquire_poke(*a); });
}

}  // namespace

void add_acquire_command(CLI::App& app) {
  auto* acquire = app.add_subcommand(
      "acquire", "Process raw measurements: poke logs, ultrasound depth picks, pressure sensors");
  acquire->require_subcommand(1);
  add_acquire_poke(*acquire);
}

}  // namespace palpa::cli
