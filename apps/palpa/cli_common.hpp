#pragma once
// Helpers shared by the subcommands: options that carry units, and the
// conventions every command follows (SI inside, units required at the edge).

#include <CLI/CLI.hpp>
#include <string>

#include "palpa/core/units.hpp"

namespace palpa::cli {

// Adds an option whose value is a quantity with a unit ("2 mm", "10kPa"). The
// value is converted to SI into `target` during parsing; a missing unit, an
// unknown unit or one of the wrong kind is a usage error naming the option.
// The help text gets the dimension and an example appended.
CLI::Option* add_quantity_option(CLI::App& app, const std::string& name, double& target,
                                 Dimension dimension, const std::string& description);

}  // namespace palpa::cli
