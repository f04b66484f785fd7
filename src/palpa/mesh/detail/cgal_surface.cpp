// SPDX-License-Identifier: AGPL-3.0-or-later
// The one translation unit of palpa that includes CGAL (see cgal_surface.hpp).
#include "palpa/mesh/detail/cgal_surface.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/clip.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/detect_features.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_self_intersections.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "palpa/core/error.hpp"
#include "palpa/mesh/detail/cgal_mesh.hpp"

namespace palpa::mesh::detail {
namespace {

using Kernel = CgalKernel;
using Point = CgalPoint;
using Mesh = CgalMesh;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
namespace PMP = CGAL::Polygon_mesh_processing;

// A triangle with an angle above this is a cap (its corners nearly in line).
constexpr double kCapAngleDeg = 175.0;

// Faces get the indices of F's rows (added in order, none removed).
Mesh to_cgal(const SurfaceMesh& mesh) {
  Mesh m;
  std::vector<Mesh::Vertex_index> vertices;
  vertices.reserve(static_cast<std::size_t>(mesh.V.rows()));
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    vertices.push_back(m.add_vertex(Point(mesh.V(i, 0), mesh.V(i, 1), mesh.V(i, 2))));
  }
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const auto face =
        m.add_face(vertices[mesh.F(f, 0)], vertices[mesh.F(f, 1)], vertices[mesh.F(f, 2)]);
    if (face == Mesh::null_face()) {
      throw_input_error("triangle " + std::to_string(f) +
                            " makes the surface non-manifold (a vertex or edge shared by "
                            "separate sheets, or a flipped triangle)",
                        {}, "a closed, consistently oriented 2-manifold surface");
    }
  }
  return m;
}

Eigen::Vector3d to_eigen(const Point& p) { return {p.x(), p.y(), p.z()}; }

}  // namespace

SurfaceMesh cgal_remesh(const SurfaceMesh& mesh, double edge_length, int iterations,
                        double feature_angle_deg) {
  Mesh m = to_cgal(mesh);
  if (feature_angle_deg > 0.0) {
    auto sharp = m.add_property_map<Mesh::Edge_index, bool>("e:palpa_sharp", false).first;
    PMP::detect_sharp_edges(m, feature_angle_deg, sharp);
    PMP::split_long_edges(edges(m), edge_length, m, PMP::parameters::edge_is_constrained_map(sharp));
    PMP::isotropic_remeshing(faces(m), edge_length, m,
                             PMP::parameters::number_of_iterations(iterations)
                                 .number_of_relaxation_steps(3)
                                 .edge_is_constrained_map(sharp)
                                 .protect_constraints(true));
    // Protected sharp edges cannot be collapsed: where two of them meet
    // nearly in line (a body's clip plane pressed through a block's top
    // face), the triangle spanning them can be left without area — a cap,
    // one angle near 180°. Flipping its longest edge removes it and keeps
    // the surface where it was; needles are left alone.
    PMP::experimental::remove_almost_degenerate_faces(m, std::cos(kCapAngleDeg * std::numbers::pi / 180.0),
                                                      std::numeric_limits<double>::max(), 0.0);
  } else {
    PMP::split_long_edges(edges(m), edge_length, m);
    PMP::isotropic_remeshing(faces(m), edge_length, m,
                             PMP::parameters::number_of_iterations(iterations)
                                 .number_of_relaxation_steps(3));
  }
  m.collect_garbage();
  return from_cgal(m);
}

SurfaceMesh cgal_remesh_patch(const SurfaceMesh& mesh, const std::vector<char>& selected, double edge_length,
                              int iterations) {
  Mesh m = to_cgal(mesh);
  std::vector<Mesh::Face_index> patch;
  for (const Mesh::Face_index f : faces(m)) {
    if (selected.at(static_cast<std::size_t>(f.idx())) != 0) patch.push_back(f);
  }
  if (patch.empty()) return mesh;
  PMP::isotropic_remeshing(patch, edge_length, m,
                           PMP::parameters::number_of_iterations(iterations).number_of_relaxation_steps(3));
  m.collect_garbage();
  return from_cgal(m);
}

std::optional<SurfaceMesh> cgal_boolean(const SurfaceMesh& a, const SurfaceMesh& b,
                                        CgalBoolean op) {
  Mesh ma = to_cgal(a);
  Mesh mb = to_cgal(b);
  Mesh out;
  bool ok = false;
  switch (op) {
    case CgalBoolean::Union: ok = PMP::corefine_and_compute_union(ma, mb, out); break;
    case CgalBoolean::Difference: ok = PMP::corefine_and_compute_difference(ma, mb, out); break;
    case CgalBoolean::Intersection: ok = PMP::corefine_and_compute_intersection(ma, mb, out); break;
  }
  if (!ok) return std::nullopt;
  // Rounding the cut's constructions to doubles can leave zero-area slivers
  // where features of the two solids coincide; they would be kept as sharp
  // edges by a feature-preserving remesh.
  PMP::remove_degenerate_faces(out);
  out.collect_garbage();
  return from_cgal(out);
}

std::optional<SurfaceMesh> cgal_clip_to_box(const SurfaceMesh& mesh, const Eigen::Vector3d& lo,
                                            const Eigen::Vector3d& hi) {
  Mesh m = to_cgal(mesh);
  const Kernel::Iso_cuboid_3 box(Point(lo.x(), lo.y(), lo.z()), Point(hi.x(), hi.y(), hi.z()));
  if (!PMP::clip(m, box, PMP::parameters::clip_volume(true))) return std::nullopt;
  m.collect_garbage();
  if (m.number_of_faces() == 0 || !CGAL::is_closed(m)) return std::nullopt;
  return from_cgal(m);
}

std::optional<SurfaceMesh> cgal_remove_self_intersections(const SurfaceMesh& mesh,
                                                          Eigen::Index* pairs) {
  Mesh m = to_cgal(mesh);
  std::size_t found = 0;
  PMP::self_intersections(faces(m), m,
                          boost::make_function_output_iterator(
                              [&found](const std::pair<Mesh::Face_index, Mesh::Face_index>&) {
                                ++found;
                              }));
  if (pairs != nullptr) *pairs = static_cast<Eigen::Index>(found);
  if (found == 0) return mesh;
  if (!PMP::experimental::remove_self_intersections(m, PMP::parameters::preserve_genus(false))) {
    return std::nullopt;
  }
  m.collect_garbage();
  if (!CGAL::is_closed(m) || PMP::does_self_intersect(m)) return std::nullopt;
  return from_cgal(m);
}

std::optional<std::pair<Eigen::Index, Eigen::Index>> cgal_self_intersection(
    const SurfaceMesh& mesh) {
  const Mesh m = to_cgal(mesh);
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
  // Only the first pair is needed: stop the search there.
  struct Full {};
  try {
    PMP::self_intersections(faces(m), m,
                            boost::make_function_output_iterator(
                                [&pairs](const std::pair<Mesh::Face_index, Mesh::Face_index>& p) {
                                  pairs.push_back(p);
                                  throw Full{};
                                }));
  } catch (const Full&) {
  }
  if (pairs.empty()) return std::nullopt;
  return std::make_pair(static_cast<Eigen::Index>(pairs.front().first.idx()),
                        static_cast<Eigen::Index>(pairs.front().second.idx()));
}

bool cgal_surfaces_intersect(const SurfaceMesh& a, const SurfaceMesh& b) {
  const Mesh ma = to_cgal(a);
  const Mesh mb = to_cgal(b);
  return PMP::do_intersect(ma, mb, PMP::parameters::do_overlap_test_of_bounded_sides(false),
                           PMP::parameters::do_overlap_test_of_bounded_sides(false));
}

struct SurfaceQueries::Impl {
  Mesh mesh;
  Tree tree;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<Mesh, Kernel>> side;
};

SurfaceQueries::SurfaceQueries(const SurfaceMesh& mesh) : impl_(std::make_unique<Impl>()) {
  impl_->mesh = to_cgal(mesh);
  impl_->tree.insert(faces(impl_->mesh).first, faces(impl_->mesh).second, impl_->mesh);
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
  impl_->side = std::make_unique<CGAL::Side_of_triangle_mesh<Mesh, Kernel>>(impl_->tree);
}

SurfaceQueries::~SurfaceQueries() = default;

std::pair<Eigen::Index, Eigen::Vector3d> SurfaceQueries::closest(const Eigen::Vector3d& p) const {
  const auto hit = impl_->tree.closest_point_and_primitive(Point(p.x(), p.y(), p.z()));
  return {static_cast<Eigen::Index>(hit.second.idx()), to_eigen(hit.first)};
}

double SurfaceQueries::distance(const Eigen::Vector3d& p) const {
  return std::sqrt(impl_->tree.squared_distance(Point(p.x(), p.y(), p.z())));
}

std::optional<double> SurfaceQueries::ray_hit(const Eigen::Vector3d& p, const Eigen::Vector3d& d,
                                              Eigen::Index skip_face) const {
  const Kernel::Ray_3 ray(Point(p.x(), p.y(), p.z()), Kernel::Vector_3(d.x(), d.y(), d.z()));
  const auto skip = [skip_face](Mesh::Face_index f) {
    return static_cast<Eigen::Index>(f.idx()) == skip_face;
  };
  const auto hit = impl_->tree.first_intersection(ray, skip);
  if (!hit) return std::nullopt;
  if (const Point* q = boost::get<Point>(&hit->first)) return (to_eigen(*q) - p).norm();
  if (const auto* s = boost::get<Kernel::Segment_3>(&hit->first)) {
    return (to_eigen(s->source()) - p).norm();
  }
  return std::nullopt;
}

bool SurfaceQueries::inside(const Eigen::Vector3d& p) const {
  return (*impl_->side)(Point(p.x(), p.y(), p.z())) == CGAL::ON_BOUNDED_SIDE;
}

}  // namespace palpa::mesh::detail
