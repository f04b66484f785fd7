// SPDX-License-Identifier: AGPL-3.0-or-later
// Mesh_3 on an implicit function (see cgal_offset.hpp).
#include "palpa/mesh/detail/cgal_offset.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/facets_in_complex_3_to_triangle_mesh.h>
#include <CGAL/make_mesh_3.h>

#include <algorithm>
#include <vector>

#include "palpa/mesh/detail/cgal_mesh.hpp"
#include "palpa/mesh/detail/cgal_surface.hpp"

namespace palpa::mesh::detail {
namespace {

using Kernel = CgalKernel;
using Point = CgalPoint;
using Domain = CGAL::Labeled_mesh_domain_3<Kernel>;
using Triangulation = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using Complex = CGAL::Mesh_complex_3_in_triangulation_3<Triangulation>;
using Criteria = CGAL::Mesh_criteria_3<Triangulation>;

// Meshes the surface {level = 0} of a function negative inside, within the
// ball (centre, radius), with triangles of about `edge`.
SurfaceMesh mesh_level_set(const std::function<double(const Eigen::Vector3d&)>& level,
                           const Eigen::Vector3d& c, double radius, double edge, double approximation) {
  namespace p = CGAL::parameters;
  const auto f = [&level](const Point& q) { return level(Eigen::Vector3d(q.x(), q.y(), q.z())); };
  const Domain domain = Domain::create_implicit_mesh_domain(
      f, Kernel::Sphere_3(Point(c.x(), c.y(), c.z()), radius * radius), p::relative_error_bound = 1e-6);
  const Criteria criteria(p::facet_angle = 25.0, p::facet_size = edge, p::facet_distance = approximation);
  const Complex complex = CGAL::make_mesh_3<Complex>(domain, criteria, p::no_perturb(), p::no_exude(), p::manifold());
  CgalMesh out;
  CGAL::facets_in_complex_3_to_triangle_mesh(complex, out);
  return from_cgal(out);
}

}  // namespace

SurfaceMesh cgal_distance_offset(const SurfaceMesh& skin,
                                 const std::function<double(Eigen::Index, const Eigen::Vector3d&)>& depth,
                                 double edge) {
  const SurfaceQueries queries(skin);
  // Negative in the offset region: depth at the closest skin point minus the
  // distance to it, for points inside the skin; positive outside.
  const auto level = [&](const Eigen::Vector3d& p) {
    if (!queries.inside(p)) return 1.0;
    const auto [face, closest] = queries.closest(p);
    return depth(face, closest) - (closest - p).norm();
  };
  const Eigen::Vector3d lo = skin.V.colwise().minCoeff().transpose();
  const Eigen::Vector3d hi = skin.V.colwise().maxCoeff().transpose();
  // Mesh_3 searches for the surface at random and would search forever for
  // an empty region: look for one inside point on a grid of half edges first.
  const Eigen::Vector3d size = hi - lo;
  const double h = 0.5 * edge;
  bool found = false;
  for (double x = lo.x() + 0.5 * h; x < hi.x() && !found; x += h) {
    for (double y = lo.y() + 0.5 * h; y < hi.y() && !found; y += h) {
      for (double z = lo.z() + 0.5 * h; z < hi.z() && !found; z += h) found = level(Eigen::Vector3d(x, y, z)) < 0.0;
    }
  }
  if (!found) return SurfaceMesh{};
  return mesh_level_set(level, 0.5 * (lo + hi), 0.5 * size.norm() + edge, edge, 0.1 * edge);
}

SurfaceMesh cgal_dilation(const SurfaceMesh& skin, double distance, double edge) {
  const SurfaceQueries queries(skin);
  const auto level = [&](const Eigen::Vector3d& p) {
    const double d = queries.distance(p);
    return (queries.inside(p) ? -d : d) - distance;
  };
  const Eigen::Vector3d lo = skin.V.colwise().minCoeff().transpose();
  const Eigen::Vector3d hi = skin.V.colwise().maxCoeff().transpose();
  return mesh_level_set(level, 0.5 * (lo + hi), 0.5 * (hi - lo).norm() + 2.0 * distance + edge, edge,
                        std::min(0.1 * edge, 0.2 * distance));
}

}  // namespace palpa::mesh::detail
