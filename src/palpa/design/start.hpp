// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A design that starts from a Sit & Relax baseline (`"design": {"start":
// "sit and relax"}`): that support is made from solved equilibria, so it is
// fitted after the scene is read, as the baseline itself is
// (design/baselines.hpp): the body solved from scratch on the baseline's
// negative image gives the frozen pressures, the body solved on the scene's
// own support gives the core's pose, and the scene's design region is fitted
// to the body's skin with them. The design then starts on the fitted support,
// with the same design vertices (the fit moves them, the mesh stays), so the
// region reaches as deep as the fit went.

#include "palpa/design/scene.hpp"

namespace palpa::design {

// With scene.start_to_fit: fits it, makes the fit the scene's support (the
// scene's own kept in scene_support, the body lifted clear where it starts
// inside the fit), fills scene.start_fit and clears start_to_fit.
// Otherwise does nothing. Throws
// palpa::Error (Solver) naming the start when an equilibrium or the fit
// fails.
void fit_sit_and_relax_start(DesignScene& scene);

}  // namespace palpa::design
