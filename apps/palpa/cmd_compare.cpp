// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa compare: the error between two pressure maps on the same support.

#include <cmath>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/core/json.hpp"
#include "palpa/core/units.hpp"
#include "palpa/report/compare.hpp"

namespace palpa::cli {

namespace {

struct CompareArgs {
  std::string map;
  std::string reference;
  std::string field = "pressure_Pa";
  std::string reference_field;
  std::string summary;
  bool transfer = false;
};

void run_compare_command(const CompareArgs& a) {
  const report::PressureMap m = report::read_pressure_map(a.map, a.field);
  const report::PressureMap r =
      report::read_pressure_map(a.reference, a.reference_field.empty() ? a.field : a.reference_field);
  report::MapTransfer moved;
  const report::MapComparison c = a.transfer ? report::compare_across_meshes(m, r, &moved)
                                             : report::compare_pressure_maps(m, r);
  if (a.transfer) {
    fmt::print("the reference's pressures moved onto the map's {} vertices by closest point: distances up to {} "
               "(mean {})\n",
               m.mesh.V.rows(), format_quantity(moved.max_distance, Dimension::Length),
               format_quantity(moved.mean_distance, Dimension::Length));
  }
  fmt::print("map:       {}\nreference: {}\n", a.map, a.reference);
  fmt::print("{:<16}{:>14}{:>14}\n", "", "map", "reference");
  fmt::print("{:<16}{:>14.4g}{:>14.4g}\n", "force [N]", c.a.force, c.b.force);
  fmt::print("{:<16}{:>14.4g}{:>14.4g}\n", "area [cm²]", c.a.contact_area * 1e4, c.b.contact_area * 1e4);
  fmt::print("{:<16}{:>14.4g}{:>14.4g}\n", "peak [kPa]", c.a.peak * 1e-3, c.b.peak * 1e-3);
  fmt::print("{:<16}{:>14.4g}{:>14.4g}\n", "mean [kPa]", c.a.mean * 1e-3, c.b.mean * 1e-3);
  fmt::print("{:<16}{:>14.4g}{:>14.4g}\n", "PPI [kPa]", c.a.peak_pressure_index * 1e-3,
             c.b.peak_pressure_index * 1e-3);
  fmt::print("{:<16}{:>14.4g}{:>14.4g}\n", "p95 [kPa]", c.a.p95 * 1e-3, c.b.p95 * 1e-3);
  fmt::print("{:<16}{:>14.4g}{:>14.4g}\n", "dispersion", c.a.dispersion_index, c.b.dispersion_index);
  const bool correlated = std::isfinite(c.correlation);
  fmt::print("over the {} vertices in either contact: RMS difference {:.4g} kPa ({:.1f}% of the reference's mean), "
             "largest {:.4g} kPa, correlation {}\n",
             c.vertices, c.rms_difference * 1e-3, 100.0 * c.relative_rms, c.max_difference * 1e-3,
             correlated ? fmt::format("{:.3f}", c.correlation) : std::string("undefined (a map is uniform there)"));
  if (!a.summary.empty()) {
    write_json_file(a.summary, {{"map", a.map},
                             {"reference", a.reference},
                             {"vertices", c.vertices},
                             {"rms_difference_Pa", c.rms_difference},
                             {"relative_rms", c.relative_rms},
                             {"max_difference_Pa", c.max_difference},
                             {"correlation", number_or_null(c.correlation)},
                             {"map_side", report::to_json(c.a)},
                             {"reference_side", report::to_json(c.b)},
                             {"transfer", a.transfer ? Json{{"method", "closest point"},
                                                            {"max_distance_m", moved.max_distance},
                                                            {"mean_distance_m", moved.mean_distance}}
                                                     : Json(nullptr)}});
  }
}

}  // namespace

void add_compare_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "compare",
      "The error between two pressure maps (PLY or VTU with a per-vertex pressure): a simulated map against a "
      "measured one, or two simulations; on the same support, or on two (--transfer: before and after a design).\n"
      "  palpa compare design/support_before.ply map/pressure.ply\n"
      "  palpa compare design/support_after.ply design/support_before.ply --transfer\n"
      "  palpa compare design/support_before.vtu design/support_before.vtu --reference-field pose_to_seat_Pa");
  auto a = std::make_shared<CompareArgs>();
  cmd->add_option("map", a->map, "The map to judge (.ply or .vtu)")->required();
  cmd->add_option("reference", a->reference, "The reference map (.ply or .vtu), on the same mesh unless --transfer")
      ->required();
  cmd->add_flag("--transfer", a->transfer,
                "The reference is on another mesh: move its pressures onto the map's vertices by closest point "
                "(each map's own figures stay on its own mesh)");
  cmd->add_option("--field", a->field, "Per-vertex pressure field [Pa] (default pressure_Pa)");
  cmd->add_option("--reference-field", a->reference_field, "The reference's field (default: --field)");
  cmd->add_option("--summary", a->summary, "Also write the figures to this JSON file");
  declare_paths(*cmd, {"map", "reference"}, {"--summary"});
  cmd->callback([a] { run_compare_command(*a); });
}

}  // namespace palpa::cli
