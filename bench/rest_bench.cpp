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
//   palpa_bench_rest [--elements linear,nodal-pressure:0.1] [scene.json ...]
//
// (default: the examples in the source tree, each with its own element).
// --elements solves every scene once per element (a name, and for
// nodal-pressure an optional stabilization after a colon): their cost at equal
// DOFs, in one run.

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "palpa/rest/rest.hpp"
#include "palpa/rest/scene.hpp"
#include "palpa/solve/sparse_cholesky.hpp"

int main(int argc, char** argv) {
  using palpa::bench::emit;
  using palpa::bench::seconds_since;
  spdlog::set_level(spdlog::level::warn);  // the JSON lines alone on stdout
  std::vector<std::filesystem::path> scenes;
  std::vector<std::optional<palpa::tet::ElementChoice>> elements{std::nullopt};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--elements" && i + 1 < argc) {
      elements.clear();
      std::stringstream list(argv[++i]);
      for (std::string item; std::getline(list, item, ',');) {
        palpa::tet::ElementChoice c;
        const std::size_t colon = item.find(':');
        const std::string name = item.substr(0, colon);
        if (name == "nodal-pressure") {
          c.element = palpa::tet::TetElement::NodalPressure;
        } else if (name != "linear") {
          std::fprintf(stderr, "unknown element '%s'\n", name.c_str());
          return 2;
        }
        if (colon != std::string::npos) c.stabilization = std::stod(item.substr(colon + 1));
        elements.emplace_back(c);
      }
      continue;
    }
    scenes.emplace_back(a);
  }
  if (scenes.empty()) {
    const std::filesystem::path ex = std::filesystem::path(PALPA_SOURCE_DIR) / "examples" / "rest";
    for (const char* s :
         {"chair/scene.json", "chair/flat.json", "foot/scene.json", "foot/negative-image.json",
          "mouse/scene.json", "thigh/scene.json", "negative-image/scene.json"}) {
      scenes.push_back(ex / s);
    }
  }
  for (const auto& file : scenes) {
    for (const auto& element : elements) {
      const auto t0 = std::chrono::steady_clock::now();
      palpa::rest::RestScene scene = palpa::rest::read_rest_scene(file);
      const double build = seconds_since(t0);
      if (element) scene.body.element = *element;
      const palpa::tet::ElementChoice used = scene.body.element;
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
            {"element",
             used.element == palpa::tet::TetElement::Linear ? "linear" : "nodal-pressure"},
            {"stabilization", used.stabilization},
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
            {"detection_seconds_per_iteration",
             r.detection_seconds / std::max(1, r.newton_iterations)},
            {"detection_share", r.detection_seconds / r.seconds},
            {"balance_error", r.balance_error},
            {"max_penetration_m", r.max_penetration},
            {"peak_pressure_Pa", r.body_pressure.maxCoeff()},
            {"peak_pressure_index_Pa", r.body_metrics.peak_pressure_index}});
    }
  }
}
