// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/mesh/csg.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "palpa/core/error.hpp"
#include "palpa/core/units.hpp"
#include "palpa/geometry/format.hpp"
#include "palpa/geometry/umbrella.hpp"
#include "palpa/mesh/detail/cgal_offset.hpp"
#include "palpa/mesh/detail/cgal_surface.hpp"
#include "palpa/mesh/surface_check.hpp"

namespace palpa::mesh {
namespace {

constexpr double kTaubinLambda = 0.5;
constexpr double kTaubinMu = -0.53;
// Edges more than this far from flat are the block's features, kept sharp.
constexpr double kFeatureAngleDeg = 60.0;


}  // namespace

SurfaceMesh boolean(const SurfaceMesh& a, const SurfaceMesh& b, BooleanOp op,
                    const std::string& source) {
  check_closed_surface(a, source);
  check_closed_surface(b, source);
  const auto kind = op == BooleanOp::Union        ? detail::CgalBoolean::Union
                    : op == BooleanOp::Difference ? detail::CgalBoolean::Difference
                                                  : detail::CgalBoolean::Intersection;
  const char* name = op == BooleanOp::Union ? "union" : op == BooleanOp::Difference ? "difference" : "intersection";
  auto out = detail::cgal_boolean(a, b, kind);
  if (!out || out->F.rows() == 0) {
    throw_input_error(fmt::format("the {} of the two solids is {}", name,
                                  out ? "empty" : "not a 2-manifold (they touch along an edge or at a point)"),
                      in_file(source), "solids that overlap in a volume or are apart");
  }
  SurfaceMesh r = repair_surface(*out);
  check_closed_surface(r, source);
  return r;
}

SurfaceMesh clip_to_box(const SurfaceMesh& mesh, const Eigen::AlignedBox3d& keep,
                        const std::string& source) {
  // Eigen's isEmpty() accepts min == max; a box without volume leaves a
  // sheet or nothing, which the corefinement cannot close.
  if (!(keep.min().array() < keep.max().array()).all()) {
    throw_input_error(fmt::format("the clipping box {} – {} has no volume",
                                  geometry::format_point(keep.min()), geometry::format_point(keep.max())),
                      in_file(source), "min < max in every coordinate");
  }
  check_closed_surface(mesh, source);
  const Eigen::AlignedBox3d bounds(mesh.V.colwise().minCoeff().transpose(),
                                   mesh.V.colwise().maxCoeff().transpose());
  const Eigen::AlignedBox3d common = keep.intersection(bounds);
  if (!(common.min().array() < common.max().array()).all()) {
    throw_input_error(fmt::format("the clipping box {} – {} does not overlap the body, which spans {} – {}",
                                  geometry::format_point(keep.min()), geometry::format_point(keep.max()),
                                  geometry::format_point(bounds.min()), geometry::format_point(bounds.max())),
                      in_file(source), "a box that keeps part of the body (same unit as the scene)");
  }
  // Only the box near the body matters: faces far out (a bound of "1e300 mm"
  // meaning none) give the corefinement coordinates whose products overflow a
  // double, and it fails or crashes. Faces more than a hundred of the body's
  // diagonals beyond it are pulled in to that distance, which keeps the same
  // part of the body (and leaves every nearer box as it is, to the bit).
  const Eigen::Vector3d far = Eigen::Vector3d::Constant(100.0 * bounds.diagonal().norm());
  const Eigen::Vector3d lo = keep.min().cwiseMax(bounds.min() - far);
  const Eigen::Vector3d hi = keep.max().cwiseMin(bounds.max() + far);
  auto out = detail::cgal_clip_to_box(mesh, lo, hi);
  if (!out) {
    throw_input_error(fmt::format("clipping to the box {} – {} leaves nothing or a non-manifold piece",
                                  geometry::format_point(keep.min()), geometry::format_point(keep.max())),
                      in_file(source), "a box that cuts the body cleanly");
  }
  SurfaceMesh r = repair_surface(*out);
  check_closed_surface(r, source);
  return r;
}

SurfaceMesh remove_self_intersections(const SurfaceMesh& mesh, const std::string& source,
                                      Eigen::Index* pairs_found) {
  Eigen::Index pairs = 0;
  auto out = detail::cgal_remove_self_intersections(mesh, &pairs);
  if (pairs_found != nullptr) *pairs_found = pairs;
  if (!out) {
    throw_input_error(fmt::format("{} pairs of crossing triangles were found and could not all be "
                                  "removed by local repair",
                                  pairs),
                      in_file(source), "a surface whose self-intersections are small skin folds");
  }
  return repair_surface(*out);
}

void taubin_smooth(SurfaceMesh& m, int rounds, const std::vector<bool>* movable) {
  const auto nb = geometry::vertex_neighbours(m.F, m.V.rows());
  for (int r = 0; r < rounds; ++r) {
    for (double factor : {kTaubinLambda, kTaubinMu}) {
      Eigen::MatrixX3d next = m.V;
      for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
        if (nb[i].empty() || (movable != nullptr && !(*movable)[std::size_t(i)])) continue;
        Eigen::RowVector3d mean = Eigen::RowVector3d::Zero();
        for (int j : nb[i]) mean += m.V.row(j);
        mean /= double(nb[i].size());
        next.row(i) += factor * (mean - m.V.row(i));
      }
      m.V = next;
    }
  }
}

NegativeImage negative_image(const SurfaceMesh& block, const SurfaceMesh& body,
                             const NegativeImageOptions& o, const std::string& source) {
  const ErrorContext where = in_file(source);
  const double down_norm = o.down.norm();
  if (!(down_norm > 0.0) || !std::isfinite(down_norm)) {
    throw_input_error("the pressing direction is zero or not finite", where, "a direction such as gravity");
  }
  const Eigen::Vector3d d = o.down / down_norm;
  if (!(o.press > 0.0) || !(o.edge_length > 0.0) || o.smoothing_rounds < 0 || !(o.smoothing_band >= 0.0) ||
      !(o.clearance >= 0.0)) {
    throw_input_error("press depth and edge length must be positive, smoothing band, rounds and clearance not negative",
                      where, "press > 0, edge > 0, band ≥ 0, rounds ≥ 0, clearance ≥ 0");
  }
  // Heights measured against the pressing direction.
  const double block_top = (-block.V * d).maxCoeff();
  const double block_bottom = (-block.V * d).minCoeff();
  const double body_low = (-body.V * d).minCoeff();
  if (o.press >= block_top - block_bottom) {
    throw_input_error(fmt::format("pressing {} into a block {} thick would cut through it",
                                  format_quantity(o.press, Dimension::Length),
                                  format_quantity(block_top - block_bottom, Dimension::Length)),
                      where, "a press depth smaller than the block's height");
  }
  NegativeImage result;
  // Lifted until its lowest point is level with the block's highest (it is
  // then clear of the block), the body is lowered along d to first contact
  // (rays from the body's vertices down to the block and from the block's
  // vertices up to the body), then `press` further. Over a flat top that is
  // the lowest point `press` below it; over spheres (a mouse under a hand)
  // the hollow starts where they first touch.
  const double lift = body_low - block_top - 1e-3 * (block_top - block_bottom);
  SurfaceMesh above = body;
  above.V.rowwise() += (lift * d).transpose();
  double contact = std::numeric_limits<double>::infinity();
  const detail::SurfaceQueries block_queries(block), body_queries(above);
  for (Eigen::Index v = 0; v < above.V.rows(); ++v) {
    if (const auto t = block_queries.ray_hit(above.V.row(v).transpose(), d, -1)) contact = std::min(contact, *t);
  }
  for (Eigen::Index v = 0; v < block.V.rows(); ++v) {
    if (const auto t = body_queries.ray_hit(block.V.row(v).transpose(), -d, -1)) contact = std::min(contact, *t);
  }
  if (!std::isfinite(contact)) {
    throw_input_error("the body, moved along the pressing direction, never meets the block", where,
                      "a body placed over the block");
  }
  result.body_shift = (lift + contact + o.press) * d;
  SurfaceMesh pressed = body;
  pressed.V.rowwise() += result.body_shift.transpose();
  // The hollow is cut by the pressed body grown by the clearance (a distance
  // offset), so the body starts clear of it everywhere.
  SurfaceMesh cutter = pressed;
  if (o.clearance > 0.0) {
    cutter = repair_surface(detail::cgal_dilation(pressed, o.clearance, o.edge_length));
    check_closed_surface(cutter, source + " (the body grown by the clearance)");
  }
  SurfaceMesh cut = boolean(block, cutter, BooleanOp::Difference, source);
  cut = detail::cgal_remesh(cut, o.edge_length, 5, kFeatureAngleDeg);
  // Smooth the vertices near the pressed body (the hollow and its rim).
  if (o.smoothing_rounds > 0) {
    const double band = std::max(o.smoothing_band, o.edge_length);
    const detail::SurfaceQueries near(cutter);
    std::vector<bool> movable(static_cast<std::size_t>(cut.V.rows()));
    for (Eigen::Index i = 0; i < cut.V.rows(); ++i) {
      movable[std::size_t(i)] = near.distance(cut.V.row(i).transpose()) <= band;
    }
    const Eigen::MatrixX3d before = cut.V;
    taubin_smooth(cut, o.smoothing_rounds, &movable);
    // Smoothing rounds the rim away from the body but would also move the
    // hollow's concave parts towards it: those vertices stay where they were.
    for (Eigen::Index i = 0; i < cut.V.rows(); ++i) {
      if (movable[std::size_t(i)] && near.inside(cut.V.row(i).transpose())) cut.V.row(i) = before.row(i);
    }
  }
  // A deep press leaves sharp creases in the hollow (the body's own clipped
  // faces pressed below the top) that the remesh and the smoothing can fold
  // through each other: they are cut out and filled, as a scan's skin folds.
  if (detail::cgal_self_intersection(cut)) cut = remove_self_intersections(cut, source);
  check_closed_surface(cut, source);
  result.support = cut;
  return result;
}

}  // namespace palpa::mesh
