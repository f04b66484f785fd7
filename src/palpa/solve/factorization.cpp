// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/solve/factorization.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "palpa/core/error.hpp"

namespace palpa {

std::string_view to_string(FactorStatus status) noexcept {
  switch (status) {
    case FactorStatus::Ok:
      return "ok";
    case FactorStatus::NotFactored:
      return "not factored";
    case FactorStatus::NotPositiveDefinite:
      return "not positive definite";
    case FactorStatus::Singular:
      return "singular";
    case FactorStatus::NonFiniteInput:
      return "non-finite matrix entries";
    case FactorStatus::OutOfMemory:
      return "out of memory";
  }
  return "unknown";
}

SymmetricFactorization::~SymmetricFactorization() = default;

namespace {

// `A` itself if it is compressed, else a compressed copy kept in `storage`.
const Eigen::SparseMatrix<double>& compressed(const Eigen::SparseMatrix<double>& A,
                                              Eigen::SparseMatrix<double>& storage) {
  if (A.isCompressed()) return A;
  storage = A;
  storage.makeCompressed();
  return storage;
}

void require_square(const Eigen::SparseMatrix<double>& A, const char* what) {
  if (A.rows() != A.cols()) {
    throw Error(ErrorKind::Internal, fmt::format("{}: matrix is {}x{}, expected a square matrix",
                                                 what, A.rows(), A.cols()));
  }
}

}  // namespace

void SymmetricFactorization::build_working(Triangle triangle) {
  const int n = static_cast<int>(n_);
  const bool lower = triangle == Triangle::Lower;
  // One slot per kept entry plus one per diagonal entry, bucketed by the column
  // it has in the working triangle; `source` is the caller's entry index, or -1
  // for the diagonal placeholder.
  struct Slot {
    int row;
    int source;
  };
  std::vector<int> start(static_cast<std::size_t>(n) + 1, 0);
  for (int j = 0; j < n; ++j) {
    ++start[static_cast<std::size_t>(j) + 1];
    for (int k = user_outer_[j]; k < user_outer_[j + 1]; ++k) {
      const int i = user_inner_[static_cast<std::size_t>(k)];
      if (i >= j) ++start[static_cast<std::size_t>(lower ? j : i) + 1];
    }
  }
  for (int j = 0; j < n; ++j) start[j + 1] += start[j];
  std::vector<Slot> slots(static_cast<std::size_t>(start[n]));
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int j = 0; j < n; ++j) {
    slots[static_cast<std::size_t>(fill[j]++)] = Slot{j, -1};
    for (int k = user_outer_[j]; k < user_outer_[j + 1]; ++k) {
      const int i = user_inner_[static_cast<std::size_t>(k)];
      if (i < j) continue;
      const int col = lower ? j : i;
      slots[static_cast<std::size_t>(fill[col]++)] = Slot{lower ? i : j, k};
    }
  }

  scatter_.assign(user_inner_.size(), -1);
  diagonal_.assign(static_cast<std::size_t>(n), -1);
  std::vector<int> outer(static_cast<std::size_t>(n) + 1, 0);
  std::vector<int> inner;
  inner.reserve(slots.size());
  for (int c = 0; c < n; ++c) {
    const auto first = slots.begin() + start[c];
    const auto last = slots.begin() + start[c + 1];
    std::sort(first, last, [](const Slot& a, const Slot& b) { return a.row < b.row; });
    outer[static_cast<std::size_t>(c)] = static_cast<int>(inner.size());
    int previous_row = -1;
    for (auto s = first; s != last; ++s) {
      // Equal rows (the diagonal placeholder and the caller's diagonal entry,
      // or duplicates) share one working entry.
      if (s->row != previous_row) {
        inner.push_back(s->row);
        previous_row = s->row;
      }
      const int index = static_cast<int>(inner.size()) - 1;
      if (s->source >= 0) {
        scatter_[static_cast<std::size_t>(s->source)] = index;
      } else {
        diagonal_[static_cast<std::size_t>(c)] = index;
      }
    }
  }
  outer[static_cast<std::size_t>(n)] = static_cast<int>(inner.size());
  std::vector<double> values(inner.size(), 0.0);
  working_ = Eigen::Map<const Eigen::SparseMatrix<double>>(
      n, n, static_cast<Eigen::Index>(inner.size()), outer.data(), inner.data(), values.data());
}

bool SymmetricFactorization::same_pattern(const Eigen::SparseMatrix<double>& A) const noexcept {
  if (A.rows() != n_ || A.cols() != n_) return false;
  if (static_cast<std::size_t>(A.nonZeros()) != user_inner_.size()) return false;
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  return std::equal(user_outer_.begin(), user_outer_.end(), outer) &&
         std::equal(user_inner_.begin(), user_inner_.end(), inner);
}

FactorStatus SymmetricFactorization::analyze(const Eigen::SparseMatrix<double>& pattern) {
  require_square(pattern, "SymmetricFactorization::analyze");
  Eigen::SparseMatrix<double> storage;
  const Eigen::SparseMatrix<double>& P = compressed(pattern, storage);

  analysed_ = false;
  status_ = FactorStatus::NotFactored;
  n_ = P.rows();
  user_outer_.assign(P.outerIndexPtr(), P.outerIndexPtr() + n_ + 1);
  user_inner_.assign(P.innerIndexPtr(), P.innerIndexPtr() + P.nonZeros());
  build_working(Triangle::Lower);
  ++counts_.analyses;
  const FactorStatus st = do_analyze(working_);
  if (st != FactorStatus::Ok) {
    status_ = st;
    return st;
  }
  if (factor_triangle() == Triangle::Upper) build_working(Triangle::Upper);
  analysed_ = true;
  return FactorStatus::Ok;
}

FactorStatus SymmetricFactorization::factorize(const Eigen::SparseMatrix<double>& A, double sigma,
                                               const Eigen::VectorXd& d) {
  require_square(A, "SymmetricFactorization::factorize");
  Eigen::SparseMatrix<double> storage;
  const Eigen::SparseMatrix<double>& M = compressed(A, storage);
  if (!analysed_ || !same_pattern(M)) {
    const FactorStatus st = analyze(M);
    if (st != FactorStatus::Ok) return st;
  }
  if (d.size() != 0 && d.size() != n_) {
    throw Error(ErrorKind::Internal,
                fmt::format("SymmetricFactorization::factorize: shift diagonal has {} entries, "
                            "expected {} (or none)",
                            d.size(), n_));
  }
  ++counts_.factorizations;
  status_ = FactorStatus::NotFactored;

  double* w = working_.valuePtr();
  const auto nnz = static_cast<std::size_t>(working_.nonZeros());
  std::fill(w, w + nnz, 0.0);
  const double* a = M.valuePtr();
  for (std::size_t k = 0; k < scatter_.size(); ++k) {
    const int target = scatter_[k];
    if (target >= 0) w[target] += a[k];
  }
  if (sigma != 0.0) {
    for (std::size_t j = 0; j < diagonal_.size(); ++j) {
      const double dj = d.size() == 0 ? 1.0 : d[static_cast<Eigen::Index>(j)];
      w[diagonal_[j]] += sigma * dj;
    }
  }
  bool finite = std::isfinite(sigma);
  for (std::size_t k = 0; k < nnz; ++k) finite = finite && std::isfinite(w[k]);
  if (!finite) {
    status_ = FactorStatus::NonFiniteInput;
    return status_;
  }
  status_ = do_factorize(working_);
  return status_;
}

Eigen::MatrixXd SymmetricFactorization::solve(const Eigen::Ref<const Eigen::MatrixXd>& B) const {
  if (status_ != FactorStatus::Ok) {
    throw Error(ErrorKind::Internal,
                fmt::format("{}: solve() without a successful factorization (status: {})", name(),
                            to_string(status_)));
  }
  if (B.rows() != n_) {
    throw Error(ErrorKind::Internal,
                fmt::format("{}: right-hand side has {} rows, expected {}", name(), B.rows(), n_));
  }
  Eigen::MatrixXd X = B;
  if (X.cols() > 0 && n_ > 0) do_solve(X);
  return X;
}

}  // namespace palpa
