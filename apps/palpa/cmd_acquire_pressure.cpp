// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa acquire pressure: pressure-sensor samples -> a pressure map on the support.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <memory>

#include "acquire_options.hpp"
#include "cli_common.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/acquire/output.hpp"
#include "palpa/core/error.hpp"
#include "palpa/io/mesh.hpp"

namespace palpa::cli {

namespace {

struct PressureArgs {
  std::string mesh, mesh_unit = "m", locations, samples, output, method = "biharmonic";
  acquire::PressureOptions o;
  double max_distance = 5e-3;
  int trim = 50;
  int clip_run = 10;
  bool no_clamp = false;
  bool overwrite = false;
};

void run_acquire_pressure(const PressureArgs& a) {
  if (!a.overwrite) require_empty_output(a.output);
  acquire::PressureOptions o = a.o;
  const ErrorContext unit_where{"", 0, 0, "option --unit"};
  const Unit* unit = find_unit(a.mesh_unit);
  if (unit == nullptr || unit->dimension != Dimension::Length) {
    throw_input_error(fmt::format("'{}' is not a length unit", a.mesh_unit), unit_where, "a length unit such as m or mm");
  }
  if (a.method == "biharmonic") {
    o.interpolation.method = geometry::SurfaceInterpolation::Biharmonic;
  } else if (a.method == "harmonic") {
    o.interpolation.method = geometry::SurfaceInterpolation::Harmonic;
  } else {
    throw_input_error(fmt::format("unknown interpolation '{}'", a.method), ErrorContext{"", 0, 0, "option --method"},
                      "biharmonic or harmonic");
  }
  o.interpolation.max_distance = a.max_distance;
  o.interpolation.clamp_to_sample_range = !a.no_clamp;
  o.trim = static_cast<std::size_t>(a.trim);
  o.clip_run = static_cast<std::size_t>(a.clip_run);
  MeshReadOptions mo;
  mo.unit_to_si = unit->to_si;
  const SurfaceMesh mesh = read_surface_mesh(a.mesh, mo);
  const acquire::PressureMap m = acquire::pressure_map(mesh, a.locations, a.samples, o);

  acquire::write_pressure_map(mesh, m, acquire::pressure_summary(mesh, m, o, a.mesh, a.locations, a.samples, a.method),
                              a.output);
  spdlog::info("acquire pressure: {} locations{}, {} interpolation onto {} vertices, {} within {} of a location; "
               "C = {}, pressure {} .. {}, net force {}; wrote {}",
               m.locations.size(), m.compensated ? " (posture compensated)" : "", a.method, mesh.V.rows(),
               format_quantity(m.covered_area, Dimension::Area),
               std::isfinite(m.reach) ? format_quantity(m.reach, Dimension::Length) : "any distance",
               format_quantity(m.constant, Dimension::Pressure),
               format_quantity(m.pressure.minCoeff(), Dimension::Pressure),
               format_quantity(m.pressure.maxCoeff(), Dimension::Pressure),
               format_quantity(m.net_force.norm(), Dimension::Force), a.output);
}

}  // namespace

void add_acquire_pressure(CLI::App& acquire) {
  auto* cmd = acquire.add_subcommand(
      "pressure",
      "Pressure-sensor samples per location + reference sensor -> pressure map on the support mesh (PLY, VTU).\n"
      "  palpa acquire pressure --mesh sole.obj --unit mm --locations locations.csv --samples samples.csv \\\n"
      "      --load 343N -o pressure");
  auto a = std::make_shared<PressureArgs>();
  cmd->add_option("--mesh", a->mesh, "Support surface (OBJ, PLY, STL, OFF, VTU)")->required();
  cmd->add_option("--unit", a->mesh_unit, "Length unit of the mesh file's coordinates (default m)");
  cmd->add_option("--locations", a->locations, "Sensor locations (CSV location,x_<unit>,y_<unit>,z_<unit>)")
      ->required();
  cmd->add_flag("--overwrite", a->overwrite,
                "Write into a non-empty output folder (the files palpa wrote there before and does not write "
                "again are removed)");
  cmd->add_option("--samples", a->samples, "Samples (CSV location,reading[,reference]; one row per sample)")
      ->required();
  add_quantity_option(*cmd, "--load", a->o.load, Dimension::Force,
                      "Net force the map must carry, e.g. half the body weight", Sign::Positive)
      ->required();
  cmd->add_option("-o,--output", a->output, "Output folder: pressure.ply, pressure.vtu, locations.csv, summary.json")
      ->required();
  cmd->add_option("--trim", a->trim, "Samples dropped at each end per location (default 50)")
      ->check(CLI::Range(0, 1000000));
  cmd->add_option("--clip-run", a->clip_run,
                  "This many identical samples in a row at a location's maximum mean a saturated sensor (default 10)")
      ->check(CLI::Range(2, 1000000));
  cmd->add_option("--method", a->method, "biharmonic (linearly precise, default) or harmonic");
  add_quantity_option(*cmd, "--max-distance", a->max_distance, Dimension::Length,
                      "Largest distance of a location from the surface (default 5 mm)", Sign::Positive);
  add_quantity_option(*cmd, "--reach", a->o.reach, Dimension::Length,
                      "How far the map extends along the surface from the nearest location; beyond it nothing was "
                      "measured and the pressure is 0 (default: the locations' spacing, the largest distance from one "
                      "to its nearest neighbour)",
                      Sign::Positive);
  cmd->add_flag("--no-clamp", a->no_clamp, "Do not clamp the interpolated map to the locations' range");
  cmd->add_option("--reading-column", a->o.reading_column, "Name (or base name) of the reading column (default reading)");
  cmd->add_option("--reference-column", a->o.reference_column,
                  "Name (or base name) of the reference sensor's column (default reference; absent: no compensation)");
  declare_paths(*cmd, {"--mesh", "--locations", "--samples"}, {"-o"});
  cmd->callback([a] { run_acquire_pressure(*a); });
}

}  // namespace palpa::cli
