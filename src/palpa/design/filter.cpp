// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/design/filter.hpp"

#include <cmath>
#include <fmt/format.h>

#include "palpa/core/error.hpp"
#include "palpa/geometry/surface_operators.hpp"

namespace palpa::design {

DesignFilter::DesignFilter(const SurfaceMesh& support, const std::vector<int>& vertices, double radius)
    : radius_(radius) {
  if (!(radius >= 0.0) || !std::isfinite(radius)) {
    throw Error(ErrorKind::Input, fmt::format("the design filter radius must be finite and ≥ 0 m, got {}", radius));
  }
  if (radius == 0.0) return;
  const auto n = static_cast<Eigen::Index>(vertices.size());
  std::vector<int> index(static_cast<std::size_t>(support.V.rows()), -1);
  for (Eigen::Index i = 0; i < n; ++i) index[static_cast<std::size_t>(vertices[static_cast<std::size_t>(i)])] = static_cast<int>(i);
  const Eigen::VectorXd area = geometry::vertex_areas(support);
  mass_.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) mass_[i] = area[vertices[static_cast<std::size_t>(i)]];
  if (!(mass_.minCoeff() > 0.0)) {
    throw Error(ErrorKind::Input, "a design vertex has no area on the support (no triangle around it): it cannot be filtered");
  }
  const Eigen::SparseMatrix<double> L = geometry::cotangent_laplacian(support);
  std::vector<Eigen::Triplet<double>> t;
  const double r2 = radius * radius;
  for (int k = 0; k < L.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(L, k); it; ++it) {
      const int i = index[static_cast<std::size_t>(it.row())], j = index[static_cast<std::size_t>(it.col())];
      if (i >= 0 && j >= 0) t.emplace_back(i, j, r2 * it.value());
    }
  }
  for (Eigen::Index i = 0; i < n; ++i) t.emplace_back(static_cast<int>(i), static_cast<int>(i), mass_[i]);
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  solver_ = std::make_unique<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>(A);
  if (solver_->info() != Eigen::Success || !(solver_->vectorD().minCoeff() > 0.0)) {
    throw Error(ErrorKind::Input, "the design filter's system is not positive definite (a degenerate support mesh)");
  }
}

DesignFilter::~DesignFilter() = default;

Eigen::MatrixXd DesignFilter::apply(const Eigen::MatrixXd& U) const {
  if (!solver_) return U;
  Eigen::MatrixXd X = U;
  for (int pass = 0; pass < 2; ++pass) {
    const Eigen::MatrixXd B = mass_.asDiagonal() * X;  // a temporary: the solve must not read what it writes
    X = solver_->solve(B);
  }
  return X;
}

Eigen::MatrixXd DesignFilter::apply_transpose(const Eigen::MatrixXd& G) const {
  if (!solver_) return G;
  Eigen::MatrixXd X = G;
  for (int pass = 0; pass < 2; ++pass) {
    const Eigen::MatrixXd Y = solver_->solve(X);
    X = mass_.asDiagonal() * Y;
  }
  return X;
}

double design_edge_length(const SurfaceMesh& support, const std::vector<int>& vertices) {
  std::vector<char> in(static_cast<std::size_t>(support.V.rows()), 0);
  for (int v : vertices) in[static_cast<std::size_t>(v)] = 1;
  double sum = 0.0;
  long count = 0;
  for (Eigen::Index f = 0; f < support.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = support.F(f, k), b = support.F(f, (k + 1) % 3);
      if (in[static_cast<std::size_t>(a)] && in[static_cast<std::size_t>(b)]) {
        sum += (support.V.row(a) - support.V.row(b)).norm();
        ++count;
      }
    }
  }
  // Each interior edge is counted from both of its triangles: the mean is
  // unchanged by that.
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

}  // namespace palpa::design
