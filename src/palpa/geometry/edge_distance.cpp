// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/geometry/edge_distance.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>
#include <utility>
#include <vector>

namespace palpa::geometry {

Eigen::VectorXd edge_path_distance(const SurfaceMesh& mesh, std::span<const Eigen::Index> sources, double limit) {
  const Eigen::Index n = mesh.V.rows();
  // Each vertex's neighbours across the triangles' edges (an edge shared by
  // two triangles listed twice; harmless for the search).
  std::vector<std::vector<Eigen::Index>> neighbours(static_cast<std::size_t>(n));
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Index a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      neighbours[static_cast<std::size_t>(a)].push_back(b);
      neighbours[static_cast<std::size_t>(b)].push_back(a);
    }
  }
  Eigen::VectorXd d = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, Eigen::Index>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  for (const Eigen::Index s : sources) {
    if (s < 0 || s >= n) throw std::out_of_range(fmt::format("source vertex {} of a mesh of {} vertices", s, n));
    d(s) = 0.0;
    queue.emplace(0.0, s);
  }
  while (!queue.empty()) {
    const auto [dv, v] = queue.top();
    queue.pop();
    if (dv > d(v)) continue;  // a stale entry
    for (const Eigen::Index w : neighbours[static_cast<std::size_t>(v)]) {
      const double dw = dv + (mesh.V.row(w) - mesh.V.row(v)).norm();
      if (dw < d(w) && dw <= limit) {
        d(w) = dw;
        queue.emplace(dw, w);
      }
    }
  }
  return d;
}

}  // namespace palpa::geometry
