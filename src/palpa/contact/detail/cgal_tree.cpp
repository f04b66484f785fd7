// SPDX-License-Identifier: AGPL-3.0-or-later
// The one translation unit of the contact module that includes CGAL.
#include "palpa/contact/detail/cgal_tree.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <vector>

namespace palpa::contact::detail {

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

struct CgalTree::Impl {
  std::vector<Triangle> triangles;
  Tree tree;
};

CgalTree::CgalTree(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F)
    : impl_(std::make_unique<Impl>()) {
  impl_->triangles.reserve(static_cast<std::size_t>(F.rows()));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    impl_->triangles.emplace_back(to_point(V.row(F(f, 0))), to_point(V.row(F(f, 1))),
                                  to_point(V.row(F(f, 2))));
  }
  impl_->tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
  // Build now (tree and the distance-query accelerator), so that concurrent
  // const queries never trigger the lazy construction.
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}

CgalTree::~CgalTree() = default;

int CgalTree::closest_triangle(const Eigen::Vector3d& p) const {
  const auto hit = impl_->tree.closest_point_and_primitive(to_point(p));
  return static_cast<int>(hit.second - impl_->triangles.cbegin());
}

}  // namespace palpa::contact::detail
