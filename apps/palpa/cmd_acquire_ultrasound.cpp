// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa acquire ultrasound: interface picks + force log -> tissue depths.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <memory>
#include <optional>

#include "acquire_options.hpp"
#include "cli_common.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/acquire/output.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/text.hpp"
#include "palpa/io/csv.hpp"

namespace palpa::cli {

namespace {

struct UltrasoundArgs {
  std::string force, output, plots, summary, depth_table, position, depth_interface;
  std::vector<std::string> interfaces;
  std::string force_columns, pick_columns, force_window;
  acquire::UltrasoundOptions o;
  bool no_align = false;
  bool overwrite = false;
};

// "12mm,40mm,310mm" -> a position [m].
std::array<double, 3> parse_position(const std::string& text, const std::string& option) {
  const auto parts = split(text, ',');
  const ErrorContext where{"", 0, 0, "option " + option};
  if (parts.size() != 3) {
    throw_input_error(fmt::format("'{}' is not a position", text), where, "X,Y,Z with units, e.g. 12mm,40mm,310mm");
  }
  return {parse_quantity(parts[0], Dimension::Length, where), parse_quantity(parts[1], Dimension::Length, where),
          parse_quantity(parts[2], Dimension::Length, where)};
}

void run_acquire_ultrasound(const UltrasoundArgs& a) {
  if (!a.plots.empty() && !a.overwrite) require_empty_output(a.plots, {}, "--plots");
  acquire::UltrasoundOptions o = a.o;
  set_columns(a.force_columns, "--force-columns", o.force_time, o.force_value);
  set_columns(a.pick_columns, "--pick-columns", o.pick_time, o.pick_depth);
  if (!a.force_window.empty()) o.force_window = parse_window(a.force_window, "--force-window");
  o.align = !a.no_align;
  std::vector<std::pair<std::string, std::filesystem::path>> interfaces;
  std::vector<std::string> names;
  for (const std::string& spec : a.interfaces) {
    const auto eq = spec.find('=');
    const std::string name = eq == std::string::npos ? "" : std::string(trim(spec.substr(0, eq)));
    const bool valid = !name.empty() && std::all_of(name.begin(), name.end(), [](char ch) {
      return std::isalnum(static_cast<unsigned char>(ch)) || ch == '-';
    });
    if (!valid || std::find(names.begin(), names.end(), name) != names.end()) {
      throw_input_error(fmt::format("'{}' is not a new interface NAME=FILE", spec),
                        ErrorContext{"", 0, 0, "option --interface"},
                        "NAME=FILE with a distinct NAME of letters, digits and '-', e.g. fat=fat.csv");
    }
    names.push_back(name);
    interfaces.emplace_back(name, spec.substr(eq + 1));
  }
  std::size_t main_interface = names.empty() ? 0 : names.size() - 1;
  if (!a.depth_interface.empty()) {
    const auto it = std::find(names.begin(), names.end(), a.depth_interface);
    if (it == names.end()) {
      throw_input_error(fmt::format("there is no interface '{}'", a.depth_interface),
                        ErrorContext{"", 0, 0, "option --depth-interface"}, "one of the --interface names");
    }
    main_interface = static_cast<std::size_t>(it - names.begin());
  }
  if (a.depth_table.empty() != a.position.empty()) {
    throw_input_error("--depth-table and --position go together", ErrorContext{"", 0, 0, "option --depth-table"},
                      "both options or neither");
  }
  std::optional<acquire::DepthRow> row;
  if (!a.position.empty()) {
    row.emplace();
    row->position = parse_position(a.position, "--position");
    row->main_interface = main_interface;
    // (The table is an output this run adds a row to: not an input to protect.)
    if (std::filesystem::exists(a.depth_table)) row->existing = read_csv(a.depth_table, InputUse::RunState);
  }
  const acquire::UltrasoundResult r = acquire::process_ultrasound(a.force, interfaces, o);
  acquire::write_ultrasound(r, o, {a.output, a.depth_table, a.plots, a.summary}, row);
  std::string rest_text;
  for (std::size_t k = 0; k < names.size(); ++k) {
    rest_text += fmt::format("{}{} {}", k ? ", " : "", names[k], format_quantity(r.rest_depth[k], Dimension::Length));
  }
  spdlog::info("acquire ultrasound: ultrasound clock {:+.4f} s{}; rest depths {}; wrote {}", r.clock_shift,
               o.align ? fmt::format(" (rank correlation {:.4f})", r.correlation) : "", rest_text, a.output);
}

}  // namespace

void add_acquire_ultrasound(CLI::App& acquire) {
  auto* cmd = acquire.add_subcommand(
      "ultrasound",
      "Ultrasound interface picks + force log -> rest depths and depth against force per interface.\n"
      "  palpa acquire ultrasound --force force.csv --interface fat=fat.csv --interface bone=bone.csv -o depths.csv \\\n"
      "      --depth-table arm-depths.csv --position 12mm,40mm,310mm");
  auto a = std::make_shared<UltrasoundArgs>();
  cmd->add_option("--force", a->force, "Force gauge log (CSV: time and force columns)")->required();
  cmd->add_option("--interface", a->interfaces,
                  "NAME=FILE: control points (time, depth) picked along one tissue interface, shallowest first; "
                  "repeat per interface")
      ->required();
  cmd->add_option("-o,--output", a->output, "Depth against force while loading (CSV time_s,force_N,<name>_depth_m...)")
      ->required();
  cmd->add_option("--depth-table", a->depth_table,
                  "Add this location's rest depths to a depth table (CSV x_m,y_m,z_m,depth_m,<name>_depth_m...; "
                  "created if missing, the row at the same position replaced)");
  cmd->add_option("--position", a->position, "The location on the body scan for --depth-table, e.g. 12mm,40mm,310mm");
  cmd->add_option("--depth-interface", a->depth_interface,
                  "The interface whose rest depth goes into the table's depth_m column (default: the last, deepest)");
  cmd->add_option("--plots", a->plots, "Folder for depths.svg");
  cmd->add_flag("--overwrite", a->overwrite,
                "Write into a non-empty --plots folder (the files palpa wrote there before and does not write "
                "again are removed)");
  cmd->add_option("--summary", a->summary, "Summary JSON (rest depths, clock shift, poke window)");
  cmd->add_option("--force-columns", a->force_columns, "Time and force columns of the force log (default time,force)");
  cmd->add_option("--pick-columns", a->pick_columns, "Time and depth columns of the picks (default time,depth)");
  add_quantity_option(*cmd, "--offset", a->o.offset, Dimension::Time,
                      "Ultrasound time + offset = force time (default 0 s: started together)");
  cmd->add_flag("--no-align", a->no_align, "Use --offset as is instead of refining it");
  add_quantity_option(*cmd, "--search", a->o.search, Dimension::Time,
                      "The refinement looks this far either side of --offset (default 0.5 s)", Sign::Positive);
  add_log_options(*cmd, a->o.order, a->o.cutoff, a->o.plateau, a->o.check, a->o.saturation);
  cmd->add_option("--force-window", a->force_window, "Poke start and end on the force clock (e.g. 1.9s,3.3s)");
  declare_paths(*cmd, {"--force", "--interface="}, {"-o", "--depth-table", "--plots", "--summary"});
  cmd->callback([a] { run_acquire_ultrasound(*a); });
}

}  // namespace palpa::cli
