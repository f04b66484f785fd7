// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa rest: a body on its rigid core resting on a support; contact pressures
// on both.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/rest/output.hpp"
#include "palpa/rest/rest.hpp"
#include "palpa/rest/scene.hpp"

namespace palpa::cli {

namespace {

struct RestArgs {
  std::string scene;
  std::string output;
  bool overwrite = false;
};

void run_rest_command(const RestArgs& a) {
  const std::filesystem::path out = a.output;
  const rest::RestRun run = rest::run_rest(rest::read_rest_scene(a.scene), out, a.overwrite);
  const rest::RestResult& r = run.result;
  spdlog::info("rest: contact force {:.4g} N against a load of {:.4g} N (balance {:.2g}%), peak pressure {:.3g} kPa "
               "(body) / {:.3g} kPa (support), max penetration {:.3g} mm, core moved ({:.3g}, {:.3g}, {:.3g}) mm; "
               "{} Newton iterations in {} solve(s), {:.1f} s; wrote {}",
               r.contact_force.norm(), r.load.norm(), 100.0 * r.balance_error, r.body_pressure.maxCoeff() * 1e-3,
               r.support_pressure.maxCoeff() * 1e-3, r.max_penetration * 1e3, r.core_translation.x() * 1e3,
               r.core_translation.y() * 1e3, r.core_translation.z() * 1e3, r.newton_iterations, r.solves, r.seconds,
               out.string());
  if (!r.message.empty()) spdlog::warn("rest: {}", r.message);
}

}  // namespace

void add_rest_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "rest",
      "Rest a body (a soft layer on a rigid core) on a support under gravity and an external load; contact "
      "pressures on the body and the support.\n"
      "  palpa rest examples/rest/foot/scene.json -o foot\n"
      "  palpa rest examples/rest/thigh/scene.json -o thigh");
  auto a = std::make_shared<RestArgs>();
  cmd->add_option("scene", a->scene, "Scene file (JSON, see the README)")->required();
  cmd->add_option("-o,--output", a->output,
                  "Output folder (body.vtu, skin.ply, support.vtu/.ply, pressure_histogram.svg, body_pressure.svg, "
                  "support_pressure.svg, summary.json)")
      ->required();
  cmd->add_flag("--overwrite", a->overwrite, "Write into a non-empty output folder");
  declare_paths(*cmd, {"scene"}, {"-o"});
  cmd->callback([a] { run_rest_command(*a); });
}

}  // namespace palpa::cli
