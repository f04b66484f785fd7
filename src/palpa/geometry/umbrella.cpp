// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/geometry/umbrella.hpp"

#include <algorithm>
#include <cmath>

namespace palpa::geometry {

std::vector<std::vector<int>> vertex_neighbours(const Eigen::MatrixX3i& F, Eigen::Index n) {
  std::vector<std::vector<int>> nb(static_cast<std::size_t>(n));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      nb[static_cast<std::size_t>(a)].push_back(b);
      nb[static_cast<std::size_t>(b)].push_back(a);
    }
  }
  for (auto& l : nb) {
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
  }
  return nb;
}

Eigen::SparseMatrix<double> umbrella_matrix(const Eigen::MatrixX3i& F, Eigen::Index n) {
  const std::vector<std::vector<int>> nb = vertex_neighbours(F, n);
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index v = 0; v < n; ++v) {
    const auto& l = nb[static_cast<std::size_t>(v)];
    if (l.empty()) {
      t.emplace_back(static_cast<int>(v), static_cast<int>(v), 1.0);
      continue;
    }
    for (int j : l) t.emplace_back(static_cast<int>(v), j, 1.0 / static_cast<double>(l.size()));
  }
  Eigen::SparseMatrix<double> W(n, n);
  W.setFromTriplets(t.begin(), t.end());
  return W;
}

Spike largest_spike(const Eigen::MatrixX3d& D, const Eigen::MatrixX3i& F, const std::vector<int>& vertices,
                    const Eigen::MatrixX3d* normals) {
  const std::vector<std::vector<int>> ring = vertex_neighbours(F, D.rows());
  Spike worst;
  for (const int v : vertices) {
    const std::vector<int>& n = ring[static_cast<std::size_t>(v)];
    if (n.empty()) continue;
    Eigen::RowVector3d mean = Eigen::RowVector3d::Zero();
    for (const int j : n) mean += D.row(j);
    mean /= static_cast<double>(n.size());
    const double d = normals ? std::abs((D.row(v) - mean).dot(normals->row(v))) : (D.row(v) - mean).norm();
    if (d > worst.distance || worst.vertex < 0) worst = {d, v};
  }
  return worst;
}

}  // namespace palpa::geometry
