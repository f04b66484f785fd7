// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A closed triangle mesh as a contact obstacle (thesis §7.3.5): the rigid
// indenter or support, or — in the reverse query — the deforming body surface.
//
// Coordinates. The mesh is held in body coordinates; a pose places it in the
// world, x_world = R·x_body + t (R a rotation). Changing the pose is O(1): the
// tree stays in body coordinates and queries are mapped into it. Every query and
// result of this header is in world coordinates [m].
//
// Inside test. A point is inside when it lies strictly inside the closed
// surface: the sign of (p − c)·N, with c the closest surface point and N the
// angle-weighted pseudo-normal of the closest feature (face normal; sum of the
// two face normals for an edge; angle-weighted sum of the incident face normals
// for a vertex). For a closed, consistently oriented manifold that does not
// cross itself (checked on construction, see ObstacleOptions) this sign is exact
// whatever feature is closest (Bærentzen & Aanæs, 2005), so there is no ray to
// shoot through an edge or a vertex and no degenerate case to break; and it
// comes free with the closest-point query that the penalty needs anyway. Points
// on the surface (distance 0) are outside; within rounding of the surface
// either answer may come back, where the penalty energy is ~0 either way.
//
// Closest feature. The closest point is reported as a feature of the mesh: a
// vertex, the interior of an edge (its two vertices) or the interior of a face
// (its three vertices), with barycentric weights (Appendix A's three Voronoi
// cases).

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>

#include "palpa/geometry/mesh.hpp"

namespace palpa::contact {

// x_world = R·x_body + t. R must be a rotation (orthonormal, det +1).
struct Pose {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();  // [m]
};

enum class Feature : std::uint8_t { Vertex, Edge, Face };

// Number of mesh vertices spanning a feature: 1, 2 or 3.
constexpr int feature_size(Feature f) {
  return static_cast<int>(f) + 1;
}

// The closest point of an obstacle to a query point.
struct ClosestPoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // world [m]
  double distance = 0.0;                            // ‖query − point‖ [m]
  bool inside = false;                              // query strictly inside the surface
  Feature feature = Feature::Face;
  int triangle = -1;  // a triangle holding the closest point
  // Obstacle vertex indices (rows of the mesh) spanning the feature: the first
  // feature_size(feature) are used (an edge's two in increasing order; a face's
  // three in its winding), the rest are −1.
  std::array<int, 3> vertices{-1, -1, -1};
  // Barycentric weights of `vertices` (sum 1, unused entries 0):
  // point = Σ weights[i]·vertex(vertices[i]).
  Eigen::Vector3d weights = Eigen::Vector3d::Zero();
};

struct ObstacleOptions {
  // A mesh whose normals point inwards (negative enclosed volume) is flipped
  // (every triangle's winding reversed; flipped() tells) when true, refused
  // (palpa::Error, Input) when false.
  bool flip_inward = true;
  // Refuse a surface that crosses itself (two triangles intersecting other
  // than along a shared edge or at a shared vertex; exact predicates). The
  // inside test is exact only for surfaces that do not: where sheets overlap,
  // the sign is that of the nearest sheet. Costs about as much as the rest of
  // the construction; the check is not redone by set_vertices().
  bool check_self_intersections = true;
};

// Queries are const and safe to run concurrently; set_pose() and
// set_vertices() must not run during queries.
class Obstacle {
 public:
  // mesh: closed, consistently oriented, manifold triangle surface in body
  // coordinates [m]. name: the file or object name used in error messages.
  // Throws palpa::Error (Input) naming `name` for a non-finite coordinate, an
  // index out of range, a degenerate triangle (repeated vertex or area below
  // 1e-12·(bounding-box diagonal)²), a boundary edge (mesh not closed), an edge
  // of more than two triangles, two triangles disagreeing on orientation, a
  // zero enclosed volume, an inward orientation when !options.flip_inward, or
  // intersecting triangles when options.check_self_intersections.
  Obstacle(const SurfaceMesh& mesh, std::string name, const ObstacleOptions& options = {});
  ~Obstacle();
  Obstacle(Obstacle&&) noexcept;
  Obstacle& operator=(Obstacle&&) noexcept;

  const std::string& name() const;
  // Body-coordinate vertices #V×3 [m] and triangles #F×3 (after any flip).
  const Eigen::MatrixX3d& vertices() const;
  const Eigen::MatrixX3i& triangles() const;
  bool flipped() const;
  double volume() const;  // enclosed volume [m³], > 0

  // Pose: O(1). Throws palpa::Error (Input) if R is not a rotation (tolerance
  // 1e-9) or t is not finite.
  void set_pose(const Pose& pose);
  const Pose& pose() const;
  // World position of vertex i [m].
  Eigen::Vector3d world_vertex(int i) const;

  // Moves the vertices (body coordinates, #V×3, same triangles), e.g. a body
  // surface deformed by a Newton step. refit = true keeps the tree's topology
  // and refits its boxes (O(#F), much cheaper than a rebuild; queries slow down
  // only if the motion is large); false rebuilds the tree; both give the same
  // answers. Normals are recomputed either way. Throws palpa::Error (Input)
  // for a wrong shape or a non-finite coordinate; the connectivity checks of
  // the constructor are not redone (triangles may degenerate or intersect
  // while a body deforms; queries stay defined).
  void set_vertices(const Eigen::MatrixX3d& body_vertices, bool refit = true);
  // A copy of this obstacle with its vertices moved (as set_vertices with a
  // refit), this one untouched: a deforming obstacle at a line-search trial,
  // evaluated from several threads at once. O(#F).
  Obstacle deformed(const Eigen::MatrixX3d& body_vertices) const;

  // Closest surface point to x [m, world], its feature, and the inside test.
  ClosestPoint closest_point(const Eigen::Vector3d& x) const;
  // The detection query: true, with `out` filled, when x is strictly inside;
  // otherwise false and `out` untouched (outside the bounding box without any
  // tree search).
  bool penetration(const Eigen::Vector3d& x, ClosestPoint& out) const;
  bool inside(const Eigen::Vector3d& x) const;

 private:
  struct Impl;
  explicit Obstacle(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace palpa::contact
