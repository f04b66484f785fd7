// SPDX-License-Identifier: AGPL-3.0-or-later
// The contact module's second (and last) CGAL translation unit: exact
// self-intersection tests.
#include "palpa/contact/detail/cgal_checks.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <iterator>
#include <utility>
#include <vector>

namespace palpa::contact::detail {

namespace {
using ExactKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CheckMesh = CGAL::Surface_mesh<ExactKernel::Point_3>;
using Face = CheckMesh::Face_index;
}  // namespace

SelfIntersections self_intersections(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                     std::size_t cap) {
  CheckMesh mesh;
  std::vector<CheckMesh::Vertex_index> vertex;
  vertex.reserve(static_cast<std::size_t>(V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    vertex.push_back(mesh.add_vertex(ExactKernel::Point_3(V(i, 0), V(i, 1), V(i, 2))));
  }
  // Faces in the order of F, so that face i is triangle i. A face the
  // halfedge structure cannot take (a vertex where separate fans meet) is
  // skipped: the pairs found among the others are still intersections.
  std::vector<int> row;
  row.reserve(static_cast<std::size_t>(F.rows()));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Face added = mesh.add_face(vertex[static_cast<std::size_t>(F(f, 0))],
                                     vertex[static_cast<std::size_t>(F(f, 1))],
                                     vertex[static_cast<std::size_t>(F(f, 2))]);
    if (added != CheckMesh::null_face()) row.push_back(static_cast<int>(f));
  }
  std::vector<std::pair<Face, Face>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(
      mesh, std::back_inserter(pairs),
      CGAL::parameters::maximum_number(static_cast<unsigned int>(cap)));
  SelfIntersections out;
  out.pairs = pairs.size();
  if (!pairs.empty()) {
    out.first = row[static_cast<std::size_t>(pairs.front().first.idx())];
    out.second = row[static_cast<std::size_t>(pairs.front().second.idx())];
  }
  return out;
}

}  // namespace palpa::contact::detail
