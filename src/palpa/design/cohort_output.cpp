// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/design/cohort_output.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/design/average_impression.hpp"
#include "palpa/design/cohort.hpp"
#include "palpa/io/mesh.hpp"
#include "palpa/design/output.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/report/plot.hpp"
#include "palpa/report/pressure_map_svg.hpp"
#include "palpa/rest/output.hpp"

namespace palpa::design {

namespace {

// One body of the cohort from scratch on the initial and the optimized
// support, its files written into its folder.
struct BodyOutcome {
  std::string name, slug;
  Evaluation before, after;
  Json summary;
};

double body_peak(const Evaluation& e) { return e.body().score.body_pressure.maxCoeff(); }
double body_ppi(const Evaluation& e) { return e.body().rest.body_metrics.peak_pressure_index; }

BodyOutcome solve_body(const std::filesystem::path& out, const CohortMember& m, std::size_t i,
                       const ShapeOptimizer& optimizer, const SurfaceMesh& initial, const SurfaceMesh& optimized,
                       double threshold) {
  BodyOutcome b;
  b.name = m.name;
  b.slug = baseline_slug(m.name);
  std::unique_ptr<rest::RestSimulation> sb, sa;
  b.before = optimizer.solve_from_scratch(m.rest.body, initial, &sb, i);
  if (!b.before.ok) {
    throw Error(ErrorKind::Solver, fmt::format("the body '{}' on the initial support, from scratch: {}", m.name,
                                               b.before.failure));
  }
  b.after = optimizer.solve_from_scratch(m.rest.body, optimized, &sa, i);
  if (!b.after.ok) {
    throw Error(ErrorKind::Solver, fmt::format("the body '{}' on the optimized support, from scratch: {}", m.name,
                                               b.after.failure));
  }
  const std::filesystem::path dir = out / "bodies" / b.slug;
  ensure_directory(dir);
  const Eigen::MatrixX3d displacement = optimized.V - initial.V;
  const Json pts_before = write_design_state(dir, "before", *sb, b.before, nullptr, threshold);
  const Json pts_after = write_design_state(dir, "after", *sa, b.after, &displacement, threshold);
  const Eigen::Vector3d toward_body = rest::support_to_body(b.before.body().rest);
  report::PressureMapOptions body_view = rest::body_pressure_view(toward_body);
  body_view.title = fmt::format("contact pressure on the body '{}': initial and cohort-optimized support", m.name);
  report::write_pressure_map_svg(
      dir / "body_pressure.svg",
      {rest::body_pressure_panel(*sb, b.before.body().rest, "body side, initial support"),
       rest::body_pressure_panel(*sa, b.after.body().rest, "body side, the cohort's support")},
      body_view);
  report::PressureMapOptions support_view = rest::support_pressure_view(toward_body);
  support_view.title = fmt::format("contact pressure on the support under '{}': initial and cohort-optimized", m.name);
  report::write_pressure_map_svg(
      dir / "support_pressure.svg",
      {rest::support_pressure_panel(*sb, b.before.body().rest, "support side, initial shape"),
       rest::support_pressure_panel(*sa, b.after.body().rest, "support side, the cohort's shape")},
      support_view);
  b.summary = {{"name", m.name},
               {"source", m.source},
               {"body", m.rest.body_source},
               {"folder", (std::filesystem::path("bodies") / b.slug).string()},
               {"initial", evaluation_json(b.before, 0.0)},
               {"final", evaluation_json(b.after, 0.0)},
               {"zeta_ratio", b.after.zeta / b.before.zeta},
               {"zeta_body_ratio", b.after.body().score.zeta_body / b.before.body().score.zeta_body},
               {"body_peak_ratio", body_peak(b.before) / body_peak(b.after)},
               {"pose_to_seat", {{"threshold_m", threshold}, {"before", pts_before}, {"after", pts_after}}}};
  spdlog::info("design: body '{}' from scratch: ζ_body {:.6g} → {:.6g} ({:.1f}% lower), body peak {:.3g} → {:.3g} kPa",
               m.name, b.before.body().score.zeta_body, b.after.body().score.zeta_body,
               100.0 * (1.0 - b.after.body().score.zeta_body / b.before.body().score.zeta_body),
               body_peak(b.before) * 1e-3, body_peak(b.after) * 1e-3);
  return b;
}

void write_cohort_table(const std::filesystem::path& file, const std::vector<BodyOutcome>& bodies,
                        const std::vector<Json>& singles, const std::vector<double>& baseline) {
  CsvTable t(file.string());
  std::vector<std::string> names;
  std::vector<double> index;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    names.push_back(fmt::format("{} {}", i + 1, bodies[i].name));
    index.push_back(static_cast<double>(i + 1));
  }
  t.add_comment("one support for a cohort: each body re-solved from scratch on the initial and on the optimized "
                "support");
  t.add_comment(fmt::format("bodies: {}", fmt::join(names, ", ")));
  t.add_column("body", index);
  const auto column = [&](auto f) {
    std::vector<double> v;
    for (const BodyOutcome& b : bodies) v.push_back(f(b));
    return v;
  };
  t.add_column("zeta_body_initial", column([](const BodyOutcome& b) { return b.before.body().score.zeta_body; }));
  t.add_column("zeta_body_final", column([](const BodyOutcome& b) { return b.after.body().score.zeta_body; }));
  t.add_column("zeta_body_ratio", column([](const BodyOutcome& b) {
                 return b.after.body().score.zeta_body / b.before.body().score.zeta_body;
               }));
  t.add_quantity("peak_initial", "kPa", Dimension::Pressure, column([](const BodyOutcome& b) { return body_peak(b.before); }));
  t.add_quantity("peak_final", "kPa", Dimension::Pressure, column([](const BodyOutcome& b) { return body_peak(b.after); }));
  t.add_quantity("ppi_initial", "kPa", Dimension::Pressure, column([](const BodyOutcome& b) { return body_ppi(b.before); }));
  t.add_quantity("ppi_final", "kPa", Dimension::Pressure, column([](const BodyOutcome& b) { return body_ppi(b.after); }));
  t.add_quantity("mean_initial", "kPa", Dimension::Pressure,
                 column([](const BodyOutcome& b) { return b.before.body().rest.body_metrics.mean; }));
  t.add_quantity("mean_final", "kPa", Dimension::Pressure,
                 column([](const BodyOutcome& b) { return b.after.body().rest.body_metrics.mean; }));
  t.add_column("contact_area_initial_m2",
               column([](const BodyOutcome& b) { return b.before.body().rest.body_metrics.contact_area; }));
  t.add_column("contact_area_final_m2",
               column([](const BodyOutcome& b) { return b.after.body().rest.body_metrics.contact_area; }));
  if (!singles.empty()) {
    std::vector<double> own;
    for (const Json& j : singles) own.push_back(j.at("zeta_body_ratio").get<double>());
    t.add_column("zeta_body_ratio_own_design", own);
  }
  if (!baseline.empty()) t.add_column("zeta_body_ratio_average_negative_image", baseline);
  write_csv(file, t);
}

// The cohort's spread: each body's ζ_body over its initial value, and its
// peak, before and after.
void write_cohort_plot(const std::filesystem::path& file, const std::vector<BodyOutcome>& bodies,
                       const std::vector<Json>& singles, const std::vector<double>& baseline) {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < bodies.size(); ++i) names.push_back(fmt::format("{} {}", i + 1, bodies[i].name));
  const std::string axis = bodies.size() <= 6 ? fmt::format("body ({})", fmt::join(names, ", ")) : "body (cohort.csv)";
  report::Series ratio_before{"initial support", {}, {}, report::Mark::Dots};
  report::Series ratio_after{"the cohort's support", {}, {}, report::Mark::Dots};
  report::Series peak_before{"initial support", {}, {}, report::Mark::Dots};
  report::Series peak_after{"the cohort's support", {}, {}, report::Mark::Dots};
  double mean = 0.0;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const double x = static_cast<double>(i + 1);
    const double r = bodies[i].after.body().score.zeta_body / bodies[i].before.body().score.zeta_body;
    mean += r / static_cast<double>(bodies.size());
    ratio_before.x.push_back(x);
    ratio_before.y.push_back(1.0);
    ratio_after.x.push_back(x);
    ratio_after.y.push_back(r);
    peak_before.x.push_back(x);
    peak_before.y.push_back(body_peak(bodies[i].before) * 1e-3);
    peak_after.x.push_back(x);
    peak_after.y.push_back(body_peak(bodies[i].after) * 1e-3);
  }
  const double n = static_cast<double>(bodies.size());
  report::Series mean_line{fmt::format("mean {:.3f}", mean), {0.5, n + 0.5}, {mean, mean}};
  mean_line.dashed = true;
  mean_line.color = 1;
  report::Plot ratios;
  ratios.title = "ζ_body over its initial value (from scratch)";
  ratios.x = {axis, false, 0.5, n + 0.5};
  ratios.y = {"ζ_body / initial ζ_body", false, 0.0, std::nullopt};
  ratios.series = {ratio_before, ratio_after, mean_line};
  if (!singles.empty()) {
    report::Series own{"each body's own design", {}, {}, report::Mark::Dots};
    own.color = 2;
    for (std::size_t i = 0; i < singles.size(); ++i) {
      own.x.push_back(static_cast<double>(i + 1));
      own.y.push_back(singles[i].at("zeta_body_ratio").get<double>());
    }
    ratios.series.push_back(own);
  }
  if (!baseline.empty()) {
    report::Series hollow{"negative image of the average body", {}, {}, report::Mark::Dots};
    hollow.color = 3;
    for (std::size_t i = 0; i < baseline.size(); ++i) {
      hollow.x.push_back(static_cast<double>(i + 1));
      hollow.y.push_back(baseline[i]);
    }
    ratios.series.push_back(hollow);
  }
  report::Plot peaks;
  peaks.title = "the body's peak pressure (from scratch)";
  peaks.x = {axis, false, 0.5, n + 0.5};
  peaks.y = {"peak pressure [kPa]", false, 0.0, std::nullopt};
  peaks.series = {peak_before, peak_after};
  report::Figure fig;
  fig.plots = {ratios, peaks};
  fig.columns = 2;
  fig.title = fmt::format("one support for {} bodies", bodies.size());
  report::write_svg(file, fig);
}

}  // namespace

Json write_cohort_outputs(const std::filesystem::path& out, const DesignScene& scene, ShapeOptimizer& optimizer,
                          const DesignResult& r, const std::vector<Json>& singles) {
  ensure_directory(out);
  const Eigen::MatrixX3i& F = optimizer.simulation().support().triangles();
  // Every figure against the scene's support (where the design began, or
  // the flat seat a start on the baseline was made from).
  const SurfaceMesh initial{scene.rest.support.V, F}, optimized{r.final.support, F};
  write_support_shape(out, "support", optimized);
  const double threshold = scene.options.pose_to_seat_threshold;
  std::vector<BodyOutcome> bodies;
  for (std::size_t i = 0; i < scene.cohort.size(); ++i) {
    bodies.push_back(solve_body(out, scene.cohort[i], i, optimizer, initial, optimized, threshold));
  }
  for (std::size_t i = 0; i < singles.size(); ++i) bodies[i].summary["own_design"] = singles[i];
  // The negative image of the average body, as a workshop would make one
  // support for all: each body on it from scratch.
  std::vector<double> baseline;
  Eigen::VectorXd baseline_zeta(static_cast<Eigen::Index>(bodies.size()));  // ζ on it, from scratch
  Json baseline_json;
  Json worse_than = Json::array();
  if (scene.cohort_baseline) {
    std::vector<const rest::RestBody*> placed;
    for (const CohortMember& m : scene.cohort) placed.push_back(&m.rest.body);
    const SurfaceMesh hollow = average_impression(placed, initial, optimizer.space().vertices(),
                                                  scene.rest.options.gravity, *scene.cohort_baseline);
    write_surface_mesh(out / "baseline_average_negative_image.obj", hollow);
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      const Evaluation e = optimizer.solve_from_scratch(scene.cohort[i].rest.body, hollow, nullptr, i);
      if (!e.ok) {
        throw Error(ErrorKind::Solver, fmt::format("the body '{}' on the negative image of the average body, from "
                                                   "scratch: {}",
                                                   bodies[i].name, e.failure));
      }
      const double on_it = e.body().score.zeta_body / bodies[i].before.body().score.zeta_body;
      baseline.push_back(on_it);
      baseline_zeta[static_cast<Eigen::Index>(i)] = e.zeta;
      bodies[i].summary["average_negative_image"] = {{"zeta_body_ratio", on_it},
                                                     {"peak_pressure_Pa", body_peak(e)},
                                                     {"final", evaluation_json(e, 0.0)}};
      const double cohort_ratio = bodies[i].after.body().score.zeta_body / bodies[i].before.body().score.zeta_body;
      if (on_it < cohort_ratio) worse_than.push_back(bodies[i].name);
      spdlog::info("design: body '{}' on the negative image of the average body, from scratch: ζ_body {:.1f}% lower "
                   "(the cohort's support: {:.1f}%)",
                   bodies[i].name, 100.0 * (1.0 - on_it), 100.0 * (1.0 - cohort_ratio));
    }
    double mean = 0.0;
    for (double x : baseline) mean += x / static_cast<double>(baseline.size());
    baseline_json = {{"name", "negative image of the average body"},
                     {"file", "baseline_average_negative_image.obj"},
                     {"press_m", scene.cohort_baseline->press},
                     {"smoothing_rounds", scene.cohort_baseline->smoothing_rounds},
                     {"mean_zeta_body_ratio", mean},
                     {"note", "each body pressed into the support until its lowest point is press below the top; "
                              "the mean of their dents at each design vertex, smoothed"}};
  }
  for (const BodyOutcome& b : bodies) write_json_file(out / "bodies" / b.slug / "summary.json", b.summary);
  write_cohort_table(out / "cohort.csv", bodies, singles, baseline);
  write_cohort_plot(out / "cohort.svg", bodies, singles, baseline);
  report::Figure score_fig;
  score_fig.plots.push_back(
      objective_plot(r, "objective [1]", fmt::format("J: the {} of the bodies' ζ / their initial ζ",
                                                     to_string(scene.options.cohort->aggregate))));
  report::write_svg(out / "score.svg", score_fig);

  // The objective from scratch: J of each body's ζ over its own from scratch
  // on the initial support.
  const auto n = static_cast<Eigen::Index>(bodies.size());
  Eigen::VectorXd ratio(n), ratio_body(n);
  Json per_body = Json::array();
  bool every_body_lower = true;
  for (Eigen::Index i = 0; i < n; ++i) {
    const BodyOutcome& b = bodies[static_cast<std::size_t>(i)];
    ratio[i] = b.after.zeta / b.before.zeta;
    ratio_body[i] = b.after.body().score.zeta_body / b.before.body().score.zeta_body;
    every_body_lower = every_body_lower && ratio_body[i] < 1.0;
    per_body.push_back(b.summary);
  }
  const CohortObjective& objective = *scene.options.cohort;
  Json cohort = {{"objective", to_string(objective.aggregate)},
                 {"bodies", n},
                 {"start", scene.cohort_start_on_baseline ? "negative image of the average body" : "scene"}};
  if (objective.aggregate == CohortAggregate::Quantile) cohort["quantile"] = objective.quantile;
  if (objective.aggregate == CohortAggregate::SmoothMax) cohort["sharpness"] = objective.sharpness;
  Json s = {{"palpa_design", 1},
            {"scene", scene.rest.file.string()},
            {"cohort", cohort},
            {"support", {{"source", scene.rest.support_source}, {"vertices", r.initial.support.rows()}}},
            {"design", design_settings_json(scene, optimizer, r)},
            {"objective_final", cohort_value(objective, ratio)},
            {"mean_zeta_body_ratio", ratio_body.mean()},
            {"worst_zeta_body_ratio", ratio_body.maxCoeff()},
            {"every_body_lower", every_body_lower},
            {"bodies", per_body},
            {"optimizer",
             {{"note", "the optimizer's own view: each body's contact model frozen, chosen anew where its penetration "
                       "left its band, warm-started from the accepted shape"},
              {"objective_initial", r.initial.zeta},
              {"objective_final", r.final.zeta}}},
            {"max_design_displacement_m", (optimized.V - initial.V).rowwise().norm().maxCoeff()}};
  if (!singles.empty()) {
    double own = 0.0;
    for (const Json& j : singles) own += j.at("zeta_body_ratio").get<double>() / static_cast<double>(singles.size());
    // The price of one support for all: the cohort's mean ζ_body ratio over
    // the mean of the bodies' own designs'.
    s["own_designs"] = {{"mean_zeta_body_ratio", own},
                        {"price_of_one_support", ratio_body.mean() / own},
                        {"note", "each body's own design: the same settings, the body alone on the support, "
                                 "re-solved from scratch"}};
  }
  // The optimizer normalizes by each body's ζ where the design began: the
  // same objective from scratch, to compare with its own view.
  Eigen::VectorXd from_start = ratio;
  if (scene.cohort_start_on_baseline) {
    for (Eigen::Index i = 0; i < n; ++i) from_start[i] = bodies[static_cast<std::size_t>(i)].after.zeta / baseline_zeta[i];
  }
  s["optimizer"]["objective_final_from_scratch"] = cohort_value(objective, from_start);
  if (!baseline_json.is_null()) {
    s["baseline"] = baseline_json;
    // The bodies that feel less on the baseline than on the cohort's support.
    s["worse_than_baseline_for"] = worse_than;
    s["worse_than_baseline_on_mean"] = baseline_json["mean_zeta_body_ratio"].get<double>() < ratio_body.mean();
  }
  s.update(run_json(r));
  cohort_report_html(out, s).write(out / "report.html");
  write_json_file(out / "summary.json", s);
  return s;
}

std::string cohort_headline_text(const Json& s) {
  std::vector<std::string> each;
  for (const Json& b : s.at("bodies")) {
    each.push_back(fmt::format("{} {:+.1f}%", b.at("name").get<std::string>(),
                               100.0 * (b.at("zeta_body_ratio").get<double>() - 1.0)));
  }
  std::string own;
  if (s.contains("baseline")) {
    own += fmt::format(" (the negative image of the average body: {:.3f}{})",
                       s.at("baseline").at("mean_zeta_body_ratio").get<double>(),
                       s.at("worse_than_baseline_for").empty()
                           ? ""
                           : fmt::format("; WORSE than it for {}",
                                         fmt::join(s.at("worse_than_baseline_for").get<std::vector<std::string>>(), ", ")));
  }
  if (s.contains("own_designs")) {
    own += fmt::format(" (each body's own design: {:.3f}; one support for all costs {:+.1f}%)",
                      s.at("own_designs").at("mean_zeta_body_ratio").get<double>(),
                      100.0 * (s.at("own_designs").at("price_of_one_support").get<double>() - 1.0));
  }
  return fmt::format("one support for {} bodies ({} objective {:.4g} from 1), re-solved from scratch: ζ_body {}; "
                     "mean ζ_body ratio {:.3f}{}{}; {} iterations ({})",
                     s.at("bodies").size(), s.at("cohort").at("objective").get<std::string>(),
                     s.at("objective_final").get<double>(), fmt::join(each, ", "),
                     s.at("mean_zeta_body_ratio").get<double>(), own,
                     s.at("every_body_lower").get<bool>() ? "" : "; NOT every body's ζ_body is lower",
                     s.at("iterations").get<int>(), s.at("termination").get<std::string>());
}

report::HtmlReport cohort_report_html(const std::filesystem::path& out, const Json& s) {
  report::HtmlReport h(fmt::format("palpa design: {}", s.at("scene").get<std::string>()), cohort_headline_text(s));
  const auto kpa = [](double pa) { return fmt::format("{:.3g} kPa", pa * 1e-3); };
  h.subheading("The cohort");
  std::vector<std::vector<std::string>> rows;
  for (const Json& b : s.at("bodies")) {
    const Json& i = b.at("initial");
    const Json& f = b.at("final");
    rows.push_back({b.at("name").get<std::string>(), fmt::format("{:.4g}", i.at("zeta_body").get<double>()),
                    fmt::format("{:.4g}", f.at("zeta_body").get<double>()),
                    fmt::format("{:.3f}", b.at("zeta_body_ratio").get<double>()),
                    b.contains("own_design") ? fmt::format("{:.3f}", b.at("own_design").at("zeta_body_ratio").get<double>())
                                             : std::string("—"),
                    b.contains("average_negative_image")
                        ? fmt::format("{:.3f}", b.at("average_negative_image").at("zeta_body_ratio").get<double>())
                        : std::string("—"),
                    fmt::format("{} → {}", kpa(i.at("peak_pressure_Pa").at("body").get<double>()),
                                kpa(f.at("peak_pressure_Pa").at("body").get<double>())),
                    fmt::format("{} → {}", kpa(i.at("pressure_map").at("body").at("peak_pressure_index_Pa").get<double>()),
                                kpa(f.at("pressure_map").at("body").at("peak_pressure_index_Pa").get<double>()))});
  }
  h.table({"body", "ζ body, initial", "ζ body, the cohort's support", "ratio", "ratio, its own design",
           "ratio, negative image of the average body", "body peak", "body PPI"},
          rows);
  h.paragraph("Every body is re-solved from scratch on the initial and on the cohort's support (the automatic "
              "contact stiffness, no warm start). ζ_body: the ergonomic score of what the body feels; PPI: the peak "
              "pressure index, the highest mean pressure over 9 cm².");
  h.picture_files({{out / "cohort.svg", "the cohort's spread"}, {out / "score.svg", "the objective per iteration"}});
  for (const Json& b : s.at("bodies")) {
    const std::filesystem::path dir = out / b.at("folder").get<std::string>();
    h.subheading(fmt::format("The body '{}'", b.at("name").get<std::string>()));
    h.picture_files({{dir / "body_pressure.svg", "what the body feels, before and after"}});
  }
  return h;
}

}  // namespace palpa::design
