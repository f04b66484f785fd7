// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The simulation mesh of a body (thesis §3.3, §7.3.1): a tetrahedral soft
// layer between the outer (skin) surface and an inner surface, whose inner
// vertices attach to a rigid core.
//
// Pipeline of make_layer():
//  1. repair the scan (repair_surface) and check it is closed, manifold,
//     outward and free of self-intersections (check_closed_surface);
//  2. remesh it isotropically to the target edge length (finer toward a
//     contact with a grading);
//  3. depth per outer vertex: uniform, or depth samples interpolated over the
//     surface (geometry::SurfaceInterpolator, linearly precise biharmonic by
//     default, clamped to the samples' range);
//  4. check the depth against the local thickness (the distance along the
//     inward normal to the opposite side of the body): depth + two edge
//     lengths (the thinnest core that can be meshed) must fit, else an input
//     error naming the place;
//  5. push every vertex inward along its angle-weighted normal by its depth,
//     smooth the result lightly (Taubin, which does not shrink), remesh it, and
//     verify that it does not intersect itself or the outer surface (an input
//     error naming the place otherwise);
//  6. tetrahedralize the layer between the two surfaces with TetGen (a hole
//     point inside each core component), drop any tet whose centroid is
//     inside the core (a robust inside test), and mark the vertices on the
//     core surface as attached;
//  7. optionally interpolate stiffness samples over the outer surface; every
//     tet vertex takes the value at its closest outer-surface point and every
//     tet the mean of its four corners (constant through the depth, as the
//     measurements are made from the skin).

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "palpa/geometry/mesh.hpp"
#include "palpa/geometry/surface_interpolation.hpp"
#include "palpa/mesh/graded_remesh.hpp"
#include "palpa/mesh/samples.hpp"
#include "palpa/mesh/tetrahedralize.hpp"

namespace palpa::mesh {

// Layer depth: uniform, or measured at samples.
struct DepthSpec {
  double uniform = 0.0;            // [m], used when samples is empty; > 0
  std::optional<Samples> samples;  // depths [m] at points near the outer surface
};

// How the inner (core) surface is made from the depth field.
enum class CoreOffset {
  // Each skin vertex pushed inward along its normal by its depth, smoothed
  // and remeshed: follows the skin's mesh, but refuses a depth that does not
  // fit the local thickness (or thins it, clamp_depth) or the curvature.
  Normals,
  // The level set at the depth (taken at the closest skin point) of the
  // distance to the skin, meshed anew: every core point is at least its depth
  // from the skin, and where the body is thinner than twice the depth (toes,
  // fingers, the rim of a clipped body, a skin fold) there is no core and the
  // layer fills the body.
  Distance,
};
CoreOffset parse_core_offset(std::string_view name);  // "normals" | "distance"

struct LayerOptions {
  // Target edge length of the outer and inner surfaces [m]; 0 keeps the scan's
  // triangles (it must then be closed and clean already).
  double edge_length = 5e-3;
  int remesh_iterations = 5;
  // Finer skin where the contact will be (graded_remesh.hpp): with a grading,
  // the skin is refined toward the points `contact_distance` puts near; the
  // core surface and the tets keep edge_length (TetGen grades the layer
  // between a fine skin and its core).
  std::optional<Grading> grading;
  ContactDistance contact_distance;
  // Interpolation of depth and stiffness samples.
  geometry::SurfaceInterpolation interpolation = geometry::SurfaceInterpolation::Biharmonic;
  // Largest accepted distance from a sample to the outer surface [m].
  double max_sample_distance = 5e-3;
  // Where the depth does not fit the local thickness (folds, thin parts, the
  // rim of a clipped body): thin the layer there (true) or refuse (false).
  bool clamp_depth = false;
  CoreOffset core_offset = CoreOffset::Normals;
  // Taubin smoothing rounds of the pushed inner surface.
  int smoothing_rounds = 3;
  // Tet quality; max_volume 0 means a regular tet of edge_length.
  TetQuality quality;
  // Names the scan in messages.
  std::string source;
  // Called before each stage with its name ("repair", "remesh", "depth",
  // "inner_surface", "tetrahedralize", "core", "stiffness"): for progress,
  // timing and interruption (it may throw, e.g. on Ctrl-C).
  std::function<void(std::string_view stage)> on_stage;
};

// Boundary markers of LayerMesh::tets.boundary.
inline constexpr int kOuterMarker = 1;
inline constexpr int kCoreMarker = 2;

struct LayerMesh {
  SurfaceMesh outer;               // repaired and remeshed skin surface [m]
  SurfaceMesh core;                // inner surface, outward normals [m]
  Eigen::VectorXd depth;           // #outer.V requested depth per outer vertex [m]
  TetMesh tets;                    // region 1; boundary markers kOuterMarker / kCoreMarker
  std::vector<Eigen::Index> attached;  // rows of tets.V on the core surface, ascending
  Eigen::VectorXd youngs_modulus;  // #T [Pa], empty without stiffness samples
  Eigen::Index dropped_in_core = 0;  // tets removed because their centroid was in the core
  Eigen::Index depth_clamped = 0;    // outer vertices whose depth was thinned to fit (clamp_depth)
  TetQuality quality;                // the bounds TetGen was given (max_volume filled in)
};

// Builds the layer mesh from a scanned surface. Throws palpa::Error (Input)
// naming options.source (or the samples' file) for: an open, non-manifold or
// self-intersecting scan, samples off the surface, a depth not positive or
// larger than the local thickness, an inner surface that would intersect itself.
LayerMesh make_layer(const SurfaceMesh& scan, const DepthSpec& depth,
                     const std::optional<Samples>& stiffness, const LayerOptions& options);

// Figures about a layer mesh.
struct LayerSummary {
  TetStatistics quality;
  double outer_volume = 0.0;   // enclosed by the outer surface [m³]
  double core_volume = 0.0;    // enclosed by the core surface [m³]
  double layer_volume = 0.0;   // Σ tet volumes [m³]
  // Distance from each outer vertex to the core surface [m].
  double thickness_min = 0.0, thickness_mean = 0.0, thickness_max = 0.0;
  // The requested depths [m].
  double depth_min = 0.0, depth_mean = 0.0, depth_max = 0.0;
  // Stiffness range [Pa] (0 without samples).
  double youngs_min = 0.0, youngs_max = 0.0;
  Eigen::Index outer_triangles = 0, core_triangles = 0, attached = 0, dropped_in_core = 0;
};
LayerSummary summarize_layer(const LayerMesh& layer, const TetQuality& bounds);

// Distance from every vertex of `points` (#P×3) to the closed surface [m].
Eigen::VectorXd distance_to_surface(const SurfaceMesh& surface, const Eigen::MatrixX3d& points);

}  // namespace palpa::mesh
