// SPDX-License-Identifier: AGPL-3.0-or-later
#include "solve/matrices.hpp"

#include <Eigen/Core>
#include <array>
#include <vector>

namespace palpa::test {

Eigen::SparseMatrix<double> laplacian_2d(int m) {
  const int n = m * m;
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(5 * n));
  auto id = [m](int i, int j) { return i + m * j; };
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < m; ++i) {
      const int k = id(i, j);
      t.emplace_back(k, k, 4.0);
      if (i > 0) t.emplace_back(k, id(i - 1, j), -1.0);
      if (i + 1 < m) t.emplace_back(k, id(i + 1, j), -1.0);
      if (j > 0) t.emplace_back(k, id(i, j - 1), -1.0);
      if (j + 1 < m) t.emplace_back(k, id(i, j + 1), -1.0);
    }
  }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

namespace {

// Springs along every node pair of each cell of an m^D grid of nodes, D DOFs
// per node, plus `mass_diagonal` on the diagonal.
template <int D>
Eigen::SparseMatrix<double> grid_elasticity_like(int m, double mass_diagonal) {
  constexpr int kCorners = 1 << D;
  using Vec = Eigen::Matrix<double, D, 1>;
  int nodes = 1;
  for (int d = 0; d < D; ++d) nodes *= m;
  const int n = D * nodes;
  int cells = 1;
  for (int d = 0; d < D; ++d) cells *= m - 1;
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(cells) * kCorners * (kCorners - 1) / 2 * 4 * D * D + n);
  for (int cell = 0; cell < cells; ++cell) {
    std::array<int, D> base{};
    for (int d = 0, rest = cell; d < D; ++d, rest /= m - 1) base[static_cast<std::size_t>(d)] = rest % (m - 1);
    std::array<int, kCorners> corner{};
    std::array<Vec, kCorners> pos;
    for (int c = 0; c < kCorners; ++c) {
      int id = 0;
      for (int d = D - 1; d >= 0; --d) id = id * m + base[static_cast<std::size_t>(d)] + ((c >> d) & 1);
      corner[static_cast<std::size_t>(c)] = id;
      for (int d = 0; d < D; ++d) pos[static_cast<std::size_t>(c)][d] = (c >> d) & 1;
    }
    for (std::size_t a = 0; a < kCorners; ++a) {
      for (std::size_t b = a + 1; b < kCorners; ++b) {
        const Vec u = (pos[b] - pos[a]).normalized();
        const Eigen::Matrix<double, D, D> block = u * u.transpose();
        for (int r = 0; r < D; ++r) {
          for (int c = 0; c < D; ++c) {
            const int ra = D * corner[a] + r;
            const int rb = D * corner[b] + r;
            const int ca = D * corner[a] + c;
            const int cb = D * corner[b] + c;
            t.emplace_back(ra, ca, block(r, c));
            t.emplace_back(rb, cb, block(r, c));
            t.emplace_back(ra, cb, -block(r, c));
            t.emplace_back(rb, ca, -block(r, c));
          }
        }
      }
    }
  }
  for (int d = 0; d < n; ++d) t.emplace_back(d, d, mass_diagonal);
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

}  // namespace

Eigen::SparseMatrix<double> elasticity_2d_like(int m, double mass_diagonal) {
  return grid_elasticity_like<2>(m, mass_diagonal);
}

Eigen::SparseMatrix<double> elasticity_3d_like(int m, double mass_diagonal) {
  return grid_elasticity_like<3>(m, mass_diagonal);
}

Eigen::SparseMatrix<double> random_spd(int n, int offdiag_per_column, std::mt19937_64& rng) {
  std::uniform_int_distribution<int> row(0, n - 1);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < n; ++j) {
    for (int e = 0; e < offdiag_per_column; ++e) {
      const int i = row(rng);
      if (i == j) continue;
      const double v = value(rng);
      t.emplace_back(i, j, v);
      t.emplace_back(j, i, v);
    }
  }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  Eigen::VectorXd diag = Eigen::VectorXd::Ones(n);
  for (int j = 0; j < n; ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it)
      diag[it.row()] += std::abs(it.value());
  }
  std::vector<Eigen::Triplet<double>> d;
  for (int j = 0; j < n; ++j) d.emplace_back(j, j, diag[j]);
  Eigen::SparseMatrix<double> D(n, n);
  D.setFromTriplets(d.begin(), d.end());
  return A + D;
}

Eigen::SparseMatrix<double> lower_triangle(const Eigen::SparseMatrix<double>& A) {
  return A.triangularView<Eigen::Lower>();
}

Eigen::SparseMatrix<double> symmetric_from_lower(const Eigen::SparseMatrix<double>& L) {
  Eigen::SparseMatrix<double> strict = L.triangularView<Eigen::StrictlyLower>();
  Eigen::SparseMatrix<double> lower = L.triangularView<Eigen::Lower>();
  return Eigen::SparseMatrix<double>(lower + Eigen::SparseMatrix<double>(strict.transpose()));
}

}  // namespace palpa::test
