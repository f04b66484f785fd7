// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A cohort's baseline as a workshop would make it: the negative image of an
// average body, on the cohort's own support.
//
// Each body, as its scene places it, is pressed into the support along
// gravity until its lowest skin point is `press` below the support's top (the
// thesis's negative image, §7.5.1); its dent at a design vertex is how far its
// skin's lower envelope reaches below the top there (0 where the body does
// not reach). The average body's impression is the mean of the bodies' dents
// at each design vertex, the bodies that miss it counting 0: the hollow the
// cohort would press, on average. The design vertices move down by it, and
// Taubin's smoothing rounds off the hollow's rim. Bodies of any meshes can be
// averaged so (no correspondence between them is needed), and the result is
// the support's own mesh, scored like the optimized one.

#include <Eigen/Core>
#include <vector>

#include "palpa/geometry/mesh.hpp"
#include "palpa/rest/rest.hpp"

namespace palpa::design {

struct AverageImpressionOptions {
  double press = 0.01;      // depth of each body's lowest skin point below the top [m]
  int smoothing_rounds = 5;  // Taubin rounds on the design vertices
};

// The support with the average impression of `bodies` pressed into its design
// vertices. down: gravity's direction (unit or not). Throws palpa::Error
// (Input) for no body, a press ≤ 0 or a body that reaches no design vertex.
SurfaceMesh average_impression(const std::vector<const rest::RestBody*>& bodies, const SurfaceMesh& support,
                               const std::vector<int>& design_vertices, const Eigen::Vector3d& down,
                               const AverageImpressionOptions& options = {});

// A surface's lower envelope over each point: the lowest crossing of the line
// through p along `down` with the triangles, as a height h = −x·d̂ (larger:
// higher); +∞ where the line misses every triangle. Triangles seen edge-on
// count as missing.
std::vector<double> lower_envelope(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                   const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& down);

}  // namespace palpa::design
