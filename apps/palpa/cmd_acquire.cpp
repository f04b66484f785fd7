// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa acquire: raw measurements -> the curves and maps the rest of palpa
// reads (thesis ch. 3, §7.6): poke logs -> force–indentation curve, ultrasound
// picks -> tissue depths, pressure-sensor samples -> pressure map. The
// subcommands are in cmd_acquire_<name>.cpp; this file holds what they share.

#include <fmt/format.h>

#include "acquire_options.hpp"
#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/text.hpp"

namespace palpa::cli {

acquire::TimeWindow parse_window(const std::string& text, const std::string& option) {
  const auto parts = split(text, ',');
  const ErrorContext where{"", 0, 0, "option " + option};
  if (parts.size() != 2) {
    throw_input_error(fmt::format("'{}' is not a time window", text), where, "START,END such as 1.9s,3.3s");
  }
  return {parse_quantity(parts[0], Dimension::Time, where), parse_quantity(parts[1], Dimension::Time, where)};
}

void set_columns(const std::string& text, const std::string& option, acquire::ColumnSpec& time,
                 acquire::ColumnSpec& value) {
  if (text.empty()) return;
  const auto specs = acquire::parse_column_specs(text, 2, option);
  time = specs[0];
  value = specs[1];
}

void add_log_options(CLI::App& cmd, int& order, double& cutoff, acquire::PlateauOptions& plateau,
                     acquire::LogCheck& check, double& saturation) {
  add_quantity_option(cmd, "--cutoff", cutoff, Dimension::Frequency,
                      "Low-pass cut-off (default 5 Hz: keeps a ~1 s poke, removes tremor and noise)", Sign::Positive);
  cmd.add_option("--order", order, "Butterworth order per pass (default 4)")->check(CLI::Range(1, 12));
  add_quantity_option(cmd, "--rest", plateau.min_duration, Dimension::Time,
                      "Shortest rest plateau before and after the poke (default 1 s)", Sign::Positive);
  cmd.add_option("--rest-tolerance", plateau.tolerance,
                 "A plateau stays within this fraction of the poke's amplitude (default 0.05)")
      ->check(finite_range(1e-4, 0.5));
  cmd.add_option("--max-gap", check.max_gap_steps,
                 "A time step longer than this many median steps is a gap (error; default 5)")
      ->check(finite_range(1.5, 1e6));
  add_quantity_option(cmd, "--saturation", saturation, Dimension::Time,
                      "Identical samples at a log's extreme for this long mean a clipped sensor (default 0.1 s)",
                      Sign::Positive);
}

void add_acquire_command(CLI::App& app) {
  auto* acquire = app.add_subcommand(
      "acquire", "Process raw measurements: poke logs, ultrasound depth picks, pressure sensors");
  acquire->require_subcommand(1);
  add_acquire_poke(*acquire);
  add_acquire_ultrasound(*acquire);
  add_acquire_pressure(*acquire);
}

}  // namespace palpa::cli
