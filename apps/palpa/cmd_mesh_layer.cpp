// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa mesh layer: a soft tet layer around a rigid core from a scan and tissue depths.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "cli_common.hpp"
#include "mesh_options.hpp"
#include "palpa/core/error.hpp"
#include "palpa/io/mesh.hpp"
#include "palpa/mesh/layer.hpp"
#include "palpa/mesh/output.hpp"
#include "palpa/mesh/surface_check.hpp"

namespace palpa::cli {

namespace {

struct LayerArgs {
  std::string surface;
  std::string unit;
  double depth = std::numeric_limits<double>::quiet_NaN();  // NaN: --depth not given
  std::string depth_samples;
  std::string depth_column = "depth";
  bool clamp_depth = false;
  std::string core_offset = "normals";
  std::string stiffness_samples;
  std::string stiffness_column = "youngs_modulus";
  double edge = 5e-3;
  double max_sample_distance = 5e-3;
  std::string interpolation = "biharmonic";
  QualityArgs quality;
  std::string output;
};

void run_layer(const LayerArgs& a) {
  existing_folder_of(a.output);
  MeshReadOptions read;
  read.unit_to_si = length_unit(a.unit);
  const SurfaceMesh scan = read_surface_mesh(a.surface, read);
  if (a.edge > 0.0) check_edge_for(mesh::surface_area(scan), a.edge, a.surface);
  const bool uniform = !std::isnan(a.depth);  // --depth given
  if (uniform && !a.depth_samples.empty()) {
    throw_input_error("both --depth and --depth-samples given", option_context("--depth"),
                      "one of them");
  }
  mesh::DepthSpec depth;
  if (!a.depth_samples.empty()) {
    depth.samples = mesh::read_samples(a.depth_samples, a.depth_column, Dimension::Length);
  } else if (!uniform) {
    throw_input_error("no layer depth", option_context("--depth"),
                      "--depth (e.g. 10mm) or --depth-samples FILE.csv");
  } else if (!(a.depth > 0.0) || !std::isfinite(a.depth)) {
    throw_input_error(fmt::format("a layer depth of {}", format_quantity(a.depth, Dimension::Length)),
                      option_context("--depth"), "a positive length, e.g. 10mm");
  } else {
    depth.uniform = a.depth;
  }
  std::optional<mesh::Samples> stiffness;
  if (!a.stiffness_samples.empty()) {
    stiffness = mesh::read_samples(a.stiffness_samples, a.stiffness_column, Dimension::Pressure);
  }
  mesh::LayerOptions o;
  o.edge_length = a.edge;
  o.max_sample_distance = a.max_sample_distance;
  if (a.interpolation == "harmonic") {
    o.interpolation = geometry::SurfaceInterpolation::Harmonic;
  } else if (a.interpolation != "biharmonic") {
    throw_input_error(fmt::format("unknown interpolation '{}'", a.interpolation),
                      option_context("--interpolation"), "harmonic or biharmonic");
  }
  o.quality = quality_from(a.quality);
  o.source = a.surface;
  o.clamp_depth = a.clamp_depth;
  try {
    o.core_offset = mesh::parse_core_offset(a.core_offset);
  } catch (const Error&) {
    throw_input_error(fmt::format("unknown core offset '{}'", a.core_offset), option_context("--core-offset"),
                      "normals or distance");
  }
  const mesh::LayerSummary s = mesh::mesh_layer_to_files(
      scan, stiffness, o, mesh::LayerRequest{a.surface, a.edge, depth, a.depth_samples}, a.output);
  const mesh::LayerFiles f = mesh::layer_files(a.output);
  spdlog::info(
      "wrote {} (+ .node/.ele/.face, {}, {}, {}, {}): {} tets, {} attached vertices, min dihedral "
      "{:.1f} deg, max radius-edge {:.2f}, layer {:.4g} cm3, thickness {:.1f}-{:.1f} mm",
      a.output, f.core.filename().string(), f.outer.filename().string(), f.summary.filename().string(),
      f.attached.filename().string(), s.quality.tets, s.attached, s.quality.min_dihedral / kDegree,
      s.quality.max_radius_edge, s.layer_volume * 1e6, s.thickness_min * 1e3,
      s.thickness_max * 1e3);
}

}  // namespace

void add_mesh_layer(CLI::App& mesh) {
  auto la = std::make_shared<LayerArgs>();
  auto* layer = mesh.add_subcommand(
      "layer",
      "Tetrahedral soft layer between a closed scan surface and an inner surface at a uniform "
      "or sampled depth; inner vertices are attached to a rigid core.");
  layer->add_option("--surface", la->surface, "Closed body surface (.obj .ply .stl .off .vtu)")
      ->required();
  layer->add_option("--unit", la->unit, "Length unit of the surface's coordinates (default m)")
      ->type_name("UNIT");
  add_quantity_option(*layer, "--depth", la->depth, Dimension::Length,
                      "Uniform layer depth, e.g. 10mm");
  layer->add_option("--depth-samples", la->depth_samples,
                    "CSV of measured depths: x_<unit>,y_<unit>,z_<unit>,depth_<unit> (positions "
                    "in the scan's frame)")
      ->type_name("FILE.csv");
  layer->add_option("--depth-column", la->depth_column,
                    "Base name of the depth column (e.g. bone_distance or fat_depth; default depth)");
  layer->add_flag("--clamp-depth", la->clamp_depth,
                  "Thin the layer where the depth does not fit the local thickness (folds, toes, "
                  "the rim of a clipped body) instead of refusing");
  layer->add_option("--core-offset", la->core_offset,
                    "How the core surface is made: normals (each skin vertex pushed inward by its "
                    "depth) or distance (the level set of the distance to the skin: no core where "
                    "the body is thinner than twice the depth; default normals)");
  layer->add_option("--stiffness-samples", la->stiffness_samples,
                    "CSV of Young's moduli: x_<unit>,y_<unit>,z_<unit>,youngs_modulus_<unit>; "
                    "each tet gets the value interpolated at the skin above it")
      ->type_name("FILE.csv");
  layer->add_option("--stiffness-column", la->stiffness_column,
                    "Base name of the modulus column (default youngs_modulus)");
  add_quantity_option(*layer, "--edge", la->edge, Dimension::Length,
                      "Target edge length of both surfaces (default 5mm; 0 keeps the scan's)");
  add_quantity_option(*layer, "--max-sample-distance", la->max_sample_distance,
                      Dimension::Length,
                      "Largest distance from a sample to the surface (default 5mm)", Sign::Positive);
  layer->add_option("--interpolation", la->interpolation,
                    "Spreading samples over the surface: biharmonic (smooth, reproduces linear "
                    "trends; default) or harmonic (no overshoot)");
  add_quality_options(*layer, la->quality);
  layer->add_option("-o,--output", la->output,
                    "Output .vtu; beside it <name>.node/.ele/.face, <name>_core.obj, "
                    "<name>_outer.obj, <name>_attached.csv and <name>_summary.json")
      ->required();
  layer->footer(
      "Examples:\n"
      "  palpa mesh body thigh -o thigh.obj\n"
      "  palpa mesh layer --surface thigh.obj --depth 15mm --edge 8mm -o thigh.vtu\n"
      "  palpa mesh layer --surface examples/rest/foot/foot_mean.obj \\\n"
      "      --depth-samples examples/mesh/foot-table31.csv --depth-column bone_distance \\\n"
      "      --stiffness-samples examples/mesh/foot-moduli.csv --clamp-depth --edge 6mm -o foot.vtu");
  declare_paths(*layer, {"--surface", "--depth-samples", "--stiffness-samples"}, {"-o"});
  layer->callback([la] { run_layer(*la); });
}

}  // namespace palpa::cli
