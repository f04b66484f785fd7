// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// What the three `palpa acquire` subcommands share: time windows, column
// specs and the options of every command that reads time-stamped logs; and
// the registration of each subcommand (cmd_acquire_<name>.cpp).

#include <CLI/CLI.hpp>

#include <string>

#include "palpa/acquire/poke.hpp"

namespace palpa::cli {

// "1.9s,3.3s" -> a window on a log's clock.
acquire::TimeWindow parse_window(const std::string& text, const std::string& option);

// "NAME[:UNIT],NAME[:UNIT]" -> the time and value columns (unchanged when empty).
void set_columns(const std::string& text, const std::string& option, acquire::ColumnSpec& time,
                 acquire::ColumnSpec& value);

// The low-pass filter, the rest plateaus and the log checks.
void add_log_options(CLI::App& cmd, int& order, double& cutoff, acquire::PlateauOptions& plateau,
                     acquire::LogCheck& check, double& saturation);

void add_acquire_poke(CLI::App& acquire);
void add_acquire_ultrasound(CLI::App& acquire);
void add_acquire_pressure(CLI::App& acquire);

}  // namespace palpa::cli
