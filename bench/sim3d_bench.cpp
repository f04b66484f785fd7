// SPDX-License-Identifier: AGPL-3.0-or-later
// sim3d: a cylinder pressed 1 mm into a 60 × 60 × 15 mm block at four mesh
// levels (up to ~100k tets). Per level: Newton iterations, time per Newton
// iteration as a multiple of one CHOLMOD numeric factorization of the same
// Hessian (measured in the same run), and collision detection per iteration.
// The fitted exponent of the step time over the tet count follows.
//
// Then the flat punch against the axisymmetric solver: a 4 mm punch 0.5 mm
// into a 10 mm layer (E 10 kPa, ν 0.3), frictionless and stick, the layer a
// quarter cylinder on `palpa poke`'s grid at mesh levels 0…M (surface
// contact); per level the 3D force, the axisymmetric one at level 4, the
// error, Newton iterations and seconds.
//
//   palpa_bench_sim3d [--max-level N] [--punch-levels M]
//     (levels 1…N of 10, 20, 30, 40 cells across; M = 3 punch levels, 0 for none)

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "bench_util.hpp"
#include "palpa/axisym/poke.hpp"
#include "palpa/material/models.hpp"
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

std::string punch_scene(int level, bool stick) {
  return fmt::format(R"({{
  "palpa_scene": 1,
  "body": {{
    "cylinder": {{"radius": "22.57 mm", "height": "10 mm", "rim": "4 mm", "level": {0}, "segments": 48,
                  "sector": "90 deg"}},
    "materials": [{{"material": {{"model": "neo-hookean", "parameters": {{"E": "10 kPa", "nu": 0.3}}}}}}],
    "fixed": [{{"set": "bottom"}}, {{"set": "sector_start", "components": "y"}},
              {{"set": "sector_end", "components": "x"}}]
  }},
  "obstacles": [{{"name": "punch", "shape": {{"cylinder": {{"radius": "4 mm", "height": "10 mm", "segments": 48}}}},
                 "path": {{"direction": [0, 0, -1], "depth": "0.5 mm"}}}}],
  "steps": 2,
  "contact": {{"max_penetration": "0.002 mm", "sampling": "surface", "friction": "{1}"}}
}})",
                     level, stick ? "stick" : "frictionless");
}

void punch_rows(const std::filesystem::path& dir, int levels) {
  const palpa::material::NeoHookean nh(10e3, 0.3);
  for (const bool stick : {false, true}) {
    palpa::axisym::PokeSetup setup;
    setup.geometry = {4e-3, 10e-3, 22.57e-3};
    setup.contact = stick ? palpa::axisym::PunchContact::Stick : palpa::axisym::PunchContact::Frictionless;
    setup.mesh_level = 4;
    palpa::axisym::PokeSimulator poke(nh, setup);
    palpa::axisym::PokeOptions po;
    po.max_depth = 5e-4;
    po.steps = 2;
    const double reference = poke.run(po).samples.back().force;
    for (int level = 0; level < levels; ++level) {
      const auto file = dir / fmt::format("punch{}{}.json", level, stick ? "stick" : "");
      std::ofstream(file) << punch_scene(level, stick);
      const palpa::sim3d::Scene scene = palpa::sim3d::read_scene(file);
      palpa::sim3d::Simulation sim(scene);
      int iterations = 0;
      double seconds = 0.0, force = 0.0;
      for (int s = 1; s <= scene.steps; ++s) {
        const palpa::sim3d::StepRecord r = sim.solve_step(s);
        iterations += r.newton_iterations;
        seconds += r.seconds;
        force = 4.0 * r.obstacles[0].indentation_force;
      }
      palpa::bench::emit({{"bench", "sim3d_punch_against_axisymmetric"},
                          {"contact", stick ? "stick" : "frictionless"},
                          {"level", level},
                          {"tets", scene.mesh.T.rows()},
                          {"force_N", force},
                          {"axisymmetric_force_N", reference},
                          {"error", force / reference - 1.0},
                          {"newton_iterations", iterations},
                          {"seconds", seconds}});
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  using palpa::bench::emit;
  using palpa::bench::seconds_since;
  int max_level = 4, punch_levels = 3;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--max-level") == 0) max_level = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--punch-levels") == 0) punch_levels = std::atoi(argv[i + 1]);
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
  punch_rows(dir, punch_levels);
  std::filesystem::remove_all(dir);
  return 0;
}
