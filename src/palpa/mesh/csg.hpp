// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Solid modelling on closed surfaces: boolean operations by corefinement,
// clipping a body to a region of interest, repairing self-intersections of a
// posed scan, Taubin smoothing, and the negative-image support of §7.5.1 (a
// block with the body pressed into it subtracted, its cut smoothed).
//
// Every input must be a closed, outward, self-intersection-free surface
// (check_closed_surface); every output is one too, or the call throws
// palpa::Error (Input) naming `source` and what went wrong.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "palpa/geometry/mesh.hpp"

namespace palpa::mesh {

enum class BooleanOp { Union, Difference, Intersection };

// a ∪ b, a − b or a ∩ b. Throws when the result is empty or not a 2-manifold
// (e.g. the two surfaces touch along an edge).
SurfaceMesh boolean(const SurfaceMesh& a, const SurfaceMesh& b, BooleanOp op,
                    const std::string& source);

// The part of a closed surface inside `keep`, closed with flat caps along the
// cut (a region of interest: the buttocks and thighs of a seated body).
SurfaceMesh clip_to_box(const SurfaceMesh& mesh, const Eigen::AlignedBox3d& keep,
                        const std::string& source);

// A closed surface without self-intersections: the crossing triangles (skin
// folds of a posed scan: behind the knee, in the groin) are removed with a
// small neighbourhood and the holes filled smoothly. `pairs_found` receives the
// number of crossing triangle pairs (0: the mesh is returned unchanged).
// Throws when an intersection cannot be removed.
SurfaceMesh remove_self_intersections(const SurfaceMesh& mesh, const std::string& source,
                                      Eigen::Index* pairs_found = nullptr);

// Taubin's smoothing (λ = 0.5, μ = −0.53 per round: smooths without
// shrinking), each vertex moved towards the mean of its neighbours
// (geometry::vertex_neighbours). With `movable` (one flag per vertex), only
// flagged vertices move.
void taubin_smooth(SurfaceMesh& mesh, int rounds, const std::vector<bool>* movable = nullptr);

struct NegativeImageOptions {
  Eigen::Vector3d down{0.0, 0.0, -1.0};  // unit direction the body is pressed in
  double press = 0.05;                   // depth of the body's lowest point below the block's top [m]
  double edge_length = 0.01;             // remeshing of the result [m]
  int smoothing_rounds = 10;             // Taubin rounds near the cut
  double smoothing_band = 0.02;          // vertices within this distance of the cut move [m]
  double clearance = 0.002;              // gap left between the hollow and the pressed body [m]
};

struct NegativeImage {
  SurfaceMesh support;          // the block with the hollow
  Eigen::Vector3d body_shift;   // translation that pressed the body in [m]
};

// The block minus the body pressed `press` into it along `down` and grown by
// `clearance` (the level set of the distance to it), remeshed to
// `edge_length` with the block's sharp edges kept, then Taubin-smoothed in a
// band around the cut so the rim is not a sharp edge (no vertex moves into
// the grown body). The body, moved by body_shift, starts clear of its hollow
// and falls into it. It may start anywhere: it is moved along `down` to
// first contact with the block (from above its highest point), then `press`
// further. Throws when pressing would cut through the block, when the body
// moved along `down` never meets it, or when the result is not a clean
// closed surface.
NegativeImage negative_image(const SurfaceMesh& block, const SurfaceMesh& body,
                             const NegativeImageOptions& options, const std::string& source);

}  // namespace palpa::mesh
