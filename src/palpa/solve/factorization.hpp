// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Sparse symmetric factorizations behind one small interface.
//
// Symbolic once, numeric often: analyze() computes the fill-reducing ordering
// and the symbolic factor of a pattern once per topology; factorize() then only
// redoes the numbers. factorize() compares the pattern of each matrix with the
// analysed one (a memory compare of the index arrays, O(nnz)) and re-analyses by
// itself when it changed, so callers need not track topology changes.
//
// Matrix convention (the same as System::hessian): an n×n
// Eigen::SparseMatrix<double> (column-major, int indices) of which only the
// LOWER TRIANGLE (row ≥ col, diagonal included) is read. Entries above the
// diagonal are ignored, so a full symmetric matrix is accepted too, but storing
// only the lower triangle halves the work of whoever assembles it. A diagonal
// entry missing from the pattern is a structural zero (a shift can still fill it).
//
// A failed factorization is a returned FactorStatus, never an assert or an
// exception: the Newton loop acts on NotPositiveDefinite by shifting.
//
// Implementations: SparseCholesky (CHOLMOD, sparse_cholesky.hpp) and SparseLdlt
// (Eigen's SimplicialLDLT, sparse_ldlt.hpp).

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <string_view>
#include <vector>

namespace palpa {

enum class FactorStatus {
  Ok,                   // factored: solve() may be called
  NotFactored,          // nothing factored yet (or only analysed)
  NotPositiveDefinite,  // a pivot ≤ 0: the matrix (plus shift) is not positive definite
  Singular,             // a zero pivot (only a factorization that accepts indefinite matrices)
  NonFiniteInput,       // the matrix, the shift or the shift diagonal holds NaN or ±inf
  OutOfMemory,          // the sparse library could not allocate the factor
};

// "ok", "not positive definite", ... for messages.
std::string_view to_string(FactorStatus status) noexcept;

// How much work a factorization object has done since it was made.
struct FactorCounts {
  std::int64_t analyses = 0;        // symbolic analyses, explicit or after a pattern change
  std::int64_t factorizations = 0;  // numeric factorizations attempted (failed ones included)
};

class SymmetricFactorization {
 public:
  virtual ~SymmetricFactorization();
  SymmetricFactorization(const SymmetricFactorization&) = delete;
  SymmetricFactorization& operator=(const SymmetricFactorization&) = delete;

  // Short name of the implementation ("cholmod", "eigen-ldlt"), for benchmarks.
  virtual std::string_view name() const noexcept = 0;

  // Symbolic analysis of `pattern` (n×n; values are ignored, only the lower
  // triangle's structure is used). Returns Ok or OutOfMemory. Resets status() to
  // NotFactored on success.
  FactorStatus analyze(const Eigen::SparseMatrix<double>& pattern);

  // Numeric factorization of  A + sigma·diag(d).
  //  A:     n×n, lower triangle read (see above), in the units of the problem
  //         (for a Hessian: energy / dof²).
  //  sigma: shift (dimensionless when d carries the units, else in A's units);
  //         0 = no shift. The shift is added to a copy: A is not modified.
  //  d:     n entries (the diagonal D of the shift), or empty for D = identity.
  // Reuses the analysis; analyses again first if A's pattern differs from the
  // analysed one (or nothing was analysed). Uncompressed matrices are accepted
  // (copied to compressed form first). Returns the status, also kept in status().
  FactorStatus factorize(const Eigen::SparseMatrix<double>& A, double sigma = 0.0,
                         const Eigen::VectorXd& d = Eigen::VectorXd());

  // Solves (A + sigma·D) X = B for the last successful factorize().
  //  B: n×k, one right-hand side per column (a vector is n×1).
  //  returns X: n×k.
  // Safe to call concurrently from several threads on one object (no shared
  // scratch). Throws palpa::Error (kind Internal) if status() is not Ok or B has
  // the wrong number of rows: both are bugs in the caller.
  Eigen::MatrixXd solve(const Eigen::Ref<const Eigen::MatrixXd>& B) const;

  FactorStatus status() const noexcept { return status_; }
  // n of the analysed pattern (0 before the first analysis).
  Eigen::Index size() const noexcept { return n_; }
  FactorCounts counts() const noexcept { return counts_; }

 protected:
  SymmetricFactorization() = default;

  // Which triangle of the (symmetric) matrix an implementation wants to be
  // handed in do_factorize(). Column-major, so Lower = entries with row ≥ col.
  enum class Triangle { Lower, Upper };

  // Symbolic analysis of the lower triangle `lower` (compressed, sorted, full
  // diagonal present). Returns Ok or OutOfMemory.
  virtual FactorStatus do_analyze(const Eigen::SparseMatrix<double>& lower) = 0;
  // The triangle do_factorize() wants; asked after each successful do_analyze().
  virtual Triangle factor_triangle() const noexcept = 0;
  // Numeric factorization of `working` (the triangle named by factor_triangle(),
  // compressed, sorted, diagonal present, all values finite).
  virtual FactorStatus do_factorize(const Eigen::SparseMatrix<double>& working) = 0;
  // Overwrites B (n×k) with the solution of the factored system.
  virtual void do_solve(Eigen::MatrixXd& B) const = 0;

 private:
  // Builds working_ (in `triangle`), scatter_ and diagonal_ from the stored user pattern.
  void build_working(Triangle triangle);
  bool same_pattern(const Eigen::SparseMatrix<double>& A) const noexcept;

  Eigen::Index n_ = 0;
  FactorStatus status_ = FactorStatus::NotFactored;
  FactorCounts counts_;
  bool analysed_ = false;
  // The caller's pattern as analysed (compressed index arrays), for change detection.
  std::vector<int> user_outer_;
  std::vector<int> user_inner_;
  // For each stored entry of the caller's matrix: its index in working_'s values,
  // or -1 if it lies in the ignored upper triangle.
  std::vector<int> scatter_;
  // Index of each diagonal entry in working_'s values.
  std::vector<int> diagonal_;
  // The matrix actually factored: one triangle, full diagonal, values scattered
  // from the caller's matrix plus the shift.
  Eigen::SparseMatrix<double> working_;
};

}  // namespace palpa
