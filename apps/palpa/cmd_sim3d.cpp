// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa sim3d: a tet body pressed by rigid obstacles (static equilibria along
// indentation paths, or settled implicit dynamics), with penalty contact.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/json.hpp"
#include "palpa/sim3d/run.hpp"

namespace palpa::cli {

namespace {

struct Sim3dArgs {
  std::string scene;
  std::string output;
  bool resume = false;
  bool overwrite = false;
};

void run_sim3d_command(const Sim3dArgs& a) {
  const std::filesystem::path out = a.output;
  bool resume = a.resume;
  // --resume where there is nothing to resume starts afresh, so that a
  // workflow can always pass it.
  if (resume && !std::filesystem::exists(out / "state.json")) {
    // A finished run is left exactly as it is.
    if (std::filesystem::exists(out / "summary.json")) {
      const Json done = read_json_file(out / "summary.json", InputUse::RunState);
      if (done.value("complete", false)) {
        spdlog::info("sim3d: the run in {} is finished ({} steps); nothing to resume", out.string(),
                     done.value("steps_done", 0));
        return;
      }
    }
    if (!a.overwrite) require_empty_output(out);  // (--resume was given: not offered again)
    spdlog::info("sim3d: no interrupted run in {}: starting afresh", out.string());
    resume = false;
  }
  if (!resume && !a.overwrite) require_empty_output(out, "simulation");
  const sim3d::Scene scene = sim3d::read_scene(a.scene);
  spdlog::info("sim3d: {}: {} vertices, {} tetrahedra, {} material(s), {} obstacle(s), {} step(s){}", a.scene,
               scene.mesh.V.rows(), scene.mesh.T.rows(), scene.materials.size(), scene.obstacles.size(), scene.steps,
               scene.local.enabled ? fmt::format(", local within {:.3g} mm", scene.local.margin * 1e3) : "");
  sim3d::RunOptions o;
  o.out = out;
  o.resume = resume;
  try {
    const Json s = sim3d::run(scene, o);
    const Json& last = s.at("records").back();
    std::string forces;
    for (const Json& ob : last.at("obstacles")) {
      forces += fmt::format("; {}: {:.4g} N, max penetration {:.3g} mm", ob.at("name").get<std::string>(),
                            ob.at("indentation_force_N").get<double>(),
                            ob.at("max_penetration_m").get<double>() * 1e3);
    }
    spdlog::info("sim3d: {} steps, {} Newton iterations, {:.1f} s ({:.1f} s collision detection){}; wrote {}",
                 s.at("steps_done").get<int>(), s.at("newton_iterations").get<int>(),
                 s.at("total_seconds").get<double>(), s.at("detection_seconds").get<double>(), forces, out.string());
  } catch (const Error& e) {
    if (e.kind() == ErrorKind::Interrupted && std::filesystem::exists(out / "state.json")) {
      spdlog::warn("sim3d: interrupted; the steps done are in {}: continue with the same command and --resume",
                   out.string());
    }
    if (e.kind() == ErrorKind::Solver && std::filesystem::exists(out / "summary.json")) {
      spdlog::warn("sim3d: the steps that converged are in {} (summary.json: \"complete\": false, "
                   "\"failed_step\")", out.string());
    }
    throw;
  }
}

}  // namespace

void add_sim3d_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "sim3d",
      "Simulate a tet body pressed by rigid obstacles (3D FEM, penalty contact): force-indentation curves, "
      "deformed meshes with stress and contact pressure.\n"
      "  palpa sim3d examples/sim3d/punch/scene.json -o punch\n"
      "  palpa sim3d examples/sim3d/punch/scene.json -o punch --resume    (continue an interrupted run)");
  auto a = std::make_shared<Sim3dArgs>();
  cmd->add_option("scene", a->scene, "Scene file (JSON, see the README)")->required();
  cmd->add_option("-o,--output", a->output,
                  "Output folder (force_<obstacle>.csv, body.pvd and frames, summary.json)")
      ->required();
  cmd->add_flag("--resume", a->resume, "Continue an interrupted run in the output folder");
  cmd->add_flag("--overwrite", a->overwrite, "Write into a non-empty output folder");
  declare_paths(*cmd, {"scene"}, {"-o"});
  cmd->callback([a] { run_sim3d_command(*a); });
}

}  // namespace palpa::cli
