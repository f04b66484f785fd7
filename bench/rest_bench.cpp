// SPDX-License-Identifier: AGPL-3.0-or-later
// rest: every shipped `palpa rest` example (the seated body on a bevelled and
// a flat block chair, the foot on a flat sole and on its negative image, the
// hand on a two-sphere mouse, the generated thigh on a block and on its
// negative image) solved to equilibrium. Per scenario: human vertices,
// contact vertices, Newton iterations, time per Newton iteration as a
// multiple of one CHOLMOD numeric factorization of the same Hessian (measured
// in the same run), collision detection per iteration, and the time to build
// the scene (meshing, CSG).
//
//   palpa_bench_rest [scene.json ...]   (default: the examples in the source tree)

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "bench_util.hpp"
#include "palpa/rest/rest.hpp"
#include "palpa/rest/scene.hpp"
#include "palpa/solve/sparse_cholesky.hpp"

int main(int argc, char** argv) {
  using palpa::bench::emit;
  using palpa::bench::seconds_since;
  spdlog::set_level(spdlog::level::warn);  // the JSON lines alone on stdout
  std::vector<std::filesystem::path> scenes;
  for (int i = 1; i < argc; ++i) scenes.emplace_back(argv[i]);
  if (scenes.empty()) {
    const std::filesystem::path ex = std::filesystem::path(PALPA_SOURCE_DIR) / "examples" / "rest";
    for (const char* s : {"chair/scene.json", "chair/flat.json", "foot/scene.json", "foot/negative-image.json",
                          "mouse/scene.json", "thigh/scene.json", "negative-image/scene.json"}) {
      scenes.push_back(ex / s);
    }
  }
  for (const auto& file : scenes) {
    const auto t0 = std::chrono::steady_clock::now();
    palpa::rest::RestScene scene = palpa::rest::read_rest_scene(file);
    const double build = seconds_since(t0);
    palpa::rest::RestSimulation sim(scene.body, scene.support, scene.options);
    const palpa::rest::RestResult r = sim.solve();
    Eigen::SparseMatrix<double> H;
    sim.system().hessian(sim.dofs(), H);
    palpa::SparseCholesky chol;
    chol.analyze(H);
    const double factor = palpa::bench::median_seconds([] {}, [&] { chol.factorize(H); });
    const double per_iteration = r.seconds / std::max(1, r.newton_iterations);
    emit({{"bench", "rest_equilibrium"},
          {"scene", file.parent_path().filename().string() + "/" + file.filename().string()},
          {"human_vertices", sim.model().num_vertices()},
          {"tets", sim.model().num_elements()},
          {"skin_vertices", sim.surface_vertices().size()},
          {"support_vertices", sim.support().vertices().rows()},
          {"contact_vertices", r.contacts},
          {"dofs", sim.system().num_dofs()},
          {"scene_build_seconds", build},
          {"solves", r.solves},
          {"newton_iterations", r.newton_iterations},
          {"seconds", r.seconds},
          {"seconds_per_iteration", per_iteration},
          {"factorization_seconds", factor},
          {"iteration_over_factorization", per_iteration / factor},
          {"detection_seconds_per_iteration", r.detection_seconds / std::max(1, r.newton_iterations)},
          {"detection_share", r.detection_seconds / r.seconds},
          {"balance_error", r.balance_error},
          {"max_penetration_m", r.max_penetration},
          {"peak_pressure_Pa", r.body_pressure.maxCoeff()}});
  }
}
