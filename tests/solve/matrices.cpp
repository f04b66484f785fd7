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

Eigen::SparseMatrix<double> elasticity_3d_like(int m, double mass_diagonal) {
  const int nodes = m * m * m;
  const int n = 3 * nodes;
  auto id = [m](int i, int j, int k) { return i + m * (j + m * k); };
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(m - 1) * (m - 1) * (m - 1) * 28 * 36 + n);
  for (int k = 0; k + 1 < m; ++k) {
    for (int j = 0; j + 1 < m; ++j) {
      for (int i = 0; i + 1 < m; ++i) {
        std::array<int, 8> corner{};
        std::array<Eigen::Vector3d, 8> pos;
        for (int c = 0; c < 8; ++c) {
          const int di = c & 1;
          const int dj = (c >> 1) & 1;
          const int dk = (c >> 2) & 1;
          corner[static_cast<std::size_t>(c)] = id(i + di, j + dj, k + dk);
          pos[static_cast<std::size_t>(c)] = Eigen::Vector3d(di, dj, dk);
        }
        for (std::size_t a = 0; a < 8; ++a) {
          for (std::size_t b = a + 1; b < 8; ++b) {
            const Eigen::Vector3d u = (pos[b] - pos[a]).normalized();
            const Eigen::Matrix3d block = u * u.transpose();
            for (int r = 0; r < 3; ++r) {
              for (int c = 0; c < 3; ++c) {
                const int ra = 3 * corner[a] + r;
                const int rb = 3 * corner[b] + r;
                const int ca = 3 * corner[a] + c;
                const int cb = 3 * corner[b] + c;
                t.emplace_back(ra, ca, block(r, c));
                t.emplace_back(rb, cb, block(r, c));
                t.emplace_back(ra, cb, -block(r, c));
                t.emplace_back(rb, ca, -block(r, c));
              }
            }
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
