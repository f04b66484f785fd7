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
  const SitAndRelaxFit fit = sit_and_relax(sim, space, ni.body().rest.body_pressure, b.smoothness);
  if (fit.scale < 1.0) {
    spdlog::warn("design: the start '{}': the full Sit & Relax fit would cross the support through itself; made with "
                 "{:.3g} of its moves",
                 b.name, fit.scale);
  }
  scene.start_fit = SitAndRelaxStart{SurfaceMesh{fit.vertices, sim.support().triangles()}, fit.scale, ni.zeta};
  begin_on_start(scene, scene.rest.body, scene.start_fit->support, "Sit & Relax fit to the pressures on " + b.source);
  // Last (b refers into it): fitted once, a second call leaves the scene as it is.
  scene.start_to_fit.reset();
}

}  // namespace palpa::design
