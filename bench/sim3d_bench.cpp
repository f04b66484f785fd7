// SPDX-License-Identifier: AGPL-3.0-or-later
// sim3d: a cylinder pressed 1 mm into a 60 × 60 × 15 mm block at four mesh
// levels (up to ~100k tets). Per level: Newton iterations, time per Newton
// iteration as a multiple of one CHOLMOD numeric factorization of the same
// Hessian (measured in the same run), and collision detection per iteration.
// The fitted exponent of the step time over the tet count is the last line.
//
//   palpa_bench_sim3d [--max-level N]   (levels 1…N of 10, 20, 30, 40 cells across)

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "bench_util.hpp"
#include "palpa/sim3d/run.hpp"
#include "palpa/solve/sparse_cholesky.hpp"

namespace {

std::string scene_text(int n) {
  return fmt::format(R"({{
  "palpa_scene": 1,
  "body": {{
    "box": {{"size": ["60 mm", "60 mm", "15 mm"], "cells": [{0}, {0}, {1}]}},
    "materials": [{{"material": {{"model": "neo-hookean", "parameters": {{"E": "10 kPa", "nu": 0.3}}}}}}],
    "fixed": [{{"set": "bottom"}}]
  }},
  "obstacles": [{{"name": "punch", "shape": {{"cylinder": {{"radius": "8 mm", "height": "10 mm", "segments": 96}}}},
                 "path": {{"direction": [0, 0, -1], "depth": "1 mm"}}}}],
  "steps": 2,
  "contact": {{"max_penetration": "0.01 mm"}}
}})",
                     n, std::max(2, n / 4));
}

}  // namespace

int main(int argc, char** argv) {
  using palpa::bench::emit;
  using palpa::bench::seconds_since;
  int max_level = 4;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--max-level") == 0) max_level = std::atoi(argv[i + 1]);
  }
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "palpa_bench_sim3d";
  std::filesystem::create_directories(dir);
  std::vector<double> log_tets, log_time;
  for (int level = 1; level <= max_level; ++level) {
    const int n = 10 * level;
    const auto file = dir / fmt::format("scene{}.json", level);
    std::ofstream(file) << scene_text(n);
    const palpa::sim3d::Scene scene = palpa::sim3d::read_scene(file);
    palpa::sim3d::Simulation sim(scene);
    int iterations = 0, solves = 0;
    double step_seconds = 0.0, detection = 0.0, force = 0.0;
    for (int s = 1; s <= scene.steps; ++s) {
      const palpa::sim3d::StepRecord r = sim.solve_step(s);
      iterations += r.newton_iterations;
      solves += r.solves;
      step_seconds += r.seconds;
      detection += r.detection_seconds;
      force = r.obstacles[0].indentation_force;
    }
    // One numeric factorization of the Hessian at the equilibrium.
    Eigen::SparseMatrix<double> H;
    sim.system().hessian(sim.state(), H);
    palpa::SparseCholesky chol;
    chol.analyze(H);
    const double factor = palpa::bench::median_seconds([] {}, [&] { chol.factorize(H); });
    const double per_iteration = step_seconds / std::max(1, iterations);
    emit({{"bench", "sim3d_indentation"},
          {"level", level},
          {"tets", scene.mesh.T.rows()},
          {"dofs", sim.system().num_dofs()},
          {"steps", scene.steps},
          {"solves", solves},
          {"newton_iterations", iterations},
          {"seconds", step_seconds},
          {"seconds_per_iteration", per_iteration},
          {"factorization_seconds", factor},
          {"iteration_over_factorization", per_iteration / factor},
          {"detection_seconds_per_iteration", detection / std::max(1, iterations)},
          {"detection_share", detection / step_seconds},
          {"force_N", force}});
    log_tets.push_back(std::log(static_cast<double>(scene.mesh.T.rows())));
    log_time.push_back(std::log(per_iteration));
  }
  if (log_tets.size() >= 2) {
    const double nx = static_cast<double>(log_tets.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (std::size_t i = 0; i < log_tets.size(); ++i) {
      sx += log_tets[i];
      sy += log_time[i];
      sxx += log_tets[i] * log_tets[i];
      sxy += log_tets[i] * log_time[i];
    }
    emit({{"bench", "sim3d_scaling"}, {"iteration_time_exponent", (nx * sxy - sx * sy) / (nx * sxx - sx * sx)}});
  }
  std::filesystem::remove_all(dir);
  return 0;
}
