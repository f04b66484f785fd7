// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A surface meshed finely where a contact will be and coarsely elsewhere
// (the skin of a body that rests on a support): the triangles within
// `within` of the contact are remeshed to `edge`, and around them the edges
// grow by at most kGradingGrowth per band of two edges up to the surface's
// own edge length. The remeshing has no sizing field: each level remeshes
// the patch of triangles closer than its band's outer distance, finest last,
// and the patches' borders are split as the finer level meets the coarser.

#include <Eigen/Core>
#include <functional>

#include "palpa/geometry/mesh.hpp"

namespace palpa::mesh {

inline constexpr double kGradingGrowth = 1.5;  // largest ratio of neighbouring levels' edges

struct Grading {
  double edge = 0.0;    // edge length in and near the contact [m], > 0
  double within = 0.0;  // distance to the contact inside which it holds [m], ≥ 0
};

// Distance of each point (#P×3, in the surface's frame) to where the
// contact will be [m].
using ContactDistance = std::function<Eigen::VectorXd(const Eigen::MatrixX3d& points)>;

// The edge of each level, coarsest (far_edge) first, and the distance each
// level's patch reaches [m] (levels[0]: the whole surface, reach infinite).
struct GradingLevels {
  std::vector<double> edge, reach;
};
GradingLevels grading_levels(double far_edge, const Grading& grading);

// `mesh` remeshed already to far_edge, refined toward the contact. A grading
// edge not below far_edge returns `mesh` unchanged. Throws palpa::Error
// (Input) for an edge or distance that is not positive and finite.
SurfaceMesh remesh_graded(const SurfaceMesh& mesh, double far_edge, const Grading& grading,
                          const ContactDistance& distance, int iterations = 5);

}  // namespace palpa::mesh
