// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa mesh: simulation meshes of bodies — a soft tet layer around a rigid
// core from a scan and tissue depths (`layer`), analytic test bodies (`body`),
// and solid tet meshes of closed surfaces (`solid`).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <filesystem>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/input_file.hpp"
#include "palpa/core/interrupt.hpp"
#include "palpa/core/text.hpp"
#include "palpa/io/mesh.hpp"
#include "palpa/mesh/bodies.hpp"
#include "palpa/mesh/layer.hpp"
#include "palpa/mesh/output.hpp"
#include "palpa/mesh/surface_check.hpp"
#include "palpa/mesh/tetrahedralize.hpp"

namespace palpa::cli {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

struct QualityArgs {
  double max_radius_edge = 1.5;
  double min_dihedral = 12.0 * kDegree;
  double tet_size = 0.0;  // edge of a regular tet of the largest volume [m]; 0 = default
};

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

struct BodyArgs {
  std::string shape;
  double length = 0.0, width = 0.0, height = 0.0, radius = 0.0;
  double edge = 5e-3;
  std::string output;
};

struct SolidArgs {
  std::string surface;
  std::string unit;
  double edge = 0.0;
  QualityArgs quality;
  std::string output;
};

ErrorContext option(const std::string& name) {
  ErrorContext c;
  c.field = "option " + name;
  return c;
}

// A surface of `area` remeshed to --edge: refused by the option's name when it
// would make more triangles than palpa makes (mesh::kMaxRemeshTriangles).
void check_edge_for(double area, double edge, const std::string& what) {
  const double n = mesh::remeshed_triangles(area, edge);
  if (!(n <= mesh::kMaxRemeshTriangles)) {
    throw_input_error(fmt::format("{} of {:.4g} m² remeshed to edges of {} would make about {:.3g} triangles, "
                                  "more than the {:.0f} palpa makes",
                                  what, area, format_quantity(edge, Dimension::Length), n, mesh::kMaxRemeshTriangles),
                      option("--edge"), "a longer --edge, or --unit for a surface whose coordinates are not metres");
  }
}

// Metres per coordinate unit: a unit symbol ("mm") or a length ("0.1 m").
double length_unit(const std::string& text) {
  if (text.empty()) return 1.0;
  const Unit* u = find_unit(trim(text));
  const double scale =
      u ? (u->dimension == Dimension::Length ? u->to_si : 0.0)
        : parse_quantity(text, Dimension::Length, option("--unit"));
  if (!(scale > 0.0)) {
    throw_input_error(fmt::format("'{}' is not a length unit", text), option("--unit"),
                      "a length unit such as mm, cm or m, or a length such as 0.1 m");
  }
  return scale;
}

mesh::TetQuality quality_from(const QualityArgs& q) {
  mesh::TetQuality t;
  t.max_radius_edge = q.max_radius_edge;
  t.min_dihedral = q.min_dihedral;
  if (q.tet_size > 0.0) t.max_volume = std::pow(q.tet_size, 3) / (6.0 * std::sqrt(2.0));
  return t;
}

void add_quality_options(CLI::App& cmd, QualityArgs& q) {
  cmd.add_option("--max-radius-edge", q.max_radius_edge,
                 "TetGen quality bound: largest circumradius / shortest edge of a tet (> 1; default 1.5)");
  add_quantity_option(cmd, "--min-dihedral", q.min_dihedral, Dimension::Angle,
                      "TetGen quality target: smallest dihedral angle (default 12 deg)", Sign::Positive);
  add_quantity_option(cmd, "--tet-size", q.tet_size, Dimension::Length,
                      "Largest tet volume, as the edge of a regular tet of that volume (default: "
                      "the --edge length for layers, no bound for solids)", Sign::Positive);
}

// The folder `target` goes into; refused if it does not exist. Checked before
// the meshing too, so that a typo in -o does not cost the whole run.
std::filesystem::path existing_folder_of(const std::filesystem::path& target) {
  const auto folder = target.parent_path().empty() ? std::filesystem::path(".") : target.parent_path();
  if (!std::filesystem::is_directory(folder)) {
    ErrorContext c;
    c.file = target.string();
    c.field = "option -o";
    throw_input_error(fmt::format("the output folder '{}' does not exist", folder.string()), c,
                      "an existing folder");
  }
  return folder;
}

void run_layer(const LayerArgs& a) {
  existing_folder_of(a.output);
  MeshReadOptions read;
  read.unit_to_si = length_unit(a.unit);
  const SurfaceMesh scan = read_surface_mesh(a.surface, read);
  if (a.edge > 0.0) check_edge_for(mesh::surface_area(scan), a.edge, a.surface);
  const bool uniform = !std::isnan(a.depth);  // --depth given
  if (uniform && !a.depth_samples.empty()) {
    throw_input_error("both --depth and --depth-samples given", option("--depth"),
                      "one of them");
  }
  mesh::DepthSpec depth;
  if (!a.depth_samples.empty()) {
    depth.samples = mesh::read_samples(a.depth_samples, a.depth_column, Dimension::Length);
  } else if (!uniform) {
    throw_input_error("no layer depth", option("--depth"),
                      "--depth (e.g. 10mm) or --depth-samples FILE.csv");
  } else if (!(a.depth > 0.0) || !std::isfinite(a.depth)) {
    throw_input_error(fmt::format("a layer depth of {}", format_quantity(a.depth, Dimension::Length)),
                      option("--depth"), "a positive length, e.g. 10mm");
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
                      option("--interpolation"), "harmonic or biharmonic");
  }
  o.quality = quality_from(a.quality);
  o.source = a.surface;
  o.clamp_depth = a.clamp_depth;
  try {
    o.core_offset = mesh::parse_core_offset(a.core_offset);
  } catch (const Error&) {
    throw_input_error(fmt::format("unknown core offset '{}'", a.core_offset), option("--core-offset"),
                      "normals or distance");
  }
  auto started = std::chrono::steady_clock::now();
  std::string current;
  Json timings = Json::object();
  o.on_stage = [&](std::string_view stage) {
    check_interrupt();
    const auto now = std::chrono::steady_clock::now();
    if (!current.empty()) {
      timings[current] = std::chrono::duration<double>(now - started).count();
    }
    current = stage;
    started = now;
    spdlog::info("mesh layer: {}", stage);
  };
  const mesh::LayerMesh layer = mesh::make_layer(scan, depth, stiffness, o);
  timings[current] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  check_interrupt();
  const mesh::LayerSummary s = mesh::summarize_layer(layer, layer.quality);

  mesh::LayerRequest request{a.surface, a.edge, depth, a.depth_samples, timings};
  mesh::write_layer(layer, mesh::layer_summary_json(layer, s, request), a.output);
  const mesh::LayerFiles f = mesh::layer_files(a.output);
  spdlog::info(
      "wrote {} (+ .node/.ele/.face, {}, {}, {}, {}): {} tets, {} attached vertices, min dihedral "
      "{:.1f} deg, max radius-edge {:.2f}, layer {:.4g} cm3, thickness {:.1f}-{:.1f} mm",
      a.output, f.core.filename().string(), f.outer.filename().string(), f.summary.filename().string(),
      f.attached.filename().string(), s.quality.tets, s.attached, s.quality.min_dihedral / kDegree,
      s.quality.max_radius_edge, s.layer_volume * 1e6, s.thickness_min * 1e3,
      s.thickness_max * 1e3);
}

void run_body(const BodyArgs& a) {
  mesh::BodyOptions o;
  o.shape = mesh::parse_body_shape(a.shape);
  o.size = Eigen::Vector3d(a.length, a.width, a.height);
  if (o.shape == mesh::BodyShape::Sphere || o.shape == mesh::BodyShape::Foot) {
    o.size = Eigen::Vector3d(a.length, a.length, a.length);
  } else if (!o.size.isZero() && !(o.size.minCoeff() > 0.0)) {
    throw_input_error("give --length, --width and --height together", option("--length"),
                      "all three sizes, or none for the default");
  }
  o.radius = a.radius;
  o.edge_length = a.edge;
  if (const double smallest = mesh::body_smallest_feature(o); !(a.edge <= smallest / 4.0)) {
    throw_input_error(fmt::format("an edge of {} for a {} whose smallest feature is {}",
                                  format_quantity(a.edge, Dimension::Length), mesh::body_shape_name(o.shape),
                                  format_quantity(smallest, Dimension::Length)),
                      option("--edge"), "at most a quarter of the smallest feature");
  }
  // The body's area is at most its bounding box's.
  check_edge_for(2.0 * (o.size.x() * o.size.y() + o.size.y() * o.size.z() + o.size.z() * o.size.x()), a.edge,
                 fmt::format("a {}", mesh::body_shape_name(o.shape)));
  const SurfaceMesh m = mesh::make_body(o);
  write_surface_mesh(a.output, m);
  spdlog::info("wrote {}: {} {} with {} vertices, {} triangles, volume {:.4g} cm3",
               a.output, mesh::body_shape_name(o.shape), "surface", m.V.rows(), m.F.rows(),
               mesh::enclosed_volume(m) * 1e6);
}

void run_solid(const SolidArgs& a) {
  MeshReadOptions read;
  read.unit_to_si = length_unit(a.unit);
  SurfaceMesh s = mesh::repair_surface(read_surface_mesh(a.surface, read));
  existing_folder_of(a.output);
  mesh::check_closed_surface(s, a.surface);
  if (a.edge > 0.0) {
    check_edge_for(mesh::surface_area(s), a.edge, a.surface);
    s = mesh::remesh_surface(s, a.edge);
  }
  const mesh::TetQuality q = quality_from(a.quality);
  const TetMesh tets = mesh::tetrahedralize(s, q);
  const mesh::TetStatistics st = mesh::tet_statistics(tets, q);
  write_tet_mesh(a.output, tets);
  spdlog::info("wrote {}: {} tets, {} vertices, min dihedral {:.1f} deg, max radius-edge {:.2f}",
               a.output, st.tets, st.vertices, st.min_dihedral / kDegree, st.max_radius_edge);
}

}  // namespace

void add_mesh_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "mesh", "Simulation meshes of bodies: a soft tet layer around a rigid core (layer), "
              "analytic test bodies (body), solid tet meshes of closed surfaces (solid).");
  cmd->require_subcommand(1);

  auto la = std::make_shared<LayerArgs>();
  auto* layer = cmd->add_subcommand(
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

  auto ba = std::make_shared<BodyArgs>();
  auto* body = cmd->add_subcommand("body", "An analytic closed test body surface.");
  body->add_option("SHAPE", ba->shape, "sphere, rounded-block, thigh or foot")->required();
  add_quantity_option(*body, "--length", ba->length, Dimension::Length,
                      "Size along x (sphere: diameter; foot: heel to toe); default per shape", Sign::Positive);
  add_quantity_option(*body, "--width", ba->width, Dimension::Length, "Size along y (block, thigh)", Sign::Positive);
  add_quantity_option(*body, "--height", ba->height, Dimension::Length,
                      "Size along z (block, thigh)", Sign::Positive);
  add_quantity_option(*body, "--radius", ba->radius, Dimension::Length,
                      "Block edge rounding radius (default 10mm)", Sign::NonNegative);
  add_quantity_option(*body, "--edge", ba->edge, Dimension::Length,
                      "Target triangle edge length (default 5mm)", Sign::Positive);
  body->add_option("-o,--output", ba->output, "Output surface (.obj .ply .stl .off .vtu), in m")
      ->required();
  body->callback([ba] { run_body(*ba); });

  auto sa = std::make_shared<SolidArgs>();
  auto* solid = cmd->add_subcommand("solid", "Solid tet mesh of the inside of a closed surface.");
  solid->add_option("--surface", sa->surface, "Closed surface (.obj .ply .stl .off .vtu)")
      ->required();
  solid->add_option("--unit", sa->unit, "Length unit of the surface's coordinates (default m)")
      ->type_name("UNIT");
  add_quantity_option(*solid, "--edge", sa->edge, Dimension::Length,
                      "Remesh the surface to this edge length first (default: keep it)");
  add_quality_options(*solid, sa->quality);
  solid->add_option("-o,--output", sa->output, "Output tet mesh (.vtu, .node, .msh)")->required();
  declare_paths(*solid, {"--surface"}, {"-o"});
  solid->callback([sa] { run_solid(*sa); });
}

}  // namespace palpa::cli
