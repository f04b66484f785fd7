// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/fit/output.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/json.hpp"
#include "palpa/core/progress.hpp"
#include "palpa/core/version.hpp"
#include "palpa/fit/simulate.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/material/material_file.hpp"
#include "palpa/report/html.hpp"
#include "palpa/report/plot.hpp"

namespace palpa::fit {

namespace {

// Display units of a dataset's curves.
struct CurveUnits {
  const char* x_label;
  const char* y_label;
  double x_factor;  // SI -> display
  double y_factor;
};

CurveUnits units_of(const Dataset& d) {
  if (d.test == TestKind::Homogeneous) return {"stretch (shear: gamma)", "nominal stress [kPa]", 1.0, 1e-3};
  if (d.test == TestKind::Compression) return {"platen travel [mm]", "force [N]", 1e3, 1.0};
  return {"indentation [mm]", "force [N]", 1e3, 1.0};
}

std::string curve_label(const Dataset& d, const MeasuredCurve& c) {
  if (d.test == TestKind::Indentation) return fmt::format("a = {:.3g} mm", c.radius * 1e3);
  return c.name;
}

std::vector<double> times(const std::vector<double>& v, double f) {
  std::vector<double> out(v.size());
  std::transform(v.begin(), v.end(), out.begin(), [f](double x) { return x * f; });
  return out;
}

report::Plot curves_plot(const Dataset& d, const std::vector<CurvePrediction>& pred,
                         const std::string& title) {
  const CurveUnits u = units_of(d);
  report::Plot p;
  p.title = title;
  p.x.label = u.x_label;
  p.y.label = u.y_label;
  for (std::size_t i = 0; i < d.curves.size(); ++i) {
    const auto& c = d.curves[i];
    const int color = static_cast<int>(i);
    const bool train = c.role == CurveRole::Train;
    p.series.push_back(report::Series{fmt::format("{} ({})", curve_label(d, c), train ? "train" : "validate"),
                                      times(c.x, u.x_factor), times(c.y, u.y_factor), report::Mark::Dots, color,
                                      false});
    p.series.push_back(report::Series{"", times(pred[i].grid_x, u.x_factor), times(pred[i].grid_y, u.y_factor),
                                      report::Mark::Line, color, !train});
  }
  return p;
}

struct Errors {
  double sq_train = 0.0, sq_validate = 0.0;
  std::size_t n_train = 0, n_validate = 0, n_validate_total = 0;
  std::vector<std::string> short_curves;  // validation curves simulated part way
};

Json estimate_json(const Estimate& e) {
  return Json{{"name", e.name},
              {"value", number_or_null(e.value)},
              {"standard_error", number_or_null(e.standard_error)},
              {"lo95", number_or_null(e.lo)},
              {"hi95", number_or_null(e.hi)}};
}

Json uncertainty_json(const Uncertainty& u) {
  Json estimates = Json::array(), names = Json::array(), matrix = Json::array();
  for (const auto& e : u.estimates) {
    estimates.push_back(estimate_json(e));
    names.push_back(e.name);
  }
  for (Eigen::Index i = 0; i < u.correlation.rows(); ++i) {
    Json row = Json::array();
    for (Eigen::Index j = 0; j < u.correlation.cols(); ++j) row.push_back(number_or_null(u.correlation(i, j)));
    matrix.push_back(row);
  }
  return Json{{"defined", u.defined},
              {"why_not", u.why_not.empty() ? Json(nullptr) : Json(u.why_not)},
              {"points", u.points},
              {"free_parameters", u.free_parameters},
              {"effective_parameters", u.effective_parameters},
              {"residual_sd", number_or_null(u.sigma)},
              {"t95", number_or_null(u.t95)},
              {"estimates", estimates},
              {"correlation", {{"names", names}, {"matrix", matrix}}},
              {"held_at_bound", u.held},
              {"undetermined", u.undetermined},
              {"method", "Gauss-Newton covariance s^2 (J^T J)^-1 at the minimum, s^2 = eps/(m - n); delta method "
                         "for E and nu; layer depth from a parabola through eps at the best depth and its "
                         "neighbours"}};
}

// report.html: the material, the fit's figures, the curves and the search
// (the report.json members a person reads first).
report::HtmlReport fit_report_html(const Dataset& d, const Json& rep, const material::Material& m,
                                   const std::string& curves_svg,
                                   const std::vector<report::HtmlReport::Picture>& search) {
  report::HtmlReport h(fmt::format("palpa fit: {}", d.sample),
                       fmt::format("{} fitted to {} curve(s) of {}; {}", rep.at("model").get<std::string>(),
                                   d.curves.size(), d.file.string(), rep.at("termination").get<std::string>()));
  h.heading("Material");
  std::vector<std::vector<std::string>> params;
  const Eigen::VectorXd theta = m.params();
  for (Eigen::Index k = 0; k < theta.size(); ++k) {
    const material::ParamInfo info = m.param_info(k);
    params.push_back({info.name, format_quantity(theta[k], info.dimension), info.meaning});
  }
  const material::ElasticConstants ec = material::small_strain_constants(m);
  params.push_back({"E (small strain)", format_quantity(ec.young(), Dimension::Pressure), "Young's modulus at rest"});
  params.push_back({"nu (small strain)", fmt::format("{:.4g}", ec.poisson()), "Poisson's ratio at rest"});
  if (d.test != TestKind::Homogeneous) {
    params.push_back({"layer depth", format_quantity(rep.at("layer_depth_m").get<double>(), Dimension::Length),
                      d.depth_search() ? "found by the search" : "given"});
  }
  h.table({"parameter", "value", "meaning"}, params);
  h.heading("Curves: measured and fitted");
  h.pictures({{curves_svg, "measured curves with the stage-1 and fitted materials' predictions"}});
  std::vector<std::vector<std::string>> rows;
  const char* unit = d.test == TestKind::Homogeneous ? "Pa" : "N";
  const auto figure = [](const Json& j) { return j.is_null() ? std::string("-") : fmt::format("{:.4g}", j.get<double>()); };
  for (const Json& c : rep.at("curves")) {
    rows.push_back({c.at("name").get<std::string>(), c.at("role").get<std::string>(),
                    c.contains("radius_m") ? format_quantity(c.at("radius_m").get<double>(), Dimension::Length) : "-",
                    std::to_string(c.at("points").get<int>()), figure(c.at("largest_measured")),
                    figure(c.at("rms_error_stage1")), figure(c.at("rms_error_fitted"))});
  }
  h.table({"curve", "role", "punch radius", "points", fmt::format("largest [{}]", unit),
           fmt::format("RMS error, stage 1 [{}]", unit), fmt::format("RMS error, fitted [{}]", unit)},
          rows);
  h.heading("The optimization");
  h.table({"iterations", "seconds", "termination", "stop reason"},
          {{std::to_string(rep.at("iterations").get<int>()), fmt::format("{:.1f}", rep.at("seconds").get<double>()),
            rep.at("termination").get<std::string>(), rep.at("stop_reason").get<std::string>()}});
  h.pictures(search);
  return h;
}

}  // namespace

std::vector<std::filesystem::path> fit_output_files(const std::filesystem::path& out, const Dataset& d) {
  std::vector<std::filesystem::path> files;
  for (const char* name :
       {"checkpoint.json", "report.json", "material.json", "curves.svg", "objective.svg", "report.html"}) {
    files.push_back(out / name);
  }
  if (d.depth_search()) files.push_back(out / "depth.svg");
  for (const auto& c : d.curves) files.push_back(out / "curves" / (c.name + ".csv"));
  return files;
}

FitSummary write_fit_outputs(const std::filesystem::path& out, const Dataset& d, const FitOptions& o,
                             const FitResult& r, double seconds, const std::string& command) {
  const GuessResult& best = r.guesses[r.best];
  // Every curve, train and validate, with the stage-1 and fitted materials: a
  // line per curve as it finishes (the deep ones take minutes).
  Progress progress("fit curves (stage 1 and fitted, every curve)", 2 * d.curves.size());
  const auto curves_of = predict_curves(
      d, best.layer_depth, std::vector<const material::Material*>{best.stage1_material.get(), best.material.get()},
      o.simulation, [&](std::size_t m, std::size_t i) {
        progress.set_note(fmt::format("{} ({}) done", d.curves[i].name, m == 0 ? "stage 1" : "fitted"));
        progress.advance();
      });
  progress.finish();
  const std::vector<CurvePrediction>& before = curves_of[0];
  const std::vector<CurvePrediction>& after = curves_of[1];

  ensure_directory(out);
  // (a failed write, a full disk, leaves no empty curves/ behind)
  OutputFolder curve_folder(out / "curves", OutputFolder::OnFailure::RemoveIfEmpty, OutputFolder::Lock::None);
  OutputBatch batch;

  // Per-curve CSVs and errors.
  Json curves = Json::array();
  Errors err;
  for (std::size_t i = 0; i < d.curves.size(); ++i) {
    const auto& c = d.curves[i];
    // Rows up to the deepest point both simulations reached (all, normally).
    std::size_t rows = c.x.size();
    while (rows > 0 && !(std::isfinite(before[i].y[rows - 1]) && std::isfinite(after[i].y[rows - 1]))) --rows;
    const auto head = [rows](const std::vector<double>& v) {
      return std::vector<double>(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(rows));
    };
    CsvTable t;
    t.add_comment(fmt::format("palpa fit: {} curve '{}' of {} ({}), layer depth {} m", to_string(c.role), c.name,
                              d.file.filename().string(), d.sample, best.layer_depth));
    if (rows < c.x.size()) {
      t.add_comment(fmt::format("the simulations stopped early: {} of {} measured points", rows, c.x.size()));
    }
    if (d.test == TestKind::Homogeneous) {
      t.add_column(c.load_case == material::LoadCase::SimpleShear ? "shear" : "stretch", head(c.x));
      t.add_quantity("stress_measured", "Pa", Dimension::Pressure, head(c.y));
      t.add_quantity("stress_stage1", "Pa", Dimension::Pressure, head(before[i].y));
      t.add_quantity("stress_fitted", "Pa", Dimension::Pressure, head(after[i].y));
    } else {
      t.add_quantity("indentation", "m", Dimension::Length, head(c.x));
      t.add_quantity("force_measured", "N", Dimension::Force, head(c.y));
      t.add_quantity("force_stage1", "N", Dimension::Force, head(before[i].y));
      t.add_quantity("force_fitted", "N", Dimension::Force, head(after[i].y));
    }
    batch.add(out / "curves" / (c.name + ".csv")) << format_csv(t);
    const double ss = sum_of_squares(c, after[i]);
    double max_err = 0.0;
    for (std::size_t j = 0; j < c.y.size(); ++j) {
      if (std::isfinite(after[i].y[j])) max_err = std::max(max_err, std::abs(after[i].y[j] - c.y[j]));
    }
    const std::size_t compared = compared_points(c, after[i]);
    if (c.role == CurveRole::Train) {
      err.sq_train += ss;
      err.n_train += compared;
    } else {
      err.sq_validate += ss;
      err.n_validate += compared;
      err.n_validate_total += c.y.size();
      if (compared < c.y.size()) {
        const double f = d.test == TestKind::Homogeneous ? 1.0 : 1e3;
        err.short_curves.push_back(fmt::format("{} to {:.3g} of {:.3g}{}", c.name, after[i].reached * f,
                                               c.x.back() * f, d.test == TestKind::Homogeneous ? "" : " mm"));
      }
    }
    for (const auto* p : {&before[i], &after[i]}) {
      if (!p->failure.empty()) {
        spdlog::warn("fit: curve {} was simulated only to {:.4g} mm of {:.4g} mm with the {} material ({}); its "
                     "errors cover the points up to there",
                     c.name, p->reached * 1e3, c.x.back() * 1e3, p == &before[i] ? "stage-1" : "fitted", p->failure);
      }
    }
    Json cj{{"name", c.name},
            {"role", std::string(to_string(c.role))},
            {"file", c.file.string()},
            {"points", c.y.size()},
            {"rms_error_stage1", number_or_null(rms_error(c, before[i]))},
            {"rms_error_fitted", number_or_null(rms_error(c, after[i]))},
            {"max_abs_error_fitted", max_err},
            {"largest_measured", *std::max_element(c.y.begin(), c.y.end())},
            {"points_compared_fitted", compared},
            {"simulated_to_fitted", after[i].reached},
            {"simulation_failure_fitted", after[i].failure.empty() ? Json(nullptr) : Json(after[i].failure)}};
    if (d.test != TestKind::Homogeneous) cj["radius_m"] = c.radius;
    curves.push_back(cj);
  }

  FitSummary s;
  s.sqrt_objective_stage1 = std::sqrt(best.objective_stage1);
  s.sqrt_objective_final = std::sqrt(best.objective_final);
  s.rms_train = err.n_train ? std::sqrt(err.sq_train / static_cast<double>(err.n_train)) : 0.0;
  s.rms_validate = err.n_validate ? std::sqrt(err.sq_validate / static_cast<double>(err.n_validate))
                                  : std::numeric_limits<double>::quiet_NaN();
  s.validate_points = err.n_validate;
  s.validate_points_total = err.n_validate_total;
  s.validate_short = err.short_curves;
  s.seconds = seconds;

  const auto starts_json = [](const std::vector<StartTrial>& starts) {
    Json a = Json::array();
    for (const auto& t : starts) {
      a.push_back({{"label", t.label},
                   {"objective_start", number_or_null(t.objective_start)},
                   {"objective_end", number_or_null(t.objective_end)},
                   {"evaluations", t.evaluations}});
    }
    return a;
  };
  Json guesses = Json::array();
  for (const auto& g : r.guesses) {
    Json hist = Json::array();
    for (const auto& h : g.history) {
      hist.push_back({{"iteration", h.iteration}, {"objective", h.objective}, {"evaluations", h.evaluations},
                      {"seconds", h.seconds}});
    }
    guesses.push_back({{"layer_depth_m", g.layer_depth},
                       {"modulus_scale", g.modulus_scale},
                       {"young_stage1_Pa", material::small_strain_constants(*g.stage1_material).young()},
                       {"objective_initial", number_or_null(g.objective_initial)},
                       {"objective_stage1", number_or_null(g.objective_stage1)},
                       {"objective_final", number_or_null(g.objective_final)},
                       {"iterations", g.iterations},
                       {"evaluations", g.evaluations},
                       {"seconds", g.seconds},
                       {"termination", std::string(to_string(g.stop.termination))},
                       {"stop_reason", g.stop.detail},
                       {"starts", starts_json(g.starts)},
                       {"history", hist}});
  }
  const material::ElasticConstants ec = material::small_strain_constants(*best.material);
  const char* unit = d.test == TestKind::Homogeneous ? "Pa" : "N";
  Json report{
      {"palpa_fit_report", 1},
      {"palpa_version", std::string(kVersion)},
      {"command", command},
      {"dataset", d.file.string()},
      {"sample", d.sample},
      {"test", std::string(to_string(d.test))},
      {"model", o.model},
      {"optimizer", std::string(to_string(o.optimizer))},
      {"mesh_level", o.simulation.mesh_level},
      {"extrapolated", d.test != TestKind::Homogeneous && !d.curves.empty() &&
                           axisym::extrapolates(poke_setup(d, d.curves.front(), best.layer_depth, o.simulation))},
      {"steps", o.simulation.steps},
      {"residual_unit", unit},
      {"layer_depth_m", best.layer_depth},
      {"depth_search", d.depth_search()},
      {"training_points", r.training_points},
      {"objective", {{"initial", best.objective_initial},
                     {"stage1", best.objective_stage1},
                     {"final", best.objective_final},
                     {"sqrt_stage1", s.sqrt_objective_stage1},
                     {"sqrt_final", s.sqrt_objective_final}}},
      {"rms_error", {{"train", s.rms_train},
                     {"validate", number_or_null(s.rms_validate)},
                     {"validate_points", s.validate_points},
                     {"validate_points_measured", s.validate_points_total},
                     {"validate_curves_short", s.validate_short}}},
      {"depth_from", d.depth_search() ? Json(std::string(to_string(o.depth_from))) : Json(nullptr)},
      {"small_indentation_profile",
       r.small_profile ? Json{{"objective", r.small_profile->objective},
                              {"young_Pa", r.small_profile->young},
                              {"training_points", r.small_profile->points},
                              {"deepest_indentation_m", r.small_profile->cut},
                              {"rule", fmt::format("indentations up to {:g} min(punch radius, shallowest guess)",
                                                   kSmallIndentation)}}
                       : Json(nullptr)},
      {"uncertainty", uncertainty_json(r.uncertainty)},
      {"warnings", r.warnings},
      {"small_strain", {{"young_Pa", ec.young()}, {"poisson", ec.poisson()}, {"shear_Pa", ec.mu}}},
      {"iterations", best.iterations},
      {"evaluations", best.evaluations},
      {"seconds", seconds},
      {"termination", std::string(to_string(best.stop.termination))},
      {"stop_reason", best.stop.detail},
      {"curves", curves},
      {"guesses", guesses}};
  batch.add(out / "report.json") << format_json(report, out / "report.json");

  // Material with provenance.
  material::Provenance prov = material::make_provenance(command);
  prov.objective = best.objective_final;
  prov.details = Json{{"dataset", d.file.string()},
                      {"sample", d.sample},
                      {"layer_depth_m", best.layer_depth},
                      {"objective_unit", fmt::format("{}^2", unit)},
                      {"rms_error_train", s.rms_train},
                      {"rms_error_validate", number_or_null(s.rms_validate)}};
  // (written through the material module so the format stays in one place)
  const std::filesystem::path material_path = out / "material.json";

  // Plots.
  report::Figure fc;
  fc.title = fmt::format("{}: {} fit", d.sample.empty() ? d.file.stem().string() : d.sample, o.model);
  if (d.test == TestKind::Indentation) fc.title += fmt::format(", layer depth {:.3g} mm", best.layer_depth * 1e3);
  fc.columns = 2;
  fc.plots.push_back(curves_plot(d, before, fmt::format("stage 1 (modulus): sqrt(eps) = {:.3g} {}",
                                                        s.sqrt_objective_stage1, unit)));
  fc.plots.push_back(curves_plot(d, after, fmt::format("fitted {}: sqrt(eps) = {:.3g} {}", o.model,
                                                       s.sqrt_objective_final, unit)));
  if (d.test != TestKind::Homogeneous) {
    for (auto& p : fc.plots) p.y.min = 0.0;
  }
  const std::string curves_svg = report::render_svg(fc);
  batch.add(out / "curves.svg") << curves_svg;

  report::Figure fo;
  fo.title = "objective per iteration";
  report::Plot po;
  po.title = fmt::format("eps [{}^2] ({}, {})", unit, o.model, to_string(o.optimizer));
  po.x.label = "iteration";
  po.y.label = fmt::format("eps [{}^2]", unit);
  po.y.log = true;
  for (std::size_t g = 0; g < r.guesses.size(); ++g) {
    std::vector<double> it, e;
    for (const auto& h : r.guesses[g].history) {
      it.push_back(h.iteration);
      e.push_back(h.objective);
    }
    po.series.push_back(report::Series{d.depth_search() ? fmt::format("D = {:.3g} mm", r.guesses[g].layer_depth * 1e3)
                                                        : std::string("eps"),
                                       it, e, report::Mark::LineDots, static_cast<int>(g), g != r.best});
  }
  fo.plots.push_back(po);
  const std::string objective_svg = report::render_svg(fo);
  batch.add(out / "objective.svg") << objective_svg;
  std::vector<report::HtmlReport::Picture> search_pictures{{objective_svg, "objective per iteration"}};

  if (d.depth_search()) {
    report::Figure fd;
    fd.title = "layer-depth search";
    report::Plot pd;
    pd.title = fmt::format("best layer depth {:.3g} mm", best.layer_depth * 1e3);
    pd.x.label = "layer depth guess [mm]";
    pd.y.label = fmt::format("eps [{}^2]", unit);
    pd.y.log = true;
    std::vector<double> dd, e1, ef;
    for (const auto& g : r.guesses) {
      dd.push_back(g.layer_depth * 1e3);
      e1.push_back(g.objective_stage1);
      ef.push_back(g.objective_final);
    }
    if (r.small_profile) {
      pd.title = fmt::format("layer depth {:.3g} mm, chosen on the small indentations", best.layer_depth * 1e3);
      pd.series.push_back(report::Series{"small indentations, stage 1 (modulus)", dd, r.small_profile->objective,
                                         report::Mark::LineDots, 2, false});
      pd.series.push_back(report::Series{fmt::format("fitted {} (all points)", o.model), {best.layer_depth * 1e3},
                                         {best.objective_final}, report::Mark::Dots, 0, false});
    } else {
      pd.series.push_back(report::Series{"after stage 1 (modulus)", dd, e1, report::Mark::LineDots, 1, true});
      pd.series.push_back(
          report::Series{fmt::format("fitted {}", o.model), dd, ef, report::Mark::LineDots, 0, false});
    }
    fd.plots.push_back(pd);
    const std::string depth_svg = report::render_svg(fd);
    batch.add(out / "depth.svg") << depth_svg;
    search_pictures.push_back({depth_svg, "layer-depth search"});
  }
  batch.add(out / "report.html") << fit_report_html(d, report, *best.material, curves_svg, search_pictures).html();
  batch.commit();
  curve_folder.keep();
  material::write_material_file(material_path, *best.material, prov);
  return s;
}

std::string validation_text(const FitSummary& s, const char* unit) {
  if (s.validate_points_total == 0) return "n/a (no validation curve)";
  if (s.validate_points == 0) return "n/a (no validation point could be simulated)";
  std::string text = fmt::format("{:.3g} {}", s.rms_validate, unit);
  if (s.validate_points < s.validate_points_total) {
    text += fmt::format(" (over {} of {} points: simulated {})", s.validate_points, s.validate_points_total,
                        fmt::join(s.validate_short, ", "));
  }
  return text;
}

std::string estimates_text(const Uncertainty& u, const material::Material& m, double layer_depth) {
  const material::ElasticConstants c = material::small_strain_constants(m);
  const auto pressure = [](double v) { return fmt::format("{:.4g} kPa", v * 1e-3); };
  if (!u.defined) {
    return fmt::format("E (small strain) = {}, nu = {:.4g} (no intervals: {})", pressure(c.young()), c.poisson(),
                       u.why_not);
  }
  const bool nu_held = std::find(u.held.begin(), u.held.end(), "nu") != u.held.end();
  std::string text;
  if (const Estimate* e = u.find("E")) {
    text += std::isfinite(e->standard_error)
                ? fmt::format("E (small strain) = {}, 95% {:.4g} to {}", pressure(e->value), e->lo * 1e-3,
                              pressure(e->hi))
                : fmt::format("E (small strain) = {} (not determined by the curves)", pressure(e->value));
    if (nu_held) text += " given nu";
  }
  if (const Estimate* nu = u.find("nu")) {
    if (nu_held) {
      text += fmt::format("; nu = {:.5g} (at an end of its range)", nu->value);
    } else if (!std::isfinite(nu->standard_error)) {
      text += fmt::format("; nu = {:.5g} (not determined by the curves)", nu->value);
    } else if (nu->standard_error > 0.0) {
      text += fmt::format("; nu = {:.5g}, 95% {:.5g} to {:.5g}", nu->value, nu->lo, nu->hi);
    } else {
      text += fmt::format("; nu = {:.5g} (held)", nu->value);
    }
  }
  if (const Estimate* dd = u.find("layer_depth")) {
    text += fmt::format("; layer depth {:.3g} mm", layer_depth * 1e3);
    if (std::isfinite(dd->standard_error)) {
      text += fmt::format(" (the objective's minimum {:.3g} mm, 95% {:.3g} to {:.3g} mm)", dd->value * 1e3,
                          dd->lo * 1e3, dd->hi * 1e3);
    }
  }
  return text;
}

}  // namespace palpa::fit
