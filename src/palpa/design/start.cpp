// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/design/start.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "palpa/core/error.hpp"
#include "palpa/design/baselines.hpp"
#include "palpa/design/optimizer.hpp"

namespace palpa::design {

void fit_sit_and_relax_start(DesignScene& scene) {
  if (!scene.start_to_fit) return;
  const Baseline& b = *scene.start_to_fit;
  rest::RestOptions options = scene.rest.options;
  options.log_solves = false;
  spdlog::info("design: fitting the start '{}': the body on {}, then on the scene's support", b.name, b.source);
  const Evaluation ni = solve_from_scratch(b.body, b.support, options, scene.options.score);
  if (!ni.ok) {
    throw Error(ErrorKind::Solver, fmt::format("the start '{}': the body on its negative image: {}", b.name, ni.failure));
  }
  rest::RestSimulation sim(scene.rest.body, scene.rest.support, options);
  try {
    (void)sim.solve();
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Solver) throw;
    throw Error(ErrorKind::Solver, fmt::format("the start '{}': the body on the scene's support: {}", b.name, e.what()));
  }
  const DesignSpace space(sim.support_rest_vertices(), sim.support().triangles(), scene.design_vertices, true);
  const SitAndRelaxFit fit = sit_and_relax(sim, space, ni.rest.body_pressure, b.smoothness);
  if (fit.scale < 1.0) {
    spdlog::warn("design: the start '{}': the full Sit & Relax fit would cross the support through itself; made with "
                 "{:.3g} of its moves",
                 b.name, fit.scale);
  }
  const std::string source = "Sit & Relax fit to the pressures on " + b.source;
  scene.start_fit = SitAndRelaxStart{SurfaceMesh{fit.vertices, sim.support().triangles()}, fit.scale, ni.zeta};
  scene.rest.support = scene.start_fit->support;
  scene.rest.support_source = source;
  // "scene.json: support" → "scene.json: the baseline '…' the design starts from".
  const std::string& was = scene.rest.options.support_name;
  const std::size_t colon = was.rfind(": ");
  scene.rest.options.support_name = fmt::format("{}the baseline '{}' the design starts from",
                                                colon == std::string::npos ? std::string() : was.substr(0, colon + 2),
                                                b.name);
  scene.start_lift = rest::place_clear_of(scene.rest.body, scene.rest.support, -scene.rest.options.gravity, 1e-3);
  if (scene.start_lift > 0.0) {
    spdlog::info("design: the body starts inside the baseline '{}': lifted {:.3g} mm before it is lowered onto it",
                 b.name, scene.start_lift * 1e3);
  }
  // Last (b refers into it): fitted once, a second call leaves the scene as it is.
  scene.start_to_fit.reset();
}

}  // namespace palpa::design
