// SPDX-License-Identifier: AGPL-3.0-or-later
#include <fmt/format.h>

#include "commands.hpp"
#include "palpa/core/units.hpp"

namespace palpa::cli {

void add_units_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "units", "List the units palpa accepts in options and files (values are SI inside).");
  cmd->callback([] {
    Dimension last = Dimension::Dimensionless;
    bool first = true;
    for (const Unit& u : known_units()) {
      if (first || u.dimension != last) {
        fmt::print("{}{} (SI: {}):", first ? "" : "\n", dimension_name(u.dimension),
                   si_unit(u.dimension));
        last = u.dimension;
        first = false;
      }
      fmt::print(" {}", u.symbol);
    }
    fmt::print("\n");
  });
}

}  // namespace palpa::cli
