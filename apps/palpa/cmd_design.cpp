// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa design: the support shape whose contact pressures are lowest and most
// even (ergonomic shape optimization).

#include <fmt/format.h>
#include <spdlog/spdlog.h>


#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/design/run.hpp"

namespace palpa::cli {

namespace {

struct DesignArgs {
  std::string scene;
  std::string output;
  bool overwrite = false;
  bool resume = false;
  bool no_baselines = false;
  int iterations = -1;
  std::string method;
  std::string start;
};

void run_design_command(const DesignArgs& a) {
  design::DesignRun run;
  run.scene = a.scene;
  run.out = a.output;
  run.resume = a.resume;
  run.overwrite = a.overwrite;
  run.baselines = !a.no_baselines;
  if (a.iterations >= 0) run.iterations = a.iterations;
  if (a.method == "cg") run.method = design::DesignMethod::ConjugateGradient;
  if (a.method == "lbfgs") run.method = design::DesignMethod::Lbfgs;
  if (!a.start.empty()) run.start = a.start;
  if (const auto summary = design::run_design(run)) {
    spdlog::info("{}; wrote {}", design::design_headline(*summary), a.output);
  }
}

}  // namespace

void add_design_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "design",
      "Optimize the shape of a support so that the contact pressures of a body resting on it are low and even "
      "(ergonomic score, adjoint gradients; L-BFGS by default, or nonlinear CG).\n"
      "  palpa design examples/design/thigh/scene.json -o thigh-design\n"
      "  palpa design examples/design/thigh/scene.json -o thigh-design --resume");
  auto a = std::make_shared<DesignArgs>();
  cmd->add_option("scene", a->scene, "Design scene (JSON: a rest scene under \"palpa_design\" with a \"design\" block)")
      ->required();
  cmd->add_option("-o,--output", a->output,
                  "Output folder (support.obj, support_mm.stl, support/body/skin before and after, score.svg, "
                  "pressure_histogram.svg, body_pressure.svg, support_pressure.svg, report.html, summary.json, "
                  "checkpoint.json)")
      ->required();
  cmd->add_flag("--overwrite", a->overwrite, "Write into a non-empty output folder (starts afresh)");
  cmd->add_flag("--resume", a->resume, "Continue an interrupted run from the output folder's checkpoint.json");
  cmd->add_option("--iterations", a->iterations, "Iteration limit (overrides the scene's design.iterations)")
      ->check(CLI::Range(0, 100000));
  cmd->add_flag("--no-baselines", a->no_baselines, "Skip the scene's baselines (a quicker look at the design alone)");
  cmd->add_option("--method", a->method, "Optimizer (overrides the scene's design.method): lbfgs (the default) or cg")
      ->check(CLI::IsMember({"cg", "lbfgs"}));
  cmd->add_option("--start", a->start,
                  "Where the design begins (overrides the scene's design.start): a baseline's name, or 'scene' for "
                  "the scene's own support");
  declare_paths(*cmd, {"scene"}, {"-o"});
  cmd->callback([a] { run_design_command(*a); });
}

}  // namespace palpa::cli
