// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa acquire: raw measurements -> the curves and maps the rest of palpa
// reads (thesis ch. 3, §7.6): poke logs -> force–indentation curve, ultrasound
// picks -> tissue depths, pressure-sensor samples -> pressure map.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <memory>
#include <optional>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/acquire/poke.hpp"
#include "palpa/acquire/pressure.hpp"
#include "palpa/acquire/ultrasound.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/json.hpp"
#include "palpa/core/text.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/io/mesh.hpp"
#include "palpa/io/ply.hpp"
#include "palpa/io/vtu.hpp"
#include "palpa/report/pressure_metrics.hpp"

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

// How smooth a curve came out and what it left: the residual RMS is the
// noise of the force gauge as the pairs see it.
Json spline_json(const acquire::PenalizedSpline& s) {
  if (s.pairs == 0) return Json{{"smoothed", false}};  // too few pairs: straight lines between them
  return Json{{"smoothed", true}, {"pairs", s.pairs}, {"effective_dof", s.effective_dof}, {"residual_rms_N", s.rms}};
}

// The options of every command that reads time-stamped logs: the low-pass
// filter, the rest plateaus and the log checks.
void add_log_options(CLI::App& cmd, int& order, double& cutoff, acquire::PlateauOptions& plateau,
                     acquire::LogCheck& check, double& saturation) {
  add_quantity_option(cmd, "--cutoff", cutoff, Dimension::Frequency,
                      "Low-pass cut-off (default 5 Hz: keeps a ~1 s poke, removes tremor and noise)", Sign::Positive);
  cmd.add_option("--order", order, "Butterworth order per pass (default 4)")->check(CLI::Range(1, 12));
  add_quantity_option(cmd, "--rest", plateau.min_duration, Dimension::Time,
                      "Shortest rest plateau before and after the poke (default 1 s)", Sign::Positive);
  cmd.add_option("--rest-tolerance", plateau.tolerance,
                 "A plateau stays within this fraction of the poke's amplitude (default 0.05)")
      ->check(CLI::Range(1e-4, 0.5));
  cmd.add_option("--max-gap", check.max_gap_steps,
                 "A time step longer than this many median steps is a gap (error; default 5)")
      ->check(CLI::Range(1.5, 1e6));
  add_quantity_option(cmd, "--saturation", saturation, Dimension::Time,
                      "Identical samples at a log's extreme for this long mean a clipped sensor (default 0.1 s)",
                      Sign::Positive);
}

struct AcquirePokeArgs {
  std::string force, laser, calibration, output, unloading, plots, summary;
  std::string force_columns, laser_columns, calibration_columns;
  std::string force_window, laser_window;
  acquire::PokeOptions o;
  int points = 50;
  bool no_tare = false;
};

void run_acquire_poke(AcquirePokeArgs& a) {
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

  const std::string source = fmt::format("palpa acquire poke: {} + {}", a.force, a.laser);
  // The folder before the batch: on failure the batch's temporaries go first,
  // so that a plots folder this run created is empty again and goes too.
  std::optional<OutputFolder> plots;
  OutputBatch batch;
  batch.add(a.output) << format_csv(curve_table(r.loading, source + "; loading (start -> maximum force)"));
  if (!a.unloading.empty()) {
    batch.add(a.unloading) << format_csv(curve_table(r.unloading, source + "; unloading (maximum force -> end)"));
  }
  if (!a.plots.empty()) {
    plots.emplace(a.plots);
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
           {"points", o.points},
           {"curves", {{"method", "P-spline through the raw (indentation, force) pairs"},
                       {"loading", spline_json(r.loading_spline)},
                       {"unloading", spline_json(r.unloading_spline)}}}};
    batch.add(a.summary) << format_json(s, a.summary);
  }
  batch.commit();
  if (plots) plots->keep();
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
  auto a = std::make_shared<AcquirePokeArgs>();
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
  add_log_options(*cmd, a->o.order, a->o.cutoff, a->o.plateau, a->o.check, a->o.saturation);
  cmd->add_option("--force-window", a->force_window,
                  "Poke start and end on the force log's clock, instead of finding them (e.g. 1.9s,3.3s)");
  cmd->add_option("--laser-window", a->laser_window, "Poke start and end on the laser log's clock");
  cmd->add_option("--points", a->points, "Points of the uniform indentation grid (default 50)");
  cmd->add_flag("--no-tare", a->no_tare, "Keep the force at rest instead of subtracting it");
  declare_paths(*cmd, {"--force", "--laser", "--calibration"}, {"-o", "--unloading", "--plots", "--summary"});
  cmd->callback([a] { run_acquire_poke(*a); });
}

struct UltrasoundArgs {
  std::string force, output, plots, summary, depth_table, position, depth_interface;
  std::vector<std::string> interfaces;
  std::string force_columns, pick_columns, force_window;
  acquire::UltrasoundOptions o;
  bool no_align = false;
};

// "12mm,40mm,310mm" -> a position [m].
std::array<double, 3> parse_position(const std::string& text, const std::string& option) {
  const auto parts = split(text, ',');
  const ErrorContext where{"", 0, 0, "option " + option};
  if (parts.size() != 3) {
    throw_input_error(fmt::format("'{}' is not a position", text), where, "X,Y,Z with units, e.g. 12mm,40mm,310mm");
  }
  return {parse_quantity(parts[0], Dimension::Length, where), parse_quantity(parts[1], Dimension::Length, where),
          parse_quantity(parts[2], Dimension::Length, where)};
}

void run_acquire_ultrasound(const UltrasoundArgs& a) {
  acquire::UltrasoundOptions o = a.o;
  set_columns(a.force_columns, "--force-columns", o.force_time, o.force_value);
  set_columns(a.pick_columns, "--pick-columns", o.pick_time, o.pick_depth);
  if (!a.force_window.empty()) o.force_window = parse_window(a.force_window, "--force-window");
  o.align = !a.no_align;
  std::vector<std::pair<std::string, std::filesystem::path>> interfaces;
  std::vector<std::string> names;
  for (const std::string& spec : a.interfaces) {
    const auto eq = spec.find('=');
    const std::string name = eq == std::string::npos ? "" : std::string(trim(spec.substr(0, eq)));
    const bool valid = !name.empty() && std::all_of(name.begin(), name.end(), [](char ch) {
      return std::isalnum(static_cast<unsigned char>(ch)) || ch == '-';
    });
    if (!valid || std::find(names.begin(), names.end(), name) != names.end()) {
      throw_input_error(fmt::format("'{}' is not a new interface NAME=FILE", spec),
                        ErrorContext{"", 0, 0, "option --interface"},
                        "NAME=FILE with a distinct NAME of letters, digits and '-', e.g. fat=fat.csv");
    }
    names.push_back(name);
    interfaces.emplace_back(name, spec.substr(eq + 1));
  }
  std::size_t main_interface = names.empty() ? 0 : names.size() - 1;
  if (!a.depth_interface.empty()) {
    const auto it = std::find(names.begin(), names.end(), a.depth_interface);
    if (it == names.end()) {
      throw_input_error(fmt::format("there is no interface '{}'", a.depth_interface),
                        ErrorContext{"", 0, 0, "option --depth-interface"}, "one of the --interface names");
    }
    main_interface = static_cast<std::size_t>(it - names.begin());
  }
  if (a.depth_table.empty() != a.position.empty()) {
    throw_input_error("--depth-table and --position go together", ErrorContext{"", 0, 0, "option --depth-table"},
                      "both options or neither");
  }
  std::optional<std::array<double, 3>> position;
  if (!a.position.empty()) position = parse_position(a.position, "--position");
  CsvTable table;
  // (The table is an output this run adds a row to: not an input to protect.)
  if (position && std::filesystem::exists(a.depth_table)) table = read_csv(a.depth_table, InputUse::RunState);

  const acquire::UltrasoundResult r = acquire::process_ultrasound(a.force, interfaces, o);
  CsvTable depths;
  depths.add_comment(fmt::format("palpa acquire ultrasound: {}; loading (start -> maximum force); ultrasound time {:+.4f} s "
                                 "= force time",
                                 a.force, r.clock_shift));
  depths.add_column("time_s", r.time);
  depths.add_column("force_N", r.force);
  for (std::size_t k = 0; k < names.size(); ++k) depths.add_column(names[k] + "_depth_m", r.depth[k]);
  std::optional<OutputFolder> plots;  // before the batch, as for a poke
  OutputBatch batch;
  batch.add(a.output) << format_csv(depths);
  if (position) {
    batch.add(a.depth_table) << format_csv(acquire::add_depth_row(table, *position, names, r.rest_depth, main_interface));
  }
  if (!a.plots.empty()) {
    plots.emplace(a.plots);
    batch.add(std::filesystem::path(a.plots) / "depths.svg") << report::render_svg(acquire::ultrasound_figure(r));
  }
  if (!a.summary.empty()) {
    Json rest = Json::object();
    for (std::size_t k = 0; k < names.size(); ++k) rest[names[k] + "_m"] = r.rest_depth[k];
    Json s{{"force_log", {{"file", a.force}, {"rate_Hz", r.force_log.rate}, {"poke", window_json(r.force_window)}}},
           {"clock_shift_s", r.clock_shift},
           {"aligned", o.align},
           {"rank_correlation", r.correlation},
           {"rest_depth", rest},
           {"max_force_N", r.force.back()}};
    batch.add(a.summary) << format_json(s, a.summary);
  }
  batch.commit();
  if (plots) plots->keep();
  std::string rest_text;
  for (std::size_t k = 0; k < names.size(); ++k) {
    rest_text += fmt::format("{}{} {}", k ? ", " : "", names[k], format_quantity(r.rest_depth[k], Dimension::Length));
  }
  spdlog::info("acquire ultrasound: ultrasound clock {:+.4f} s{}; rest depths {}; wrote {}", r.clock_shift,
               o.align ? fmt::format(" (rank correlation {:.4f})", r.correlation) : "", rest_text, a.output);
}

void add_acquire_ultrasound(CLI::App& acquire) {
  auto* cmd = acquire.add_subcommand(
      "ultrasound",
      "Ultrasound interface picks + force log -> rest depths and depth against force per interface.\n"
      "  palpa acquire ultrasound --force force.csv --interface fat=fat.csv --interface bone=bone.csv -o depths.csv \\\n"
      "      --depth-table arm-depths.csv --position 12mm,40mm,310mm");
  auto a = std::make_shared<UltrasoundArgs>();
  cmd->add_option("--force", a->force, "Force gauge log (CSV: time and force columns)")->required();
  cmd->add_option("--interface", a->interfaces,
                  "NAME=FILE: control points (time, depth) picked along one tissue interface, shallowest first; "
                  "repeat per interface")
      ->required();
  cmd->add_option("-o,--output", a->output, "Depth against force while loading (CSV time_s,force_N,<name>_depth_m...)")
      ->required();
  cmd->add_option("--depth-table", a->depth_table,
                  "Add this location's rest depths to a depth table (CSV x_m,y_m,z_m,depth_m,<name>_depth_m...; "
                  "created if missing, the row at the same position replaced)");
  cmd->add_option("--position", a->position, "The location on the body scan for --depth-table, e.g. 12mm,40mm,310mm");
  cmd->add_option("--depth-interface", a->depth_interface,
                  "The interface whose rest depth goes into the table's depth_m column (default: the last, deepest)");
  cmd->add_option("--plots", a->plots, "Folder for depths.svg");
  cmd->add_option("--summary", a->summary, "Summary JSON (rest depths, clock shift, poke window)");
  cmd->add_option("--force-columns", a->force_columns, "Time and force columns of the force log (default time,force)");
  cmd->add_option("--pick-columns", a->pick_columns, "Time and depth columns of the picks (default time,depth)");
  add_quantity_option(*cmd, "--offset", a->o.offset, Dimension::Time,
                      "Ultrasound time + offset = force time (default 0 s: started together)");
  cmd->add_flag("--no-align", a->no_align, "Use --offset as is instead of refining it");
  add_quantity_option(*cmd, "--search", a->o.search, Dimension::Time,
                      "The refinement looks this far either side of --offset (default 0.5 s)", Sign::Positive);
  add_log_options(*cmd, a->o.order, a->o.cutoff, a->o.plateau, a->o.check, a->o.saturation);
  cmd->add_option("--force-window", a->force_window, "Poke start and end on the force clock (e.g. 1.9s,3.3s)");
  declare_paths(*cmd, {"--force", "--interface="}, {"-o", "--depth-table", "--plots", "--summary"});
  cmd->callback([a] { run_acquire_ultrasound(*a); });
}

struct PressureArgs {
  std::string mesh, mesh_unit = "m", locations, samples, output, method = "biharmonic";
  acquire::PressureOptions o;
  double max_distance = 5e-3;
  int trim = 50;
  int clip_run = 10;
  bool no_clamp = false;
};

CsvTable location_table(const acquire::PressureMap& m) {
  CsvTable t;
  t.add_comment("per sensor location: trimmed readings, reference, compensated and normalized pressure");
  std::vector<std::vector<double>> cols(12);
  for (const auto& l : m.locations) {
    const double row[] = {static_cast<double>(l.id),  l.position.x(),      l.position.y(),      l.position.z(),
                          static_cast<double>(l.samples), l.reading.mean,  l.reading.std,       l.reference.mean,
                          l.reference.std,            l.pressure,          l.pressure_std,      l.distance};
    for (std::size_t c = 0; c < cols.size(); ++c) cols[c].push_back(row[c]);
  }
  const char* names[] = {"location",       "x_m",       "y_m",         "z_m",
                         "samples",        "reading",   "reading-std", "reference",
                         "reference-std",  "pressure_Pa", "pressure_std_Pa", "distance_m"};
  for (std::size_t c = 0; c < cols.size(); ++c) t.add_column(names[c], std::move(cols[c]));
  return t;
}

void run_acquire_pressure(const PressureArgs& a) {
  acquire::PressureOptions o = a.o;
  const ErrorContext unit_where{"", 0, 0, "option --unit"};
  const Unit* unit = find_unit(a.mesh_unit);
  if (unit == nullptr || unit->dimension != Dimension::Length) {
    throw_input_error(fmt::format("'{}' is not a length unit", a.mesh_unit), unit_where, "a length unit such as m or mm");
  }
  if (a.method == "biharmonic") {
    o.interpolation.method = geometry::SurfaceInterpolation::Biharmonic;
  } else if (a.method == "harmonic") {
    o.interpolation.method = geometry::SurfaceInterpolation::Harmonic;
  } else {
    throw_input_error(fmt::format("unknown interpolation '{}'", a.method), ErrorContext{"", 0, 0, "option --method"},
                      "biharmonic or harmonic");
  }
  o.interpolation.max_distance = a.max_distance;
  o.interpolation.clamp_to_sample_range = !a.no_clamp;
  o.trim = static_cast<std::size_t>(a.trim);
  o.clip_run = static_cast<std::size_t>(a.clip_run);
  MeshReadOptions mo;
  mo.unit_to_si = unit->to_si;
  const SurfaceMesh mesh = read_surface_mesh(a.mesh, mo);
  const acquire::PressureMap m = acquire::pressure_map(mesh, a.locations, a.samples, o);

  const std::filesystem::path out = a.output;
  OutputFolder folder(out, OutputFolder::OnFailure::Wipe);
  PlyWriteOptions ply;
  ply.vertex_scalars = {{"pressure_Pa", m.pressure}, {"pressure_std_Pa", m.pressure_std}};
  UnstructuredGrid grid = grid_of(mesh);
  grid.point_data.push_back({"pressure_Pa", m.pressure});
  grid.point_data.push_back({"pressure_std_Pa", m.pressure_std});
  Json locations = Json::array();
  for (const auto& l : m.locations) {
    locations.push_back({{"location", l.id},
                         {"position_m", {l.position.x(), l.position.y(), l.position.z()}},
                         {"samples", l.samples},
                         {"reading_mean", l.reading.mean},
                         {"reading_std", l.reading.std},
                         {"reference_mean", l.reference.mean},
                         {"pressure_Pa", l.pressure},
                         {"pressure_std_Pa", l.pressure_std},
                         {"distance_to_surface_m", l.distance}});
  }
  const Json summary{{"mesh", a.mesh},
                     {"vertices", mesh.V.rows()},
                     {"locations_file", a.locations},
                     {"samples_file", a.samples},
                     {"load_N", o.load},
                     {"trim", o.trim},
                     {"posture_compensated", m.compensated},
                     {"interpolation", a.method},
                     {"clamped_to_sample_range", !a.no_clamp},
                     {"constant_Pa", m.constant},
                     {"net_force_N", {m.net_force.x(), m.net_force.y(), m.net_force.z()}},
                     {"pressure_min_Pa", m.pressure.minCoeff()},
                     {"pressure_max_Pa", m.pressure.maxCoeff()},
                     {"contact_area_m2", m.contact_area},
                     {"pressure_map", report::to_json(report::pressure_metrics(mesh, m.pressure))},
                     {"locations", locations}};
  OutputBatch batch;
  batch.add(out / "locations.csv") << format_csv(location_table(m));
  batch.add(out / "summary.json") << format_json(summary, out / "summary.json");
  write_ply(out / "pressure.ply", mesh, ply);
  write_vtu(out / "pressure.vtu", grid);
  batch.commit();
  folder.keep();
  spdlog::info("acquire pressure: {} locations{}, {} interpolation onto {} vertices; C = {}, pressure {} .. {}, net "
               "force {}; wrote {}",
               m.locations.size(), m.compensated ? " (posture compensated)" : "", a.method, mesh.V.rows(),
               format_quantity(m.constant, Dimension::Pressure),
               format_quantity(m.pressure.minCoeff(), Dimension::Pressure),
               format_quantity(m.pressure.maxCoeff(), Dimension::Pressure),
               format_quantity(m.net_force.norm(), Dimension::Force), out.string());
}

void add_acquire_pressure(CLI::App& acquire) {
  auto* cmd = acquire.add_subcommand(
      "pressure",
      "Pressure-sensor samples per location + reference sensor -> pressure map on the support mesh (PLY, VTU).\n"
      "  palpa acquire pressure --mesh sole.obj --unit mm --locations locations.csv --samples samples.csv \\\n"
      "      --load 343N -o pressure");
  auto a = std::make_shared<PressureArgs>();
  cmd->add_option("--mesh", a->mesh, "Support surface (OBJ, PLY, STL, OFF, VTU)")->required();
  cmd->add_option("--unit", a->mesh_unit, "Length unit of the mesh file's coordinates (default m)");
  cmd->add_option("--locations", a->locations, "Sensor locations (CSV location,x_<unit>,y_<unit>,z_<unit>)")
      ->required();
  cmd->add_option("--samples", a->samples, "Samples (CSV location,reading[,reference]; one row per sample)")
      ->required();
  add_quantity_option(*cmd, "--load", a->o.load, Dimension::Force,
                      "Net force the map must carry, e.g. half the body weight", Sign::Positive)
      ->required();
  cmd->add_option("-o,--output", a->output, "Output folder: pressure.ply, pressure.vtu, locations.csv, summary.json")
      ->required();
  cmd->add_option("--trim", a->trim, "Samples dropped at each end per location (default 50)")
      ->check(CLI::Range(0, 1000000));
  cmd->add_option("--clip-run", a->clip_run,
                  "This many identical samples in a row at a location's maximum mean a saturated sensor (default 10)")
      ->check(CLI::Range(2, 1000000));
  cmd->add_option("--method", a->method, "biharmonic (linearly precise, default) or harmonic");
  add_quantity_option(*cmd, "--max-distance", a->max_distance, Dimension::Length,
                      "Largest distance of a location from the surface (default 5 mm)", Sign::Positive);
  cmd->add_flag("--no-clamp", a->no_clamp, "Do not clamp the interpolated map to the locations' range");
  cmd->add_option("--reading-column", a->o.reading_column, "Name (or base name) of the reading column (default reading)");
  cmd->add_option("--reference-column", a->o.reference_column,
                  "Name (or base name) of the reference sensor's column (default reference; absent: no compensation)");
  declare_paths(*cmd, {"--mesh", "--locations", "--samples"}, {"-o"});
  cmd->callback([a] { run_acquire_pressure(*a); });
}

}  // namespace

void add_acquire_command(CLI::App& app) {
  auto* acquire = app.add_subcommand(
      "acquire", "Process raw measurements: poke logs, ultrasound depth picks, pressure sensors");
  acquire->require_subcommand(1);
  add_acquire_poke(*acquire);
  add_acquire_ultrasound(*acquire);
  add_acquire_pressure(*acquire);
}

}  // namespace palpa::cli
