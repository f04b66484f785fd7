// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/mesh/output.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <numbers>
#include <vector>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/interrupt.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/io/mesh.hpp"
#include "palpa/io/vtu.hpp"

namespace palpa::mesh {

namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

std::filesystem::path with_suffix(const std::filesystem::path& out, const std::string& suffix,
                                  const std::string& extension) {
  return out.parent_path() / (out.stem().string() + suffix + extension);
}

}  // namespace

LayerFiles layer_files(const std::filesystem::path& vtu) {
  return {vtu,
          with_suffix(vtu, "", ".node"),
          with_suffix(vtu, "", ".ele"),
          with_suffix(vtu, "", ".face"),
          with_suffix(vtu, "_core", ".obj"),
          with_suffix(vtu, "_outer", ".obj"),
          with_suffix(vtu, "_summary", ".json"),
          with_suffix(vtu, "_attached", ".csv")};
}

Json tet_statistics_json(const TetStatistics& s) {
  return Json{{"tets", s.tets},
              {"vertices", s.vertices},
              {"inverted_tets", s.inverted},
              {"min_dihedral_deg", s.min_dihedral / kDegree},
              {"max_dihedral_deg", s.max_dihedral / kDegree},
              {"max_radius_edge", s.max_radius_edge},
              {"mean_radius_edge", s.mean_radius_edge},
              {"tets_below_min_dihedral", s.below_min_dihedral},
              {"tets_above_max_radius_edge", s.above_max_radius_edge},
              {"min_tet_volume_m3", s.min_volume},
              {"volume_m3", s.volume}};
}

Json layer_summary_json(const LayerMesh& layer, const LayerSummary& s, const LayerRequest& request) {
  const DepthSpec& depth = request.depth;
  return Json{
      {"palpa_mesh_layer", 1},
      {"surface", request.surface},
      {"edge_length_m", request.edge_length},
      {"depth",
       depth.samples ? Json{{"samples", request.depth_samples}, {"column", depth.samples->field}}
                     : Json{{"uniform_m", depth.uniform}}},
      {"quality_bounds", {{"max_radius_edge", layer.quality.max_radius_edge},
                          {"min_dihedral_deg", layer.quality.min_dihedral / kDegree},
                          {"max_volume_m3", layer.quality.max_volume}}},
      {"elements", tet_statistics_json(s.quality)},
      {"outer_triangles", s.outer_triangles},
      {"core_triangles", s.core_triangles},
      {"attached_vertices", s.attached},
      {"tets_dropped_inside_core", s.dropped_in_core},
      {"volume_m3", {{"outer", s.outer_volume}, {"core", s.core_volume}, {"layer", s.layer_volume}}},
      {"thickness_m", {{"min", s.thickness_min}, {"mean", s.thickness_mean}, {"max", s.thickness_max}}},
      {"requested_depth_m", {{"min", s.depth_min}, {"mean", s.depth_mean}, {"max", s.depth_max}}},
      {"depth_clamped_vertices", layer.depth_clamped},
      {"youngs_modulus_Pa",
       layer.youngs_modulus.size() > 0 ? Json{{"min", s.youngs_min}, {"max", s.youngs_max}} : Json(nullptr)},
      {"stage_seconds", request.stage_seconds}};
}

void write_layer(const LayerMesh& layer, const Json& summary, const std::filesystem::path& vtu) {
  const LayerFiles f = layer_files(vtu);
  OutputBatch batch;
  UnstructuredGrid grid = grid_of(layer.tets);
  Eigen::VectorXd attached = Eigen::VectorXd::Zero(layer.tets.V.rows());
  for (const Eigen::Index i : layer.attached) attached(i) = 1.0;
  grid.point_data.push_back({"attached", attached});
  if (layer.youngs_modulus.size() > 0) grid.cell_data.push_back({"youngs_modulus_Pa", layer.youngs_modulus});
  write_vtu(batch.stage(f.vtu), grid);
  write_tet_mesh(batch.stage(f.node), layer.tets);
  batch.stage(f.ele);
  batch.stage(f.face);
  write_surface_mesh(batch.stage(f.core), layer.core);
  write_surface_mesh(batch.stage(f.outer), layer.outer);
  CsvTable attached_table;
  attached_table.add_comment("vertices of " + vtu.filename().string() +
                             " (0-based rows of its points / .node) attached to the rigid core");
  attached_table.add_column("vertex", std::vector<double>(layer.attached.begin(), layer.attached.end()));
  batch.add(f.attached) << format_csv(attached_table);
  batch.add(f.summary) << format_json(summary, f.summary);
  batch.commit();
}

LayerSummary mesh_layer_to_files(const SurfaceMesh& scan, const std::optional<Samples>& stiffness, LayerOptions o,
                                 LayerRequest request, const std::filesystem::path& vtu) {
  auto started = std::chrono::steady_clock::now();
  std::string current;
  const auto close_stage = [&] {
    const auto now = std::chrono::steady_clock::now();
    if (!current.empty()) request.stage_seconds[current] = std::chrono::duration<double>(now - started).count();
    started = now;
  };
  o.on_stage = [&](std::string_view stage) {
    check_interrupt();
    close_stage();
    current = stage;
    spdlog::info("mesh layer: {}", stage);
  };
  const LayerMesh layer = make_layer(scan, request.depth, stiffness, o);
  close_stage();
  check_interrupt();
  const LayerSummary s = summarize_layer(layer, layer.quality);
  write_layer(layer, layer_summary_json(layer, s, request), vtu);
  return s;
}

}  // namespace palpa::mesh
