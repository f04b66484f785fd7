// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// palpa's wall around CGAL: the surface operations the mesh module needs, with
// palpa types only. Implemented in cgal_surface.cpp, the one translation unit
// of palpa that includes CGAL.

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "palpa/geometry/mesh.hpp"

namespace palpa::mesh::detail {

// Isotropic remeshing (split long edges, collapse short ones, flip, tangential
// relaxation, project back onto the input) to `edge_length` [m], `iterations`
// rounds. The input must be a closed, consistently oriented 2-manifold.
// With feature_angle_deg > 0, edges whose dihedral angle deviates from flat
// by more than that are kept (split, never collapsed or flipped), so box
// corners stay sharp.
SurfaceMesh cgal_remesh(const SurfaceMesh& mesh, double edge_length, int iterations,
                        double feature_angle_deg = 0.0);

// Isotropic remeshing of the triangles with `selected[f]` != 0 alone (one flag
// per row of mesh.F) to `edge_length` [m]: the patch's border edges are split
// where long (the triangles outside them are split along), never collapsed or
// flipped, so the rest of the surface keeps its triangles.
SurfaceMesh cgal_remesh_patch(const SurfaceMesh& mesh, const std::vector<char>& selected, double edge_length,
                              int iterations);

// Boolean operations on closed, self-intersection-free, outward surfaces by
// corefinement. nullopt when the result would not be a 2-manifold.
enum class CgalBoolean { Union, Difference, Intersection };
std::optional<SurfaceMesh> cgal_boolean(const SurfaceMesh& a, const SurfaceMesh& b,
                                        CgalBoolean op);

// The part of a closed surface inside the axis-aligned box [lo, hi], closed
// again along the cut (clip_volume). nullopt when nothing is left or the cut
// would not be manifold.
std::optional<SurfaceMesh> cgal_clip_to_box(const SurfaceMesh& mesh, const Eigen::Vector3d& lo,
                                             const Eigen::Vector3d& hi);

// Removes self-intersections by deleting the crossing triangles with a small
// neighbourhood and filling the holes smoothly (CGAL's local repair). Returns
// the repaired surface, or nullopt if some intersection could not be removed.
// `pairs` receives the number of intersecting triangle pairs found first.
std::optional<SurfaceMesh> cgal_remove_self_intersections(const SurfaceMesh& mesh,
                                                          Eigen::Index* pairs);

// A pair of intersecting triangles (rows of F) of a surface, if any: triangles
// that share a vertex or an edge only intersect if they overlap beyond it.
std::optional<std::pair<Eigen::Index, Eigen::Index>> cgal_self_intersection(
    const SurfaceMesh& mesh);

// Whether two surfaces intersect (touch or cross) — not whether one holds the
// other.
bool cgal_surfaces_intersect(const SurfaceMesh& a, const SurfaceMesh& b);

// Queries against one closed surface (AABB tree), built once.
class SurfaceQueries {
 public:
  explicit SurfaceQueries(const SurfaceMesh& mesh);
  ~SurfaceQueries();
  SurfaceQueries(const SurfaceQueries&) = delete;
  SurfaceQueries& operator=(const SurfaceQueries&) = delete;

  // Closest point of the surface to p: its face (row of F) and position [m].
  std::pair<Eigen::Index, Eigen::Vector3d> closest(const Eigen::Vector3d& p) const;
  // Distance from p to the surface [m].
  double distance(const Eigen::Vector3d& p) const;
  // Distance along the ray p + t d (t > 0, d unit) to the first surface hit,
  // skipping triangle `skip_face` (the one the ray starts on; −1 for none).
  // nullopt if the ray leaves without a hit.
  std::optional<double> ray_hit(const Eigen::Vector3d& p, const Eigen::Vector3d& d,
                                Eigen::Index skip_face) const;
  // Whether p is strictly inside the closed surface.
  bool inside(const Eigen::Vector3d& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace palpa::mesh::detail
