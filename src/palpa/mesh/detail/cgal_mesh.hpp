// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Shared by the CGAL translation units of the mesh module (cgal_*.cpp) and
// by nothing else: the surface type they use and its conversion to palpa's.

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include <vector>

#include "palpa/geometry/mesh.hpp"

namespace palpa::mesh::detail {

using CgalKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalPoint = CgalKernel::Point_3;
using CgalMesh = CGAL::Surface_mesh<CgalPoint>;

// Vertices renumbered 0.. in iteration order (removed ones skipped).
inline SurfaceMesh from_cgal(const CgalMesh& m) {
  SurfaceMesh out;
  out.V.resize(static_cast<Eigen::Index>(m.number_of_vertices()), 3);
  std::vector<int> index(m.num_vertices(), -1);
  int next = 0;
  for (const auto v : m.vertices()) {
    const CgalPoint& p = m.point(v);
    out.V.row(next) << p.x(), p.y(), p.z();
    index[v] = next++;
  }
  out.F.resize(static_cast<Eigen::Index>(m.number_of_faces()), 3);
  Eigen::Index f = 0;
  for (const auto face : m.faces()) {
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(m.halfedge(face), m)) out.F(f, k++) = index[v];
    ++f;
  }
  return out;
}

}  // namespace palpa::mesh::detail
