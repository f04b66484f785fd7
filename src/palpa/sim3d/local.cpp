// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/sim3d/local.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "palpa/core/error.hpp"

namespace palpa::sim3d {

ActiveRegion active_region(const TetMesh& mesh, const std::vector<const contact::Obstacle*>& obstacles,
                           double margin) {
  const Eigen::Index nv = mesh.V.rows();
  std::vector<char> near(static_cast<std::size_t>(nv), 0);
  tbb::parallel_for(Eigen::Index{0}, nv, [&](Eigen::Index v) {
    const Eigen::Vector3d p = mesh.V.row(v).transpose();
    for (const contact::Obstacle* o : obstacles) {
      const contact::ClosestPoint c = o->closest_point(p);
      if (c.inside || c.distance <= margin) {
        near[static_cast<std::size_t>(v)] = 1;
        return;
      }
    }
  });
  ActiveRegion r;
  std::vector<char> kept_vertex(static_cast<std::size_t>(nv), 0);
  std::vector<char> dropped_vertex(static_cast<std::size_t>(nv), 0);
  for (Eigen::Index t = 0; t < mesh.T.rows(); ++t) {
    bool keep = false;
    for (int a = 0; a < 4; ++a) keep = keep || near[static_cast<std::size_t>(mesh.T(t, a))];
    for (int a = 0; a < 4; ++a) (keep ? kept_vertex : dropped_vertex)[static_cast<std::size_t>(mesh.T(t, a))] = 1;
    if (keep) r.element.push_back(static_cast<int>(t));
  }
  if (r.element.empty()) {
    throw Error(ErrorKind::Input,
                fmt::format("local simulation: no tetrahedron lies within {:.3g} mm of an obstacle", margin * 1e3));
  }
  std::vector<int> to_sub(static_cast<std::size_t>(nv), -1);
  for (Eigen::Index v = 0; v < nv; ++v) {
    if (!kept_vertex[static_cast<std::size_t>(v)]) continue;
    to_sub[static_cast<std::size_t>(v)] = static_cast<int>(r.vertex.size());
    if (dropped_vertex[static_cast<std::size_t>(v)]) r.cut.push_back(static_cast<int>(r.vertex.size()));
    r.vertex.push_back(static_cast<int>(v));
  }
  r.mesh.V.resize(static_cast<Eigen::Index>(r.vertex.size()), 3);
  for (std::size_t i = 0; i < r.vertex.size(); ++i) r.mesh.V.row(static_cast<Eigen::Index>(i)) = mesh.V.row(r.vertex[i]);
  r.mesh.T.resize(static_cast<Eigen::Index>(r.element.size()), 4);
  if (mesh.region.size() == mesh.T.rows()) r.mesh.region.resize(r.mesh.T.rows());
  for (std::size_t i = 0; i < r.element.size(); ++i) {
    const auto t = static_cast<Eigen::Index>(r.element[i]);
    for (int a = 0; a < 4; ++a) r.mesh.T(static_cast<Eigen::Index>(i), a) = to_sub[static_cast<std::size_t>(mesh.T(t, a))];
    if (r.mesh.region.size() > 0) r.mesh.region[static_cast<Eigen::Index>(i)] = mesh.region[t];
  }
  return r;
}

}  // namespace palpa::sim3d
