// SPDX-License-Identifier: AGPL-3.0-or-later
// The one translation unit of the tests and benchmarks that includes CGAL.
#include "common/cgal_triangle_tree.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <vector>

namespace palpa::test {

namespace {
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Point to_point(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}
}  // namespace

struct CgalTriangleTree::Impl {
  std::vector<Triangle> triangles;
  Tree tree;
};

CgalTriangleTree::CgalTriangleTree(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F)
    : impl_(std::make_unique<Impl>()) {
  impl_->triangles.reserve(static_cast<std::size_t>(F.rows()));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    impl_->triangles.emplace_back(to_point(V.row(F(f, 0))), to_point(V.row(F(f, 1))),
                                  to_point(V.row(F(f, 2))));
  }
  impl_->tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}

CgalTriangleTree::~CgalTriangleTree() = default;

CgalTriangleTree::Hit CgalTriangleTree::closest(const Eigen::Vector3d& p) const {
  const auto [point, primitive] = impl_->tree.closest_point_and_primitive(to_point(p));
  Hit hit;
  hit.triangle = static_cast<int>(primitive - impl_->triangles.cbegin());
  hit.point = Eigen::Vector3d(point.x(), point.y(), point.z());
  hit.distance2 = (p - hit.point).squaredNorm();
  return hit;
}

}  // namespace palpa::test
