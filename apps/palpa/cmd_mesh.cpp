// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa mesh: simulation meshes of bodies — a soft tet layer around a rigid
// core from a scan and tissue depths (`layer`), analytic test bodies (`body`),
// and solid tet meshes of closed surfaces (`solid`). The subcommands are in
// cmd_mesh_<name>.cpp; this file holds what they share.

#include <fmt/format.h>

#include <cmath>

#include "cli_common.hpp"
#include "commands.hpp"
#include "mesh_options.hpp"
#include "palpa/core/text.hpp"
#include "palpa/mesh/layer.hpp"
#include "palpa/mesh/surface_check.hpp"

namespace palpa::cli {

ErrorContext option_context(const std::string& name) {
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
                      option_context("--edge"),
                      "a longer --edge, or --unit for a surface whose coordinates are not metres");
  }
}

// Metres per coordinate unit: a unit symbol ("mm") or a length ("0.1 m").
double length_unit(const std::string& text) {
  if (text.empty()) return 1.0;
  const Unit* u = find_unit(trim(text));
  const double scale =
      u ? (u->dimension == Dimension::Length ? u->to_si : 0.0)
        : parse_quantity(text, Dimension::Length, option_context("--unit"));
  if (!(scale > 0.0)) {
    throw_input_error(fmt::format("'{}' is not a length unit", text), option_context("--unit"),
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
                 "TetGen quality bound: largest circumradius / shortest edge of a tet (> 1; default 1.5)")
      ->check(finite_range(1.0, 1e3));
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

void add_mesh_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "mesh", "Simulation meshes of bodies: a soft tet layer around a rigid core (layer), "
              "analytic test bodies (body), solid tet meshes of closed surfaces (solid).");
  cmd->require_subcommand(1);
  add_mesh_layer(*cmd);
  add_mesh_body(*cmd);
  add_mesh_solid(*cmd);
}

}  // namespace palpa::cli
