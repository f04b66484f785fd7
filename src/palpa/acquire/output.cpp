// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/acquire/output.hpp"

#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "palpa/core/atomic_file.hpp"
#include "palpa/io/ply.hpp"
#include "palpa/io/vtu.hpp"
#include "palpa/report/pressure_metrics.hpp"

namespace palpa::acquire {

namespace {

Json window_json(const PokeWindow& w) {
  return Json{{"start_s", w.start},
              {"peak_s", w.peak},
              {"end_s", w.end},
              {"manual", w.manual},
              {"rest_before_s", {w.before.t0, w.before.t1}},
              {"rest_after_s", {w.after.t0, w.after.t1}}};
}

// How smooth a curve came out and what it left: the residual RMS is the
// noise of the force gauge as the pairs see it.
Json spline_json(const PenalizedSpline& s) {
  if (s.pairs == 0) return Json{{"smoothed", false}};  // too few pairs: straight lines between them
  return Json{{"smoothed", true}, {"pairs", s.pairs}, {"effective_dof", s.effective_dof}, {"residual_rms_N", s.rms}};
}

Json log_json(const Log& log, const PokeWindow& w) {
  return Json{{"file", log.file},
              {"column", log.value.name},
              {"samples", log.signal.size()},
              {"rate_Hz", log.rate},
              {"poke", window_json(w)}};
}

}  // namespace

CsvTable curve_table(const Curve& c, const std::string& comment) {
  CsvTable t;
  t.add_comment(comment);
  t.add_column("indentation_m", c.indentation);
  t.add_column("force_N", c.force);
  return t;
}

Json poke_summary(const PokeResult& r, const PokeOptions& o, const std::string& calibration) {
  return Json{{"force_log", log_json(r.force_log, r.force_window)},
              {"laser_log", log_json(r.laser_log, r.laser_window)},
              {"calibration", calibration},
              {"filter",
               {{"type", "Butterworth low-pass, forward-backward"}, {"order", o.order}, {"cutoff_Hz", o.cutoff}}},
              {"clock_shift_s", r.clock_shift},
              {"coarse_clock_shift_s", r.coarse_shift},
              {"rank_correlation", r.correlation},
              {"common_rate_Hz", r.common_rate},
              {"rest_distance_m", r.rest_distance},
              {"max_force_N", r.force[r.peak]},
              {"max_indentation_m", r.loading.indentation.back()},
              {"points", o.points},
              {"curves", {{"method", "P-spline through the raw (indentation, force) pairs"},
                          {"loading", spline_json(r.loading_spline)},
                          {"unloading", spline_json(r.unloading_spline)}}}};
}

void write_poke(const PokeResult& r, const PokeOptions& o, const std::string& calibration, const PokeFiles& files) {
  const std::string source = fmt::format("palpa acquire poke: {} + {}", r.force_log.file, r.laser_log.file);
  // The folder before the batch: on failure the batch's temporaries go first,
  // so that a plots folder this run created is empty again and goes too.
  std::optional<OutputFolder> plots;
  OutputBatch batch;
  batch.add(files.curve) << format_csv(curve_table(r.loading, source + "; loading (start -> maximum force)"));
  if (!files.unloading.empty()) {
    batch.add(files.unloading) << format_csv(curve_table(r.unloading, source + "; unloading (maximum force -> end)"));
  }
  if (!files.plots.empty()) {
    plots.emplace(files.plots);
    batch.add(files.plots / "signals.svg") << report::render_svg(poke_signals_figure(r));
    batch.add(files.plots / "curve.svg") << report::render_svg(poke_curve_figure(r));
  }
  if (!files.summary.empty()) batch.add(files.summary) << format_json(poke_summary(r, o, calibration), files.summary);
  batch.commit();
  if (plots) plots->keep();
}

Json ultrasound_summary(const UltrasoundResult& r, const UltrasoundOptions& o) {
  Json rest = Json::object();
  for (std::size_t k = 0; k < r.interfaces.size(); ++k) rest[r.interfaces[k].name + "_m"] = r.rest_depth[k];
  return Json{{"force_log", {{"file", r.force_log.file}, {"rate_Hz", r.force_log.rate},
                             {"poke", window_json(r.force_window)}}},
              {"clock_shift_s", r.clock_shift},
              {"aligned", o.align},
              {"rank_correlation", r.correlation},
              {"rest_depth", rest},
              {"max_force_N", r.force.back()}};
}

void write_ultrasound(const UltrasoundResult& r, const UltrasoundOptions& o, const UltrasoundFiles& files,
                      const std::optional<DepthRow>& row) {
  std::vector<std::string> names;
  for (const InterfacePicks& p : r.interfaces) names.push_back(p.name);
  CsvTable depths;
  depths.add_comment(fmt::format("palpa acquire ultrasound: {}; loading (start -> maximum force); ultrasound time {:+.4f} s "
                                 "= force time",
                                 r.force_log.file, r.clock_shift));
  depths.add_column("time_s", r.time);
  depths.add_column("force_N", r.force);
  for (std::size_t k = 0; k < names.size(); ++k) depths.add_column(names[k] + "_depth_m", r.depth[k]);
  std::optional<OutputFolder> plots;  // before the batch, as for a poke
  OutputBatch batch;
  batch.add(files.depths) << format_csv(depths);
  if (row) {
    batch.add(files.depth_table) << format_csv(
        add_depth_row(row->existing, row->position, names, r.rest_depth, row->main_interface));
  }
  if (!files.plots.empty()) {
    plots.emplace(files.plots);
    batch.add(files.plots / "depths.svg") << report::render_svg(ultrasound_figure(r));
  }
  if (!files.summary.empty()) batch.add(files.summary) << format_json(ultrasound_summary(r, o), files.summary);
  batch.commit();
  if (plots) plots->keep();
}

CsvTable pressure_location_table(const PressureMap& m) {
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

Json pressure_summary(const SurfaceMesh& mesh, const PressureMap& m, const PressureOptions& o,
                      const std::filesystem::path& mesh_file, const std::filesystem::path& locations_file,
                      const std::filesystem::path& samples_file, const std::string& method) {
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
  return Json{{"mesh", mesh_file.string()},
              {"vertices", mesh.V.rows()},
              {"locations_file", locations_file.string()},
              {"samples_file", samples_file.string()},
              {"load_N", o.load},
              {"trim", o.trim},
              {"posture_compensated", m.compensated},
              {"interpolation", method},
              {"clamped_to_sample_range", o.interpolation.clamp_to_sample_range},
              {"constant_Pa", m.constant},
              {"net_force_N", {m.net_force.x(), m.net_force.y(), m.net_force.z()}},
              {"pressure_min_Pa", m.pressure.minCoeff()},
              {"pressure_max_Pa", m.pressure.maxCoeff()},
              {"contact_area_m2", m.contact_area},
              {"reach_m", std::isfinite(m.reach) ? Json(m.reach) : Json(nullptr)},
              {"covered_area_m2", m.covered_area},
              {"pressure_map", report::to_json(report::pressure_metrics(mesh, m.pressure))},
              {"locations", locations}};
}

void write_pressure_map(const SurfaceMesh& mesh, const PressureMap& m, const Json& summary,
                        const std::filesystem::path& out) {
  OutputFolder folder(out, OutputFolder::OnFailure::Wipe);
  PlyWriteOptions ply;
  ply.vertex_scalars = {{"pressure_Pa", m.pressure}, {"pressure_std_Pa", m.pressure_std}};
  UnstructuredGrid grid = grid_of(mesh);
  grid.point_data.push_back({"pressure_Pa", m.pressure});
  grid.point_data.push_back({"pressure_std_Pa", m.pressure_std});
  OutputBatch batch;
  batch.add(out / "locations.csv") << format_csv(pressure_location_table(m));
  batch.add(out / "summary.json") << format_json(summary, out / "summary.json");
  write_ply(out / "pressure.ply", mesh, ply);
  write_vtu(out / "pressure.vtu", grid);
  batch.commit();
  folder.keep();
}

}  // namespace palpa::acquire
