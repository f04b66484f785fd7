// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/design/output.hpp"

#include <algorithm>
#include <cctype>
#include <memory>
#include <optional>
#include <vector>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/io/mesh.hpp"
#include "palpa/io/ply.hpp"
#include "palpa/io/vtu.hpp"
#include "palpa/design/baselines.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/geometry/umbrella.hpp"
#include "palpa/report/compare.hpp"
#include "palpa/report/plot.hpp"
#include "palpa/report/html.hpp"
#include "palpa/report/pressure_map_svg.hpp"
#include "palpa/rest/output.hpp"
#include "palpa/sim3d/scene_json.hpp"

namespace palpa::design {

namespace {

Json vec(const Eigen::Vector3d& v) { return Json::array({v[0], v[1], v[2]}); }

}  // namespace

Json evaluation_json(const Evaluation& e, double gamma) {
  Json j = {{"phi", e.phi},
          {"zeta", e.zeta},
          {"zeta_body", e.body().score.zeta_body},
          {"zeta_support", e.body().score.zeta_support},
          {"gamma_psi", gamma * e.psi},
          {"peak_pressure_Pa", {{"body", e.body().score.body_pressure.maxCoeff()}, {"support", e.body().score.support_pressure.maxCoeff()}}},
          {"peak_smoothed_pressure_Pa",
           {{"body", e.body().score.body_smoothed.maxCoeff()}, {"support", e.body().score.support_smoothed.maxCoeff()}}},
          {"contacts", {{"body_vertices", e.body().score.body_contacts}, {"support_vertices", e.body().score.support_contacts}}},
          {"pressure_map_force_N",
           {{"body", e.body().rest.body_map_force}, {"support", e.body().rest.support_map_force}, {"load", e.body().rest.load.norm()}}},
          {"pressure_map",
           {{"body", report::to_json(e.body().rest.body_metrics)}, {"support", report::to_json(e.body().rest.support_metrics)}}},
          {"max_penetration_m", e.body().rest.max_penetration},
          {"contact_force_N", vec(e.body().rest.contact_force)},
          {"load_N", vec(e.body().rest.load)},
          {"balance_error", e.body().rest.balance_error},
          {"core_translation_m", vec(e.body().rest.core_translation)},
          {"min_det_F", e.body().rest.min_det_f}};
  if (e.body().state.support.size() > 0) {
    j["deformable_support"] = {{"max_displacement_m", e.body().rest.support_max_displacement},
                               {"min_det_F", e.body().rest.support_min_det_f},
                               {"base_force_N", vec(e.body().rest.support_base_force)}};
  }
  return j;
}

Json write_design_state(const std::filesystem::path& out, const std::string& tag, rest::RestSimulation& sim,
                 const Evaluation& e, const Eigen::MatrixX3d* displacement, double threshold) {
  const PressureEstimate pts = pose_to_seat(sim, e.body().rest, threshold);
  UnstructuredGrid body = rest::body_grid(sim, e.body().rest);
  body.point_data.push_back(DataArray{"pressure_smoothed_Pa", e.body().score.body_smoothed});
  body.point_data.push_back(DataArray{"pose_to_seat_Pa", pts.body_pressure});
  write_vtu(out / fmt::format("body_{}.vtu", tag), body);
  UnstructuredGrid support = rest::support_grid(sim, e.body().rest);
  support.point_data.push_back(DataArray{"pressure_smoothed_Pa", e.body().score.support_smoothed});
  support.point_data.push_back(DataArray{"pose_to_seat_Pa", pts.support_pressure});
  if (displacement != nullptr) support.point_data.push_back(DataArray{"design_displacement_m", *displacement});
  write_vtu(out / fmt::format("support_{}.vtu", tag), support);
  if (sim.deformable_support()) write_vtu(out / fmt::format("support_volume_{}.vtu", tag), rest::support_volume_grid(sim));
  rest::write_skin_ply(out / fmt::format("skin_{}.ply", tag), sim,
                       {{"pressure_Pa", e.body().score.body_pressure},
                        {"pressure_smoothed_Pa", e.body().score.body_smoothed},
                        {"pose_to_seat_Pa", pts.body_pressure}});
  PlyWriteOptions po;
  po.vertex_scalars = {{"pressure_Pa", e.body().score.support_pressure},
                       {"pressure_smoothed_Pa", e.body().score.support_smoothed},
                       {"pose_to_seat_Pa", pts.support_pressure}};
  const SurfaceMesh world = rest::world_support(sim);
  write_ply(out / fmt::format("support_{}.ply", tag), world, po);
  Json j = {{"contacts", pts.contacts}, {"peak_Pa", pts.body_pressure.maxCoeff()}};
  if (pts.support_pressure.maxCoeff() > 0.0 || e.body().score.support_pressure.maxCoeff() > 0.0) {
    const report::MapComparison c = report::compare_pressure_maps(
        report::PressureMap{world, pts.support_pressure, "pose-to-seat"},
        report::PressureMap{world, e.body().score.support_pressure, "palpa"});
    j["against_palpa_on_the_support"] = {{"rms_difference_Pa", c.rms_difference},
                                         {"relative_rms", c.relative_rms},
                                         {"correlation", number_or_null(c.correlation)},
                                         {"contact_area_m2", c.a.contact_area},
                                         {"palpa_contact_area_m2", c.b.contact_area}};
  }
  return j;
}

namespace {

// A shape solved from scratch (ShapeOptimizer::solve_from_scratch), its
// smoothness taken from the optimizer's evaluation of the same shape.
Evaluation scored_from_scratch(const ShapeOptimizer& optimizer, const rest::RestBody& body, const SurfaceMesh& shape,
                               const Evaluation& same_shape, std::unique_ptr<rest::RestSimulation>* keep,
                               const std::string& what) {
  Evaluation e = optimizer.solve_from_scratch(body, shape, keep);
  if (!e.ok) throw Error(ErrorKind::Solver, fmt::format("solving {} from scratch: {}", what, e.failure));
  e.psi = same_shape.psi;
  e.phi = e.zeta + optimizer.gamma() * e.psi;
  return e;
}

}  // namespace

void write_support_shape(const std::filesystem::path& out, const std::string& stem, const SurfaceMesh& shape) {
  write_surface_mesh(out / (stem + ".obj"), shape);
  SurfaceMesh mm = shape;
  mm.V *= 1e3;
  write_surface_mesh(out / (stem + "_mm.stl"), mm);
}

Json write_design_outputs(const std::filesystem::path& out, const DesignScene& scene, ShapeOptimizer& optimizer,
                          const DesignResult& r) {
  ensure_directory(out);
  rest::RestSimulation& sim = optimizer.simulation(0);
  const Evaluation before = optimizer.evaluate(r.initial.support, r.initial.states(), false, 0);
  if (!before.ok) throw Error(ErrorKind::Solver, "re-solving the initial shape: " + before.failure);
  const double threshold = scene.options.pose_to_seat_threshold;
  const Json pts_before = write_design_state(out, "before", sim, before, nullptr, threshold);
  // Each side's map before and after, for the pictures (taken while the
  // simulation is at that state).
  std::vector<report::PressureMapPanel> body_maps, support_maps;
  const std::string start = scene.start.empty() ? std::string("initial") : "start '" + scene.start + "'";
  body_maps.push_back(rest::body_pressure_panel(sim, before.body().rest, "body side, " + start + " support"));
  support_maps.push_back(rest::support_pressure_panel(sim, before.body().rest, "support side, " + start + " shape"));
  const Evaluation after = optimizer.evaluate(r.final.support, r.final.states(), false, 0);
  if (!after.ok) throw Error(ErrorKind::Solver, "re-solving the optimized shape: " + after.failure);
  const Eigen::MatrixX3d displacement = r.final.support - r.initial.support;
  // A spike sticks out of the optimized surface: along its normals.
  const Eigen::MatrixX3d optimized_normals =
      geometry::vertex_normals(SurfaceMesh{r.final.support, sim.support().triangles()}, geometry::NormalWeighting::Area);
  const geometry::Spike spike =
      geometry::largest_spike(displacement, sim.support().triangles(), optimizer.space().vertices(), &optimized_normals);
  const geometry::Spike spike_any =
      geometry::largest_spike(displacement, sim.support().triangles(), optimizer.space().vertices());
  const Json pts_after = write_design_state(out, "after", sim, after, &displacement, threshold);
  body_maps.push_back(rest::body_pressure_panel(sim, after.body().rest, "body side, optimized support"));
  support_maps.push_back(rest::support_pressure_panel(sim, after.body().rest, "support side, optimized shape"));

  // The shape to make: for a deformable support its rest shape.
  const SurfaceMesh optimized{r.final.support, sim.support().triangles()};
  write_support_shape(out, "support", optimized);

  // Both shapes checked from scratch, as `palpa rest` would solve them: what
  // the summary's headline figures are. The optimized shape's maps from
  // scratch are the third panel of each picture.
  // The initial shape was solved from scratch when the optimizer was built
  // (its contact model chosen there): `before` is that solution.
  const Evaluation& checked_initial = before;
  std::unique_ptr<rest::RestSimulation> fresh;
  const Evaluation checked_final =
      scored_from_scratch(optimizer, scene.rest.body, optimized, after, &fresh, "the optimized shape");
  write_design_state(out, "resolved", *fresh, checked_final, nullptr, threshold);
  body_maps.push_back(rest::body_pressure_panel(*fresh, checked_final.body().rest, "body side, optimized, from scratch"));
  support_maps.push_back(rest::support_pressure_panel(*fresh, checked_final.body().rest, "support side, optimized, from scratch"));

  // With a start baseline, the scene's own support from scratch: what the
  // design is also reported against (its body map is the first panel).
  std::optional<Evaluation> own;
  if (scene.scene_support) {
    std::unique_ptr<rest::RestSimulation> osim;
    own = optimizer.solve_from_scratch(scene.scene_support->body, scene.scene_support->support, &osim);
    if (!own->ok) throw Error(ErrorKind::Solver, "solving the scene's own support from scratch: " + own->failure);
    body_maps.insert(body_maps.begin(), rest::body_pressure_panel(*osim, own->body().rest, "body side, the scene's support"));
    support_maps.insert(support_maps.begin(),
                        rest::support_pressure_panel(*osim, own->body().rest, "support side, the scene's support"));
  }

  // Baselines, solved from scratch alike (simulation 0 is used for Sit &
  // Relax's fit at the initial equilibrium, so they come after the optimized
  // shape's files).
  Json baselines = Json::array();
  Json worse_than = Json::array();  // baselines that beat the optimized shape on what the body feels
  for (const Baseline& b : scene.baselines) {
    std::unique_ptr<rest::RestSimulation> bsim;
    Json j;
    Evaluation e;
    if (b.sit_and_relax && scene.start_fit && b.name == scene.start) {
      // The start itself, fitted on the scene's own support before the run.
      const SurfaceMesh& fitted = scene.start_fit->support;
      e = optimizer.solve_from_scratch(scene.scene_support->body, fitted, &bsim);
      j["zeta_negative_image"] = scene.start_fit->zeta_negative_image;
      j["fit_scale"] = scene.start_fit->scale;
      write_surface_mesh(out / fmt::format("baseline_{}.obj", baseline_slug(b.name)), fitted);
    } else if (b.sit_and_relax) {
      // The frozen pressures: the body on the negative image.
      const Evaluation ni = optimizer.solve_from_scratch(b.body, b.support);
      if (!ni.ok) throw Error(ErrorKind::Solver, fmt::format("the baseline '{}' (negative image): {}", b.name, ni.failure));
      const Evaluation at = optimizer.evaluate(r.initial.support, r.initial.states(), false, 0);
      if (!at.ok) throw Error(ErrorKind::Solver, "re-solving the initial shape: " + at.failure);
      const SitAndRelaxFit fit = sit_and_relax(sim, optimizer.space(), ni.body().rest.body_pressure, b.smoothness);
      if (fit.scale < 1.0) {
        spdlog::warn("design: baseline '{}': the full Sit & Relax fit would cross the support through itself; "
                     "made with {:.3g} of its moves",
                     b.name, fit.scale);
      }
      const SurfaceMesh fitted{fit.vertices, sim.support().triangles()};
      e = optimizer.solve_from_scratch(scene.rest.body, fitted, &bsim);
      j["zeta_negative_image"] = ni.zeta;
      j["fit_scale"] = fit.scale;
      write_surface_mesh(out / fmt::format("baseline_{}.obj", baseline_slug(b.name)), fitted);
    } else {
      e = optimizer.solve_from_scratch(b.body, b.support, &bsim);
    }
    if (!e.ok) throw Error(ErrorKind::Solver, fmt::format("the baseline '{}': {}", b.name, e.failure));
    const std::string slug = baseline_slug(b.name);
    UnstructuredGrid grid = rest::support_grid(*bsim, e.body().rest);
    grid.point_data.push_back(DataArray{"pressure_smoothed_Pa", e.body().score.support_smoothed});
    write_vtu(out / fmt::format("baseline_{}_support.vtu", slug), grid);
    write_vtu(out / fmt::format("baseline_{}_body.vtu", slug), rest::body_grid(*bsim, e.body().rest));
    j.update(evaluation_json(e, 0.0));
    j["name"] = b.name;
    j["source"] = b.sit_and_relax ? "Sit & Relax fit to the pressures on " + b.source : b.source;
    const double zeta_body = e.body().score.zeta_body / checked_final.body().score.zeta_body;
    const double body_peak = e.body().score.body_pressure.maxCoeff() / checked_final.body().score.body_pressure.maxCoeff();
    j["zeta_over_optimized"] = e.zeta / checked_final.zeta;
    j["zeta_body_over_optimized"] = zeta_body;
    j["body_peak_over_optimized"] = body_peak;
    baselines.push_back(j);
    spdlog::info("design: baseline '{}' from scratch: ζ = {:.6g}, ζ_body {:.2f}× and body peak {:.2f}× the optimized "
                 "shape's",
                 b.name, e.zeta, zeta_body, body_peak);
    if (zeta_body < 1.0 || body_peak < 1.0) {
      std::vector<std::string> on;
      if (zeta_body < 1.0) on.push_back("zeta_body");
      if (body_peak < 1.0) on.push_back("body_peak");
      worse_than.push_back({{"baseline", b.name}, {"on", on}});
    }
  }

  // Scores per iteration.
  report::Plot scores = objective_plot(r, fmt::format("score [Pa^{} m^2]", scene.options.score.exponent),
                                       "ζ (ergonomic score)");
  // What the summary reports: both shapes from scratch, and each baseline.
  const double last = r.history.empty() ? 1.0 : static_cast<double>(r.history.back().iteration);
  scores.series.push_back(report::Series{"ζ from scratch (initial, optimized)",
                                         {0.0, last},
                                         {checked_initial.zeta, checked_final.zeta},
                                         report::Mark::Dots});
  if (own) {
    report::Series line{"ζ of the scene's own support (from scratch)", {0.0, last}, {own->zeta, own->zeta}};
    line.dashed = true;
    scores.series.push_back(line);
  }
  for (const Json& b : baselines) {
    report::Series line{fmt::format("ζ of the baseline '{}' (from scratch)", b["name"].get<std::string>()),
                        {0.0, last},
                        {b["zeta"].get<double>(), b["zeta"].get<double>()}};
    line.dashed = true;
    scores.series.push_back(line);
  }
  report::Figure score_fig;
  score_fig.plots.push_back(scores);
  report::write_svg(out / "score.svg", score_fig);

  // Pressures before and after from scratch, body and support together.
  auto both = [](const Evaluation& e) {
    Eigen::VectorXd v(e.body().score.body_pressure.size() + e.body().score.support_pressure.size());
    v << e.body().score.body_pressure, e.body().score.support_pressure;
    return v;
  };
  const Eigen::VectorXd pb = both(checked_initial), pa = both(checked_final);
  const double top = std::max({pb.maxCoeff(), pa.maxCoeff(), 1e-12});
  report::Plot hist;
  hist.title = "contact pressure from scratch (body and support vertices)";
  hist.x.label = "pressure [kPa]";
  hist.y.label = "vertices";
  hist.series.push_back(rest::pressure_histogram("initial shape", pb, top, 24));
  hist.series.push_back(rest::pressure_histogram("optimized shape", pa, top, 24));
  report::Figure hist_fig;
  hist_fig.plots.push_back(hist);
  report::write_svg(out / "pressure_histogram.svg", hist_fig);

  // The maps as pictures, before beside after on one colour scale per side.
  const Eigen::Vector3d toward_body = rest::support_to_body(before.body().rest);
  report::PressureMapOptions body_view = rest::body_pressure_view(toward_body);
  body_view.title = "contact pressure on the body: initial and optimized support";
  report::write_pressure_map_svg(out / "body_pressure.svg", body_maps, body_view);
  report::PressureMapOptions support_view = rest::support_pressure_view(toward_body);
  support_view.title = "contact pressure on the support: initial and optimized shape";
  report::write_pressure_map_svg(out / "support_pressure.svg", support_maps, support_view);

  Json s = {{"palpa_design", 1},
            {"scene", scene.rest.file.string()},
            {"body", {{"source", scene.rest.body_source},
                      {"vertices", sim.model().num_vertices()},
                      {"tetrahedra", sim.model().num_elements()},
                      {"element", sim3d::element_json(sim.model())},
                      {"skin_vertices", sim.surface_vertices().size()}}},
            {"support", {{"source", scene.rest.support_source}, {"vertices", r.initial.support.rows()}}},
            {"design", design_settings_json(scene, optimizer, r)},
            {"stiffness_N_per_m", r.initial.body().state.stiffness},
            {"initial", evaluation_json(checked_initial, r.gamma)},
            {"final", evaluation_json(checked_final, r.gamma)},
            {"zeta_reduction_percent", 100.0 * (1.0 - checked_final.zeta / checked_initial.zeta)},
            {"zeta_body_reduction_percent", 100.0 * (1.0 - checked_final.body().score.zeta_body / checked_initial.body().score.zeta_body)},
            {"body_peak_ratio", checked_initial.body().score.body_pressure.maxCoeff() / checked_final.body().score.body_pressure.maxCoeff()},
            {"worse_than_baselines", worse_than},
            {"optimizer",
             {{"note", "the optimizer's own view: the contact model frozen, chosen anew where the penetration left its band, warm-started from the accepted shape"},
              {"initial", evaluation_json(before, r.gamma)},
              {"final", evaluation_json(after, r.gamma)},
              {"zeta_reduction_percent", 100.0 * (1.0 - after.zeta / before.zeta)},
              {"from_scratch_over_optimizer",
               {{"zeta", checked_final.zeta / after.zeta},
                {"zeta_body", checked_final.body().score.zeta_body / after.body().score.zeta_body},
                {"body_peak", checked_final.body().score.body_pressure.maxCoeff() / after.body().score.body_pressure.maxCoeff()}}}}},
            {"max_design_displacement_m", displacement.rowwise().norm().maxCoeff()},
            {"largest_spike", {{"note", "a design vertex's move from its neighbours' mean move, along the optimized surface's normal (any_direction: the whole difference, sideways sliding included)"},
                               {"distance_m", spike.distance},
                               {"vertex", spike.vertex},
                               {"any_direction_m", spike_any.distance},
                               {"any_direction_vertex", spike_any.vertex}}},
            {"pose_to_seat", {{"threshold_m", threshold}, {"before", pts_before}, {"after", pts_after}}},
            {"baselines", baselines}};
  s.update(run_json(r));
  if (r.before_post_smoothing) s["zeta_before_post_smoothing"] = r.before_post_smoothing->zeta;
  if (own) {
    // `initial` is the start; these figures are against the scene's own support.
    s["start"] = {{"baseline", scene.start},
                  {"note", "the design began on this baseline's support; initial is that support"},
                  {"scene_support", evaluation_json(*own, 0.0)},
                  {"scene_support_source", scene.scene_support->source},
                  {"zeta_reduction_percent", 100.0 * (1.0 - checked_final.zeta / own->zeta)},
                  {"zeta_body_reduction_percent", 100.0 * (1.0 - checked_final.body().score.zeta_body / own->body().score.zeta_body)},
                  {"body_peak_ratio", own->body().score.body_pressure.maxCoeff() / checked_final.body().score.body_pressure.maxCoeff()}};
  }
  // The report first: summary.json marks the run as finished.
  design_report_html(out, s).write(out / "report.html");
  write_json_file(out / "summary.json", s);
  return s;
}

Json design_settings_json(const DesignScene& scene, const ShapeOptimizer& optimizer, const DesignResult& r) {
  const DesignOptions& o = scene.options;
  return {{"region", scene.region},
          {"variables", optimizer.space().size()},
          {"direction", o.normal_only ? "normal" : "free"},
          {"filter_radius_m", optimizer.space().filter_radius()},
          {"exponent", o.score.exponent},
          {"gamma", r.gamma},
          {"smoothing_exponent", o.gamma ? Json() : Json(o.smoothing_exponent)},
          {"taubin_iterations", o.taubin_iterations},
          {"moves_m", o.moves},
          {"post_smoothing", o.post_smoothing}};
}

Json run_json(const DesignResult& r) {
  Json history = Json::array();
  for (const IterationRecord& it : r.history) {
    history.push_back({{"iteration", it.iteration},
                       {"phi", it.phi},
                       {"zeta", it.zeta},
                       {"gamma_psi", r.gamma * it.psi},
                       {"move_m", it.move},
                       {"evaluations", it.evaluations},
                       {"restarted", it.restarted},
                       {"stiffness_N_per_m", it.stiffness},
                       {"refrozen", it.refrozen},
                       {"seconds", it.seconds}});
  }
  double iteration_seconds = 0.0;
  for (const IterationRecord& it : r.history) iteration_seconds += it.seconds;
  const double per_iteration = r.history.empty() ? 0.0 : iteration_seconds / static_cast<double>(r.history.size());
  return {{"iterations", r.iterations},
          {"equilibrium_solves", r.evaluations},
          {"newton_iterations", r.newton_iterations},
          {"seconds", r.seconds},
          {"seconds_per_iteration", per_iteration},
          {"initial_equilibrium_seconds", r.equilibrium_seconds},
          {"iteration_per_equilibrium", r.equilibrium_seconds > 0.0 ? per_iteration / r.equilibrium_seconds : 0.0},
          {"termination", std::string(to_string(r.stop.termination))},
          {"stop_reason", r.stop.detail},
          {"resumed", r.resumed},
          {"refreezes", r.refreezes},
          {"history", history}};
}

report::Plot objective_plot(const DesignResult& r, const std::string& unit_label, const std::string& zeta_label) {
  report::Plot scores;
  scores.title = "objective per iteration";
  scores.x.label = "iteration";
  scores.y.label = unit_label;
  scores.y.log = true;
  report::Series phi{"φ = ζ + γψ", {}, {}, report::Mark::LineDots};
  report::Series zeta{zeta_label, {}, {}, report::Mark::LineDots};
  report::Series psi{"γψ (smoothness)", {}, {}, report::Mark::Line};
  phi.x.push_back(0.0);
  phi.y.push_back(r.initial.phi);
  zeta.x.push_back(0.0);
  zeta.y.push_back(r.initial.zeta);
  psi.x.push_back(0.0);
  psi.y.push_back(r.gamma * r.initial.psi);
  for (const IterationRecord& it : r.history) {
    phi.x.push_back(it.iteration);
    phi.y.push_back(it.phi);
    zeta.x.push_back(it.iteration);
    zeta.y.push_back(it.zeta);
    psi.x.push_back(it.iteration);
    psi.y.push_back(r.gamma * it.psi);
  }
  psi.dashed = true;
  scores.series = {phi, zeta, psi};
  return scores;
}

void add_design_sections(report::HtmlReport& h, const std::filesystem::path& out, const Json& s) {
  const auto kpa = [](double pa) { return fmt::format("{:.3g} kPa", pa * 1e-3); };
  const auto sci = [](double v) { return fmt::format("{:.4g}", v); };
  h.subheading("Pressures felt (body) and seen (support), before and after");
  h.picture_files({{out / "body_pressure.svg", "the body's side: what the person feels"}});
  h.picture_files({{out / "support_pressure.svg", "the support's side: what a pressure mat on it would read"}});
  h.subheading("Scores");
  const auto row = [&](const std::string& name, const Json& e) {
    const Json& body = e.at("pressure_map").at("body");
    return std::vector<std::string>{name,
                                    sci(e.at("zeta").get<double>()),
                                    sci(e.at("zeta_body").get<double>()),
                                    kpa(e.at("peak_pressure_Pa").at("body").get<double>()),
                                    kpa(body.at("peak_pressure_index_Pa").get<double>()),
                                    kpa(body.at("mean_Pa").get<double>()),
                                    fmt::format("{:.1f} cm²", body.at("contact_area_m2").get<double>() * 1e4),
                                    kpa(e.at("peak_pressure_Pa").at("support").get<double>())};
  };
  std::vector<std::vector<std::string>> rows{row("initial support", s.at("initial")),
                                             row("designed support", s.at("final"))};
  for (const Json& bl : s.at("baselines")) rows.push_back(row("baseline: " + bl.at("name").get<std::string>(), bl));
  h.table({"support", "ζ", "ζ body", "body peak", "body PPI", "body mean", "body contact area", "support peak"}, rows);
  h.paragraph("Every row is re-solved from scratch (the automatic contact stiffness, no warm start). ζ: the "
              "ergonomic score of the pressures; PPI: the peak pressure index, the highest mean pressure over "
              "9 cm² (a 3 × 3 block of a mat's 1 cm sensels).");
  h.picture_files({{out / "score.svg", "the score per iteration"},
                   {out / "pressure_histogram.svg", "pressures before and after"}});
}

std::string design_headline_text(const Json& s) {
  const auto kpa = [](double pa) { return fmt::format("{:.3g} kPa", pa * 1e-3); };
  return fmt::format("re-solved from scratch: score ζ {:.1f}% lower, the body's ζ {:.1f}% lower, body peak {} → {}; "
                     "{} iterations ({})",
                     s.at("zeta_reduction_percent").get<double>(), s.at("zeta_body_reduction_percent").get<double>(),
                     kpa(s.at("initial").at("peak_pressure_Pa").at("body").get<double>()),
                     kpa(s.at("final").at("peak_pressure_Pa").at("body").get<double>()), s.at("iterations").get<int>(),
                     s.at("termination").get<std::string>());
}

report::HtmlReport design_report_html(const std::filesystem::path& out, const Json& s) {
  report::HtmlReport h(fmt::format("palpa design: {}", s.at("scene").get<std::string>()), design_headline_text(s));
  add_design_sections(h, out, s);
  return h;
}

}  // namespace palpa::design
