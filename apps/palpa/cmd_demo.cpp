// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa demo: the tour of palpa on the bundled example data (pipeline/demo.hpp).

#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <string>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/pipeline/demo.hpp"

#ifndef PALPA_EXAMPLES_DIR
#error "PALPA_EXAMPLES_DIR must name the bundled examples folder"
#endif

namespace palpa::cli {

void add_demo_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "demo",
      "Run palpa's stages on the bundled example data (materials, pokes, a fit) and write the results to a "
      "folder; `make demo` runs the whole subject pipeline.\n"
      "  palpa demo -o stages-demo");
  auto out = std::make_shared<std::string>("stages-demo");
  auto examples = std::make_shared<std::string>(PALPA_EXAMPLES_DIR);
  auto overwrite = std::make_shared<bool>(false);
  cmd->add_option("-o,--output", *out, "Output folder (created if missing; default stages-demo)");
  cmd->add_option("--examples", *examples, "Folder of the bundled examples");
  cmd->add_flag("--overwrite", *overwrite, "Write into a non-empty output folder");
  declare_paths(*cmd, {"--examples"}, {"-o"});
  cmd->callback([out, examples, overwrite] {
    if (!*overwrite) require_empty_output(*out);
    const pipeline::DemoResult r = pipeline::run_demo(*examples, *out);
    fmt::print("{}\nwrote {} files to {}\n", r.summary, r.files, *out);
  });
}

}  // namespace palpa::cli
