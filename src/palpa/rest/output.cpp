// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/rest/output.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tuple>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/geometry/closest_point.hpp"
#include "palpa/io/ply.hpp"
#include "palpa/io/vtu.hpp"
#include "palpa/report/plot.hpp"
#include "palpa/sim3d/scene_json.hpp"
#include "palpa/report/pressure_template.hpp"
#include "palpa/rest/measurements.hpp"
#include "palpa/tet/material_field.hpp"

namespace palpa::rest {

namespace {

Json vec(const Eigen::Vector3d& v) { return Json::array({v[0], v[1], v[2]}); }

}  // namespace

UnstructuredGrid body_grid(const RestSimulation& sim, const RestResult& r) {
  const Eigen::VectorXd u = sim.system().full_displacement(sim.dofs());
  const TetMesh& mesh = sim.model().mesh();
  UnstructuredGrid grid;
  grid.points.resize(mesh.V.rows(), 3);
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) grid.points.row(v) = mesh.V.row(v) + u.segment<3>(3 * v).transpose();
  grid.cells.push_back(CellBlock{VtkCellType::Tetra, mesh.T});
  Eigen::MatrixXd disp(mesh.V.rows(), 3);
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) disp.row(v) = u.segment<3>(3 * v).transpose();
  grid.point_data.push_back(DataArray{"displacement_m", disp});
  grid.point_data.push_back(DataArray{"contact_force_N", contact_pressures(sim).body_force.transpose()});
  grid.point_data.push_back(DataArray{"pressure_Pa", r.body_pressure});
  Eigen::VectorXd attached = Eigen::VectorXd::Zero(mesh.V.rows());
  for (int v : sim.body().attached) attached[v] = 1.0;
  grid.point_data.push_back(DataArray{"attached", attached});
  grid.cell_data.push_back(DataArray{"von_mises_stress_Pa", tet::ElasticModel::von_mises(sim.model().cauchy_stress(u))});
  grid.cell_data.push_back(DataArray{"youngs_modulus_Pa", tet::element_young(sim.model())});
  return grid;
}

UnstructuredGrid support_grid(const RestSimulation& sim, const RestResult& r) {
  const contact::Obstacle& support = sim.support();
  UnstructuredGrid grid;
  grid.points.resize(support.vertices().rows(), 3);
  for (Eigen::Index v = 0; v < grid.points.rows(); ++v) grid.points.row(v) = support.world_vertex(static_cast<int>(v)).transpose();
  grid.cells.push_back(CellBlock{VtkCellType::Triangle, support.triangles()});
  grid.point_data.push_back(DataArray{"pressure_Pa", r.support_pressure});
  if (sim.support_model() != nullptr) {
    grid.point_data.push_back(DataArray{"displacement_m", grid.points - sim.support_rest_vertices()});
  }
  return grid;
}

UnstructuredGrid support_volume_grid(const RestSimulation& sim) {
  const tet::ElasticModel* model = sim.support_model();
  if (model == nullptr) throw Error(ErrorKind::Internal, "the support is rigid: it has no tets");
  const Eigen::VectorXd u = sim.support_system()->full_displacement(sim.support_dofs());
  const TetMesh& mesh = model->mesh();
  UnstructuredGrid grid;
  grid.points.resize(mesh.V.rows(), 3);
  Eigen::MatrixXd disp(mesh.V.rows(), 3);
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
    disp.row(v) = u.segment<3>(3 * v).transpose();
    grid.points.row(v) = mesh.V.row(v) + disp.row(v);
  }
  grid.cells.push_back(CellBlock{VtkCellType::Tetra, mesh.T});
  grid.point_data.push_back(DataArray{"displacement_m", disp});
  grid.cell_data.push_back(DataArray{"von_mises_stress_Pa", tet::ElasticModel::von_mises(model->cauchy_stress(u))});
  return grid;
}

SurfaceMesh deformed_skin(const RestSimulation& sim) {
  const Eigen::VectorXd p = sim.system().positions(sim.dofs());
  SurfaceMesh s;
  s.V = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(p.data(), p.size() / 3, 3);
  s.F = sim.surface_faces();
  return s;
}

report::Series pressure_histogram(const std::string& label, const Eigen::VectorXd& v, double top, int bins) {
  std::vector<double> counts(static_cast<std::size_t>(bins), 0.0);
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (!(v[i] > 0.0)) continue;
    const int b = std::min(bins - 1, static_cast<int>(v[i] / top * bins));
    counts[static_cast<std::size_t>(b)] += 1.0;
  }
  report::Series s;
  s.label = label;
  for (int b = 0; b < bins; ++b) {
    const double lo = top * b / bins * 1e-3, hi = top * (b + 1) / bins * 1e-3;
    s.x.insert(s.x.end(), {lo, hi});
    s.y.insert(s.y.end(), {counts[static_cast<std::size_t>(b)], counts[static_cast<std::size_t>(b)]});
  }
  return s;
}

void write_skin_ply(const std::filesystem::path& path, const RestSimulation& sim,
                    const std::vector<std::pair<std::string, Eigen::VectorXd>>& fields) {
  const SurfaceMesh skin = deformed_skin(sim);
  std::vector<int> to_new(static_cast<std::size_t>(skin.V.rows()), -1);
  std::vector<int> used;
  for (Eigen::Index f = 0; f < skin.F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = skin.F(f, c);
      if (to_new[static_cast<std::size_t>(v)] < 0) {
        to_new[static_cast<std::size_t>(v)] = static_cast<int>(used.size());
        used.push_back(v);
      }
    }
  }
  SurfaceMesh compact;
  compact.V.resize(static_cast<Eigen::Index>(used.size()), 3);
  for (std::size_t i = 0; i < used.size(); ++i) compact.V.row(static_cast<Eigen::Index>(i)) = skin.V.row(used[i]);
  compact.F.resize(skin.F.rows(), 3);
  for (Eigen::Index f = 0; f < skin.F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) compact.F(f, c) = to_new[static_cast<std::size_t>(skin.F(f, c))];
  }
  PlyWriteOptions options;
  for (const auto& [name, values] : fields) {
    Eigen::VectorXd v(static_cast<Eigen::Index>(used.size()));
    for (std::size_t i = 0; i < used.size(); ++i) v[static_cast<Eigen::Index>(i)] = values[used[i]];
    options.vertex_scalars.push_back({name, v});
  }
  write_ply(path, compact, options);
}

SurfaceMesh world_support(const RestSimulation& sim) {
  SurfaceMesh support;
  support.V.resize(sim.support().vertices().rows(), 3);
  for (Eigen::Index v = 0; v < support.V.rows(); ++v) support.V.row(v) = sim.support().world_vertex(static_cast<int>(v)).transpose();
  support.F = sim.support().triangles();
  return support;
}

Eigen::Vector3d support_to_body(const RestResult& r) {
  if (r.load.norm() > 0.0) return -r.load.normalized();
  if (r.contact_force.norm() > 0.0) return r.contact_force.normalized();
  return Eigen::Vector3d::UnitZ();
}

report::PressureMapPanel body_pressure_panel(const RestSimulation& sim, const RestResult& r, std::string title) {
  return {deformed_skin(sim), r.body_pressure, std::move(title), r.body_metrics, r.load.norm()};
}

report::PressureMapPanel support_pressure_panel(const RestSimulation& sim, const RestResult& r, std::string title) {
  return {world_support(sim), r.support_pressure, std::move(title), r.support_metrics, r.load.norm()};
}

report::PressureMapOptions body_pressure_view(const Eigen::Vector3d& support_to_body) {
  report::PressureMapOptions o;
  o.view_direction = support_to_body;
  o.view_label = "seen from the support";
  return o;
}

report::PressureMapOptions support_pressure_view(const Eigen::Vector3d& support_to_body) {
  report::PressureMapOptions o;
  o.view_direction = -support_to_body;
  o.view_label = "seen from the body";
  o.hide_back_faces = true;  // the support is closed and wound outward
  return o;
}

Eigen::VectorXd vertex_young(const RestSimulation& sim) {
  const TetMesh& mesh = sim.model().mesh();
  const Eigen::VectorXd young = tet::element_young(sim.model());
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(mesh.V.rows()), count = Eigen::VectorXd::Zero(mesh.V.rows());
  for (Eigen::Index t = 0; t < mesh.T.rows(); ++t) {
    for (int a = 0; a < 4; ++a) {
      sum[mesh.T(t, a)] += young[t];
      count[mesh.T(t, a)] += 1.0;
    }
  }
  return sum.cwiseQuotient(count.cwiseMax(1.0));
}

Eigen::VectorXd skin_layer_depth(const RestSimulation& sim) {
  const TetMesh& mesh = sim.model().mesh();
  std::vector<char> attached(static_cast<std::size_t>(mesh.V.rows()), 0);
  for (int v : sim.body().attached) attached[static_cast<std::size_t>(v)] = 1;
  SurfaceMesh core;
  core.V = mesh.V;
  std::vector<Eigen::Index> rows;
  const Eigen::MatrixX3i& faces = sim.boundary_faces();
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    if (attached[faces(f, 0)] && attached[faces(f, 1)] && attached[faces(f, 2)]) rows.push_back(f);
  }
  core.F.resize(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t i = 0; i < rows.size(); ++i) core.F.row(static_cast<Eigen::Index>(i)) = faces.row(rows[i]);
  Eigen::VectorXd depth = Eigen::VectorXd::Zero(mesh.V.rows());
  if (core.F.rows() == 0) return depth;
  const geometry::TriangleTree tree(core.V, core.F);
  for (int v : sim.surface_vertices()) depth[v] = geometry::closest_point(core, tree, mesh.V.row(v).transpose()).distance;
  return depth;
}

Json write_rest_outputs(const std::filesystem::path& out, const RestScene& scene, const RestSimulation& sim,
                        const RestResult& r) {
  ensure_directory(out);
  write_vtu(out / "body.vtu", body_grid(sim, r));
  write_vtu(out / "support.vtu", support_grid(sim, r));
  if (sim.deformable_support()) write_vtu(out / "support_volume.vtu", support_volume_grid(sim));
  const Eigen::VectorXd young = vertex_young(sim);
  const Eigen::VectorXd depth = skin_layer_depth(sim);
  write_skin_ply(out / "skin.ply", sim,
                 {{"pressure_Pa", r.body_pressure}, {"youngs_modulus_Pa", young}, {"layer_depth_m", depth}});
  const SurfaceMesh support = world_support(sim);
  write_ply(out / "support.ply", support, {.vertex_scalars = {{"pressure_Pa", r.support_pressure}}});

  const double top = std::max({r.body_pressure.maxCoeff(), r.support_pressure.maxCoeff(), 1e-12});
  report::Plot plot;
  plot.title = "contact pressure";
  plot.x.label = "pressure [kPa]";
  plot.y.label = "vertices";
  plot.series.push_back(pressure_histogram("body", r.body_pressure, top, 20));
  plot.series.push_back(pressure_histogram("support", r.support_pressure, top, 20));
  report::Figure fig;
  fig.plots.push_back(plot);
  report::write_svg(out / "pressure_histogram.svg", fig);
  const Eigen::Vector3d toward_body = support_to_body(r);
  report::write_pressure_map_svg(out / "body_pressure.svg", {body_pressure_panel(sim, r, "body side")},
                                 body_pressure_view(toward_body));
  report::write_pressure_map_svg(out / "support_pressure.svg", {support_pressure_panel(sim, r, "support side")},
                                 support_pressure_view(toward_body));
  // The body's own fields, seen as its pressures are.
  for (const auto& [file, field, values] :
       {std::tuple{"body_depth.svg", report::MapField{"layer depth", "mm", 1e3}, &depth},
        std::tuple{"body_stiffness.svg", report::MapField{"Young's modulus", "kPa", 1e-3}, &young}}) {
    report::PressureMapOptions view = body_pressure_view(toward_body);
    view.field = field;
    // Colours up to the 90th percentile of the skin's values when the largest
    // are outliers (a clipped body's cut is far from any core).
    std::vector<double> skin_values;
    for (int v : sim.surface_vertices()) skin_values.push_back((*values)[v]);
    std::sort(skin_values.begin(), skin_values.end());
    const double p90 = skin_values.empty() ? 0.0 : skin_values[skin_values.size() * 9 / 10];
    if (!skin_values.empty() && skin_values.back() > 2.0 * p90) view.field->cap = p90;
    report::PressureMapPanel panel{deformed_skin(sim), *values, field.name + " of the soft layer"};
    report::write_pressure_map_svg(out / file, {panel}, view);
  }

  const double deg = 180.0 / 3.14159265358979323846;
  const Eigen::AngleAxisd aa(r.core_rotation);
  const bool surface = sim.contact_term().sampling() == body::ContactSampling::Surface;
  const Eigen::VectorXd tet_young = tet::element_young(sim.model());
  Json s = {{"palpa_rest", 1},
            {"scene", scene.file.string()},
            {"body", {{"source", scene.body_source},
                      {"vertices", sim.model().num_vertices()},
                      {"tetrahedra", sim.model().num_elements()},
                      {"element", sim3d::element_json(sim.model())},
                      {"skin_vertices", sim.surface_vertices().size()},
                      {"attached_vertices", scene.body.attached.size()},
                      {"self_intersections_removed", scene.body_repaired_pairs},
                      {"depth_clamped_vertices", scene.body_depth_clamped},
                      {"mass_kg", sim.model().total_mass()},
                      {"youngs_modulus_Pa", {{"min", tet_young.minCoeff()}, {"max", tet_young.maxCoeff()}}},
                      {"materials", sim.model().materials().size()}}},
            {"support", {{"source", scene.support_source}, {"vertices", sim.support().vertices().rows()}}},
            {"core", {{"translation_m", vec(r.core_translation)},
                      {"rotation_axis", vec(aa.axis())},
                      {"rotation_deg", aa.angle() * deg}}},
            {"load_N", vec(r.load)},
            {"contact_force_N", vec(r.contact_force)},
            {"contact_torque_Nm", vec(r.contact_torque)},
            {"balance_error", r.balance_error},
            {"max_penetration_m", r.max_penetration},
            {surface ? "stiffness_Pa_per_m" : "stiffness_N_per_m", r.stiffness},
            {"contact_sampling", surface ? "surface" : "vertices"},
            {"contacts", {{"body_vertices", (r.body_pressure.array() > 0.0).count()},
                          {"support_vertices", r.support_contacts},
                          {"springs", r.contacts}}},
            {"pressure_map_force_N",
             {{"body", r.body_map_force}, {"support", r.support_map_force}, {"load", r.load.norm()}}},
            {"pressure_map", {{"body", report::to_json(r.body_metrics)}, {"support", report::to_json(r.support_metrics)}}},
            {"peak_pressure_Pa", {{"body", r.body_pressure.maxCoeff()}, {"support", r.support_pressure.maxCoeff()}}},
            {"newton_iterations", r.newton_iterations},
            {"solves", r.solves},
            {"residual_N", r.residual},
            {"min_det_F", r.min_det_f},
            {"seconds", r.seconds},
            {"detection_seconds", r.detection_seconds}};
  if (const tet::ElasticModel* m = sim.support_model()) {
    s["support"]["deformable"] = {{"tetrahedra", m->num_elements()},
                                  {"vertices", m->num_vertices()},
                                  {"max_displacement_m", r.support_max_displacement},
                                  {"min_det_F", r.support_min_det_f},
                                  {"base_force_N", vec(r.support_base_force)},
                                  {"reverse_contacts", r.reverse_contacts}};
  }
  if (scene.reference_map && !(r.body_pressure.maxCoeff() > 0.0)) {
    s["template"] = {{"grid", scene.reference_map->file.string()}, {"note", "no contact to compare"}};
  } else if (scene.reference_map) {
    const TemplateSpec& t = *scene.reference_map;
    const report::TemplateComparison c = report::compare_with_template(deformed_skin(sim), r.body_pressure, toward_body, t.grid);
    report::write_template_comparison_svg(out / "template_comparison.svg", c, t.grid, "simulated, body side", t.title);
    s["template"] = {{"grid", t.file.string()},
                     {"title", t.title},
                     {"correlation", c.correlation},
                     {"pixels", c.pixels},
                     {"peak_pressure_Pa", {{"simulated", c.simulated_peak}, {"template", c.template_peak}}},
                     {"length_scale", c.length_scale},
                     {"width_scale", c.width_scale},
                     {"length_reversed", c.length_reversed},
                     {"width_reversed", c.width_reversed}};
  }
  if (!r.message.empty()) s["note"] = r.message;
  write_json_file(out / "summary.json", s);
  return s;
}

RestRun run_rest(const RestScene& scene, const std::filesystem::path& out, bool overwrite) {
  if (!overwrite) require_empty_output(out);
  spdlog::info("rest: {}: body from {} ({} vertices, {} tetrahedra, {} attached), support {}", scene.file.string(),
               scene.body_source, scene.body.mesh.V.rows(), scene.body.mesh.T.rows(), scene.body.attached.size(),
               scene.support_source);
  OutputFolder folder(out);  // only now: bad input leaves nothing behind
  RestSimulation sim(scene.body, scene.support, scene.options);
  RestRun run;
  run.result = sim.solve();
  run.summary = write_rest_outputs(out, scene, sim, run.result);
  folder.keep();
  run.skin = deformed_skin(sim);
  run.support = world_support(sim);
  return run;
}

}  // namespace palpa::rest
