// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Helpers shared by the subcommands: options that carry units, and the
// conventions every command follows (SI inside, units required at the edge).

#include <CLI/CLI.hpp>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "palpa/core/units.hpp"

namespace palpa::cli {

// Which values of a quantity option mean something.
enum class Sign { Any, Positive, NonNegative };

// Adds an option whose value is a quantity with a unit ("2 mm", "10kPa"). The
// value is converted to SI into `target` during parsing; a missing unit, an
// unknown unit, one of the wrong kind or a value of the wrong sign is a usage
// error naming the option. The help text gets the dimension and an example
// appended.
CLI::Option* add_quantity_option(CLI::App& app, const std::string& name, double& target,
                                 Dimension dimension, const std::string& description, Sign sign = Sign::Any);

// A plain number option's check: a finite number from `lo` to `hi` (CLI::Range
// lets NaN through: every comparison with it is false).
CLI::Validator finite_range(double lo, double hi);

// "LOW:HIGH" -> (LOW, HIGH), two plain numbers with LOW < HIGH; an input
// error naming `option` otherwise, with `example` ("0.6:1.6") as the expected form.
std::pair<double, double> parse_range(const std::string& text, const std::string& option, const std::string& example);

// Declares which of a command's options (by any of their names, positional
// ones by their name) are files it reads and which are files or folders it
// writes. A name ending in '=' ("--interface=") takes values NAME=FILE, of
// which FILE counts.
void declare_paths(const CLI::App& cmd, std::vector<std::string> inputs, std::vector<std::string> outputs);

// After parsing: refuses (palpa::Error, Input) any output of a parsed command
// that is one of its inputs or another of its outputs (the same file under
// any spelling, through links too), before anything is read or written.
void check_distinct_paths(const CLI::App& app);

}  // namespace palpa::cli
