// SPDX-License-Identifier: AGPL-3.0-or-later
// `palpa convert IN OUT [--unit U]`: meshes between formats (coordinates to
// metres), and CSV tables to SI column units.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <memory>
#include <string>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/text.hpp"
#include "palpa/core/units.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/io/mesh.hpp"

namespace palpa::cli {

namespace {

struct ConvertOptions {
  std::string in;
  std::string out;
  std::string unit;  // empty: metres
  std::string obj_group;
};

// The size of IN's coordinate unit in metres: a length unit ("mm") or a
// length ("25.4 mm" for inches). Throws palpa::Error (Input) naming the option.
double unit_scale(const std::string& text) {
  ErrorContext where;
  where.field = "option --unit";
  const std::string_view t = trim(text);
  double scale = 0.0;
  if (const Unit* u = find_unit(t)) {
    if (u->dimension != Dimension::Length) {
      throw_input_error(
          fmt::format("'{}' is a {} unit, not a length unit", t, dimension_name(u->dimension)),
          where, "a length unit such as mm, cm or m, or a length such as 25.4 mm");
    }
    scale = u->to_si;
  } else if (!t.empty() &&
             std::string_view("0123456789+-.").find(t.front()) == std::string_view::npos) {
    // A word that is not a unit symbol.
    std::string hint;
    for (const Unit& known : known_units()) {
      if (known.dimension == Dimension::Length && to_lower(known.symbol) == to_lower(t)) {
        hint = fmt::format("; did you mean '{}'?", known.symbol);
      }
    }
    throw_input_error(fmt::format("unknown unit '{}'{}", t, hint), where,
                      "a length unit such as mm, cm or m, or a length such as 25.4 mm");
  } else {
    scale = parse_quantity(t, Dimension::Length, where);
  }
  if (!(scale > 0.0)) {
    throw_input_error(fmt::format("'{}' is not a positive length", t), where,
                      "a length unit such as mm, or a positive length such as 25.4 mm");
  }
  return scale;
}

bool is_csv(const std::filesystem::path& p) {
  return to_lower(p.extension().string()) == ".csv";
}

void run_convert(const ConvertOptions& opt) {
  const std::filesystem::path in = opt.in;
  const std::filesystem::path out = opt.out;
  if (!opt.obj_group.empty() && to_lower(in.extension().string()) != ".obj") {
    ErrorContext ctx;
    ctx.field = "option --obj-group";
    throw_input_error(fmt::format("'{}' is not an OBJ file; only OBJ files have groups", opt.in),
                      ctx, "an .obj input");
  }
  if (is_csv(in) || is_csv(out)) {
    if (!is_csv(in) || !is_csv(out)) {
      ErrorContext ctx;
      ctx.file = is_csv(in) ? out.string() : in.string();
      throw_input_error("a CSV table converts only to a CSV table", ctx, "IN.csv OUT.csv");
    }
    if (!opt.unit.empty()) {
      ErrorContext ctx;
      ctx.field = "option --unit";
      throw_input_error("--unit applies to meshes; CSV columns carry their own units", ctx,
                        "column names such as indentation_mm, force_gf");
    }
    const CsvTable si = csv_to_si(read_csv(in));
    write_csv(out, si);
    std::string names;
    for (const auto& n : si.names()) names += (names.empty() ? "" : ", ") + n;
    spdlog::info("wrote {}: {} rows, columns {}", out.string(), si.rows(), names);
    return;
  }
  MeshReadOptions read;
  if (!opt.unit.empty()) read.unit_to_si = unit_scale(opt.unit);
  read.obj_group = opt.obj_group;
  const MeshConversion done = convert_mesh(in, out, read);
  spdlog::info("wrote {}: {} vertices, {} {} (coordinates in m)", out.string(), done.vertices,
               done.elements, done.kind == MeshKind::Tet ? "tetrahedra" : "triangles");
}

}  // namespace

void add_convert_command(CLI::App& app) {
  auto opt = std::make_shared<ConvertOptions>();
  auto* cmd = app.add_subcommand(
      "convert",
      "Convert a mesh between formats (by extension), with coordinates in metres; or rewrite a "
      "CSV table with SI column units.");
  cmd->add_option("IN", opt->in,
                  "Input: a surface (.obj .ply .stl .off .vtu), a tet mesh (.node/.ele .msh "
                  ".vtu), or a .csv whose column names end in units (indentation_mm, force_gf)")
      ->required();
  cmd->add_option("OUT", opt->out,
                  "Output, format by extension: surfaces to .obj .ply .stl .off .vtu; tet meshes "
                  "to .node (with .ele, .face) .msh .vtu; CSV to .csv with SI names "
                  "(indentation_m, force_N)")
      ->required();
  cmd->add_option("--unit", opt->unit,
                  "Length unit of IN's coordinates (mm, cm, m, or a length such as '25.4 mm' for "
                  "inches); the output is in metres. Default: m. Meshes only.")
      ->type_name("UNIT");
  cmd->add_option("--obj-group", opt->obj_group,
                  "OBJ input only: keep the faces of this group or object (e.g. body)")
      ->type_name("NAME");
  cmd->footer(
      "Examples:\n"
      "  palpa convert examples/convert/scan.stl scan.ply --unit mm     surface in mm -> binary PLY in m\n"
      "  palpa convert examples/convert/scan.obj ball.ply --unit mm --obj-group body\n"
      "  palpa convert thigh.msh thigh.vtu                              Gmsh tet mesh -> ParaView\n"
      "  palpa convert examples/convert/raw.csv curve.csv               indentation_mm,force_gf -> "
      "indentation_m,force_N");
  declare_paths(*cmd, {"IN"}, {"OUT"});
  cmd->callback([opt] { run_convert(*opt); });
}

}  // namespace palpa::cli
