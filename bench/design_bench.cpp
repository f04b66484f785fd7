// SPDX-License-Identifier: AGPL-3.0-or-later
// design: every shipped `palpa design` example optimized with both methods —
// nonlinear CG over the ladder of 8 step lengths (evaluated in parallel) and
// L-BFGS — for the same number of iterations. Per example and method:
// iterations, equilibrium solves, Newton iterations, total time, time per
// iteration as a multiple of one equilibrium solved from scratch (the initial
// one, measured in the same run), the adjoint solve (factorization and
// back-solve) against the same, ζ before and after; and what the person
// feels, both shapes solved from scratch: ζ_body and the body's peak before
// and after, with the figures of the thesis's Table 7.1 (γ, vertex counts).
//
//   palpa_bench_design [--iterations N] [--method cg|lbfgs] [scene.json ...]
//   (default: the examples in the source tree but the -full ones, the scenes'
//   iteration limits, both methods)
//   palpa_bench_design --method lbfgs examples/design/chair-full/scene.json
//   (Table 7.1's resolution)
//
// With --whole, each scene is instead run as `palpa design` runs it (its own
// start and method, the baselines, every shape solved from scratch, the
// output folder written to a scratch folder): the wall time of the whole run,
// the figures of its summary and each baseline against the optimum.
//   palpa_bench_design --whole examples/design/chair-full/scene.json

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "bench_util.hpp"
#include "palpa/design/optimizer.hpp"
#include "palpa/design/run.hpp"
#include "palpa/design/scene.hpp"
#include "palpa/design/start.hpp"

int main(int argc, char** argv) {
  using palpa::bench::emit;
  spdlog::set_level(spdlog::level::warn);  // the JSON lines alone on stdout
  std::vector<std::filesystem::path> scenes;
  int iterations = -1;
  bool whole = false;
  std::vector<palpa::design::DesignMethod> methods = {palpa::design::DesignMethod::ConjugateGradient,
                                                      palpa::design::DesignMethod::Lbfgs};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--whole") {
      whole = true;
    } else if (a == "--iterations" && i + 1 < argc) {
      iterations = std::atoi(argv[++i]);
    } else if (a == "--method" && i + 1 < argc) {
      const std::string m = argv[++i];
      if (m != "cg" && m != "lbfgs") {
        spdlog::error("--method: '{}' (expected cg or lbfgs)", m);
        return 2;
      }
      methods = {m == "cg" ? palpa::design::DesignMethod::ConjugateGradient : palpa::design::DesignMethod::Lbfgs};
    } else {
      scenes.emplace_back(a);
    }
  }
  if (scenes.empty()) {
    const std::filesystem::path ex = std::filesystem::path(PALPA_SOURCE_DIR) / "examples" / "design";
    for (const auto& e : std::filesystem::directory_iterator(ex)) {
      // The -full scenes (Table 7.1's resolution, an hour or more with both
      // methods) are run by name.
      const std::string name = e.path().filename().string();
      const bool full = name.size() > 5 && name.compare(name.size() - 5, 5, "-full") == 0;
      if (!full && std::filesystem::exists(e.path() / "scene.json")) scenes.push_back(e.path() / "scene.json");
    }
    std::sort(scenes.begin(), scenes.end());
  }
  if (whole) {
    const std::filesystem::path scratch =
        std::filesystem::temp_directory_path() / ("palpa_bench_design_" + std::to_string(::getpid()));
    for (const auto& file : scenes) {
      palpa::design::DesignRun run;
      run.scene = file;
      run.out = scratch;
      run.overwrite = true;
      if (iterations >= 0) run.iterations = iterations;
      const auto t0 = std::chrono::steady_clock::now();
      const auto summary = palpa::design::run_design(run);
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const palpa::Json& s = *summary;
      palpa::Json baselines = palpa::Json::array();
      for (const auto& b : s["baselines"]) {
        baselines.push_back({{"name", b["name"]},
                             {"zeta_body_over_optimized", b["zeta_body_over_optimized"]},
                             {"body_peak_over_optimized", b["body_peak_over_optimized"]}});
      }
      emit({{"bench", "design_whole_run"},
            {"scene", file.parent_path().filename().string() + "/" + file.filename().string()},
            {"start", s.contains("start") ? s["start"]["baseline"] : palpa::Json("the scene's support")},
            {"seconds", wall},
            {"optimizer_seconds", s["seconds"]},
            {"iterations", s["iterations"]},
            {"equilibrium_solves", s["equilibrium_solves"]},
            {"zeta_body_reduction_percent", s["zeta_body_reduction_percent"]},
            {"body_peak_ratio", s["body_peak_ratio"]},
            {"baselines", baselines},
            {"worse_than_baselines", s["worse_than_baselines"].size()},
            {"stop", s["stop_reason"]}});
      std::filesystem::remove_all(scratch);
    }
    return 0;
  }
  for (const auto& file : scenes) {
    for (const auto method : methods) {
      palpa::design::DesignScene scene = palpa::design::read_design_scene(file, false);
      palpa::design::fit_sit_and_relax_start(scene);
      scene.options.method = method;
      if (iterations >= 0) scene.options.max_iterations = iterations;
      palpa::design::ShapeOptimizer opt(scene.rest.body, scene.rest.support, scene.rest.options,
                                        scene.design_vertices, scene.options);
      const palpa::design::DesignResult r = opt.run();
      double iteration_seconds = 0.0;
      for (const auto& it : r.history) iteration_seconds += it.seconds;
      const double per_iteration = r.history.empty() ? 0.0 : iteration_seconds / static_cast<double>(r.history.size());
      // What the person feels, the optimized shape solved from scratch (the
      // initial one was, when the optimizer was built).
      const auto checked = opt.solve_from_scratch(scene.rest.body, {r.final.support, opt.simulation().support().triangles()});
      const double body_before = r.initial.body().score.body_pressure.maxCoeff();
      const double body_after = checked.ok ? checked.body().score.body_pressure.maxCoeff() : 0.0;
      emit({{"bench", "design"},
            {"scene", file.parent_path().filename().string() + "/" + file.filename().string()},
            {"method", method == palpa::design::DesignMethod::Lbfgs ? "lbfgs" : "cg"},
            {"human_vertices", opt.simulation().model().num_vertices()},
            {"tets", opt.simulation().model().num_elements()},
            {"support_vertices", r.initial.support.rows()},
            {"design_variables", opt.space().size()},
            {"contact_vertices", r.initial.body().score.body_contacts},
            {"iterations", r.iterations},
            {"equilibrium_solves", r.evaluations},
            {"newton_iterations", r.newton_iterations},
            {"seconds", r.seconds},
            {"seconds_per_iteration", per_iteration},
            {"equilibrium_seconds", r.equilibrium_seconds},
            {"iteration_over_equilibrium", per_iteration / r.equilibrium_seconds},
            {"adjoint_seconds", r.initial.adjoint_seconds},
            {"adjoint_over_equilibrium", r.initial.adjoint_seconds / r.equilibrium_seconds},
            {"zeta_initial", r.initial.zeta},
            {"zeta_final", r.final.zeta},
            {"zeta_reduction_percent", 100.0 * (1.0 - r.final.zeta / r.initial.zeta)},
            {"start", scene.start.empty() ? std::string("the scene's support") : scene.start},
            {"gamma", r.gamma},
            {"from_scratch_ok", checked.ok},
            {"zeta_final_from_scratch", checked.zeta},
            {"zeta_body_initial", r.initial.body().score.zeta_body},
            {"zeta_body_final_from_scratch", checked.body().score.zeta_body},
            {"zeta_body_reduction_percent", 100.0 * (1.0 - checked.body().score.zeta_body / r.initial.body().score.zeta_body)},
            {"body_peak_initial_Pa", body_before},
            {"body_peak_final_from_scratch_Pa", body_after},
            {"body_peak_ratio", body_after > 0.0 ? body_before / body_after : 0.0},
            {"stop", r.stop.detail}});
    }
  }
}
