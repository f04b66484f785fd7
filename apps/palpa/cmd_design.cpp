// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa design: the support shape whose contact pressures are lowest and most
// even (ergonomic shape optimization).

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <filesystem>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/json.hpp"
#include "palpa/core/termination.hpp"
#include "palpa/design/optimizer.hpp"
#include "palpa/design/output.hpp"
#include "palpa/design/scene.hpp"

namespace palpa::cli {

namespace {

struct DesignArgs {
  std::string scene;
  std::string output;
  bool overwrite = false;
  bool resume = false;
  bool no_baselines = false;
  int iterations = -1;
  int threads = -1;
  std::string method;
};

void run_design_command(const DesignArgs& a) {
  const std::filesystem::path out = a.output;
  const std::filesystem::path checkpoint = out / "checkpoint.json";
  const std::filesystem::path finished = out / "summary.json";
  bool resume = a.resume;
  // --resume where there is nothing to resume starts afresh, so that a
  // workflow can always pass it.
  if (resume && !std::filesystem::exists(checkpoint)) {
    spdlog::info("design: no checkpoint in {}: starting afresh", out.string());
    resume = false;
  }
  if (!resume && !a.overwrite) require_empty_output(out, "design run");
  design::DesignScene scene = design::read_design_scene(a.scene, !a.no_baselines);
  if (a.iterations >= 0) scene.options.max_iterations = a.iterations;
  if (a.threads >= 0) scene.options.threads = a.threads;
  if (a.method == "cg") scene.options.method = design::DesignMethod::ConjugateGradient;
  if (a.method == "lbfgs") scene.options.method = design::DesignMethod::Lbfgs;
  // A finished run is resumed only to go on past the iteration limit it
  // stopped at; otherwise it is left exactly as it is.
  if (resume && std::filesystem::exists(finished)) {
    const Json done = read_json_file(finished, InputUse::RunState);
    const JsonView d(done, finished.string());
    const int iterations = static_cast<int>(d.at("iterations").as_integer());
    const std::string reason = d.at("stop_reason").as_string();
    // (A summary without a termination was written by an older palpa: not resumed.)
    const auto termination = d.find("termination");
    const bool at_limit = termination && parse_termination(termination->as_string(), termination->context()) ==
                                             Termination::IterationLimit;
    if (!at_limit || iterations >= scene.options.max_iterations) {
      spdlog::info("design: the run in {} is finished ({} iterations, stopped by {}); nothing to resume{}", out.string(),
                   iterations, reason,
                   at_limit ? fmt::format(" (raise --iterations above {} to go on)", iterations) : std::string());
      return;
    }
  }
  scene.options.checkpoint = checkpoint;
  scene.options.resume = resume;
  if (!resume) {
    // A fresh run leaves no result of an earlier one that could pass for its own.
    std::error_code ec;
    std::filesystem::remove(checkpoint, ec);
    std::filesystem::remove(finished, ec);
  }
  if (!scene.start.empty()) {
    spdlog::info("design: starting from the baseline '{}' (the scene's own support, {}, is scored beside it)",
                 scene.start, scene.scene_support->source);
  }
  spdlog::info("design: {}: body from {} ({} vertices, {} tetrahedra), support {} ({} vertices), {}", a.scene,
               scene.rest.body_source, scene.rest.body.mesh.V.rows(), scene.rest.body.mesh.T.rows(),
               scene.rest.support_source, scene.rest.support.V.rows(), scene.region);
  design::ShapeOptimizer optimizer(scene.rest.body, scene.rest.support, scene.rest.options, scene.design_vertices,
                                   scene.options);
  spdlog::info("design: initial shape: ζ = {:.6g}, γ = {:.4g}, φ = {:.6g}; {} design variables",
               optimizer.initial().zeta, optimizer.gamma(), optimizer.initial().phi, optimizer.space().size());
  // Only now: bad input leaves nothing behind.
  OutputFolder folder(out, OutputFolder::OnFailure::RemoveIfEmpty, OutputFolder::Lock::Exclusive,
                      resume ? OutputFolder::Start::Resumed : OutputFolder::Start::Fresh);
  design::DesignResult r;
  try {
    r = optimizer.run();
  } catch (const Error& e) {
    if (e.kind() == ErrorKind::Interrupted) {
      // The best shape so far, as a shape to look at or make; no summary (the
      // run is not finished, nothing is checked from scratch).
      if (optimizer.last_accepted().rows() > 0) {
        design::write_support_shape(out, "support_interrupted",
                                    SurfaceMesh{optimizer.last_accepted(), optimizer.simulation().support().triangles()});
        spdlog::warn("design: interrupted; the last finished iteration is in {} and its support in "
                     "support_interrupted.obj (m) and support_interrupted_mm.stl: continue with --resume",
                     checkpoint.string());
      } else {
        spdlog::warn("design: interrupted before the first iteration finished: nothing to keep");
      }
    }
    throw;
  }
  // The outputs count together: a failure part way (a full disk, a shape that
  // no longer solves from scratch) takes back the ones already written.
  const std::size_t written_before = folder.written_count();
  Json s;
  try {
    s = design::write_design_outputs(out, scene, optimizer, r);
  } catch (...) {
    folder.remove_written_since(written_before);
    throw;
  }
  for (const char* f : {"support_interrupted.obj", "support_interrupted_mm.stl"}) {
    std::error_code ec;
    std::filesystem::remove(out / f, ec);  // an interruption's shape is not this run's result
  }
  folder.keep();
  // The headline: both shapes solved from scratch.
  const Json& initial = s["initial"];
  const Json& optimized = s["final"];
  std::string verdict;
  for (const Json& w : s["worse_than_baselines"]) {
    verdict += fmt::format("; WORSE than the baseline '{}' on {}", w["baseline"].get<std::string>(),
                           fmt::join(w["on"].get<std::vector<std::string>>(), " and "));
  }
  if (s.contains("start")) {
    const Json& st = s["start"];
    verdict += fmt::format("; against the scene's own support ζ {:.1f}% lower, ζ_body {:.1f}% lower, body peak {:.3g} → "
                           "{:.3g} kPa",
                           st["zeta_reduction_percent"].get<double>(), st["zeta_body_reduction_percent"].get<double>(),
                           st["scene_support"]["peak_pressure_Pa"]["body"].get<double>() * 1e-3,
                           optimized["peak_pressure_Pa"]["body"].get<double>() * 1e-3);
  }
  spdlog::info("design: from scratch, ζ {:.6g} → {:.6g} ({:.1f}% lower; the optimizer's own view {:.1f}%), ζ_body "
               "{:.1f}% lower, peak pressure {:.3g} → {:.3g} kPa (body), max penetration {:.3g} mm, {} iterations, {} "
               "equilibria, {:.1f} s ({}){}; wrote {}",
               initial["zeta"].get<double>(), optimized["zeta"].get<double>(), s["zeta_reduction_percent"].get<double>(),
               s["optimizer"]["zeta_reduction_percent"].get<double>(), s["zeta_body_reduction_percent"].get<double>(),
               initial["peak_pressure_Pa"]["body"].get<double>() * 1e-3,
               optimized["peak_pressure_Pa"]["body"].get<double>() * 1e-3, optimized["max_penetration_m"].get<double>() * 1e3,
               r.iterations, r.evaluations, r.seconds, r.stop.detail, verdict, out.string());
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
                  "pressure_histogram.svg, body_pressure.svg, support_pressure.svg, summary.json, checkpoint.json)")
      ->required();
  cmd->add_flag("--overwrite", a->overwrite, "Write into a non-empty output folder (starts afresh)");
  cmd->add_flag("--resume", a->resume, "Continue an interrupted run from the output folder's checkpoint.json");
  cmd->add_option("--iterations", a->iterations, "Iteration limit (overrides the scene's design.iterations)")
      ->check(CLI::Range(0, 100000));
  cmd->add_option("--threads", a->threads, "Equilibria solved at once (0: min(step lengths, cores))")
      ->check(CLI::Range(0, 1024));
  cmd->add_flag("--no-baselines", a->no_baselines, "Skip the scene's baselines (a quicker look at the design alone)");
  cmd->add_option("--method", a->method, "Optimizer (overrides the scene's design.method): lbfgs (the default) or cg")
      ->check(CLI::IsMember({"cg", "lbfgs"}));
  declare_paths(*cmd, {"scene"}, {"-o"});
  cmd->callback([a] { run_design_command(*a); });
}

}  // namespace palpa::cli
