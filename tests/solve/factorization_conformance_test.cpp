// SPDX-License-Identifier: AGPL-3.0-or-later
// Every SymmetricFactorization runs through the same solves (typed test):
// random SPD matrices, several right-hand sides, many numeric factorizations on
// one analysis, indefinite matrices, changed patterns, shifts, bad input.
// Accuracy: relative residual ‖Ax − b‖/‖b‖ < 1e-12 on well-conditioned
// matrices (condition numbers ≲ 1e3 here).

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "common/test_support.hpp"
#include "palpa/solve/factorization.hpp"
#include "palpa/solve/sparse_cholesky.hpp"
#include "palpa/solve/sparse_ldlt.hpp"
#include "solve/matrices.hpp"

namespace palpa {
namespace {

using test::lower_triangle;
using test::make_rng;
using test::random_spd;
using SpMat = Eigen::SparseMatrix<double>;

constexpr double kResidualTol = 1e-12;

double relative_residual(const SpMat& A, const Eigen::MatrixXd& X, const Eigen::MatrixXd& B) {
  return (A * X - B).norm() / B.norm();
}

// Same pattern as A, new random values: symmetric, strictly diagonally dominant.
SpMat revalue(const SpMat& A, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> value(-2.0, 2.0);
  SpMat L = lower_triangle(A);
  for (int j = 0; j < L.outerSize(); ++j) {
    for (SpMat::InnerIterator it(L, j); it; ++it) {
      if (it.row() != it.col()) it.valueRef() = value(rng);
    }
  }
  SpMat S = test::symmetric_from_lower(L);
  Eigen::VectorXd row_sum = Eigen::VectorXd::Zero(S.rows());
  for (int j = 0; j < S.outerSize(); ++j) {
    for (SpMat::InnerIterator it(S, j); it; ++it) {
      if (it.row() != it.col()) row_sum[it.row()] += std::abs(it.value());
    }
  }
  for (int j = 0; j < S.outerSize(); ++j) S.coeffRef(j, j) = 0.5 + row_sum[j];
  return S;
}

struct CholmodAuto {
  static std::unique_ptr<SymmetricFactorization> make() {
    return std::make_unique<SparseCholesky>(SparseCholesky::Method::Auto);
  }
};
struct CholmodSupernodal {
  static std::unique_ptr<SymmetricFactorization> make() {
    return std::make_unique<SparseCholesky>(SparseCholesky::Method::Supernodal);
  }
};
struct CholmodSimplicial {
  static std::unique_ptr<SymmetricFactorization> make() {
    return std::make_unique<SparseCholesky>(SparseCholesky::Method::Simplicial);
  }
};
struct EigenLdlt {
  static std::unique_ptr<SymmetricFactorization> make() {
    return std::make_unique<SparseLdlt>(SparseLdlt::Definiteness::RequirePositive);
  }
};

template <typename Impl>
class FactorizationConformance : public ::testing::Test {
 protected:
  std::unique_ptr<SymmetricFactorization> f = Impl::make();
};

struct ImplName {
  template <typename T>
  static std::string GetName(int) {
    if (std::is_same_v<T, CholmodAuto>) return "CholmodAuto";
    if (std::is_same_v<T, CholmodSupernodal>) return "CholmodSupernodal";
    if (std::is_same_v<T, CholmodSimplicial>) return "CholmodSimplicial";
    return "EigenLdlt";
  }
};

using Implementations =
    ::testing::Types<CholmodAuto, CholmodSupernodal, CholmodSimplicial, EigenLdlt>;
TYPED_TEST_SUITE(FactorizationConformance, Implementations, ImplName);

TYPED_TEST(FactorizationConformance, SolvesRandomSpdMatrix) {
  auto rng = make_rng(1);
  const SpMat A = random_spd(300, 4, rng);
  const Eigen::VectorXd b = Eigen::VectorXd::Random(300);
  ASSERT_EQ(this->f->factorize(A), FactorStatus::Ok);
  EXPECT_EQ(this->f->status(), FactorStatus::Ok);
  EXPECT_EQ(this->f->size(), 300);
  const Eigen::VectorXd x = this->f->solve(b);
  EXPECT_LT(relative_residual(A, x, b), kResidualTol);
  EXPECT_EQ(this->f->counts().analyses, 1);
  EXPECT_EQ(this->f->counts().factorizations, 1);
}

TYPED_TEST(FactorizationConformance, SolvesLaplacianAnd2dAnd3dStiffnessLikeMatrices) {
  const SpMat L2 = test::laplacian_2d(40);
  const Eigen::VectorXd b2 = Eigen::VectorXd::Ones(L2.rows());
  ASSERT_EQ(this->f->factorize(L2), FactorStatus::Ok);
  EXPECT_LT(relative_residual(L2, this->f->solve(b2), b2), kResidualTol);

  // Mass term 0.1: condition number about 5e2.
  const SpMat K = test::elasticity_3d_like(6, 0.1);
  ASSERT_EQ(K.rows(), 3 * 216);
  auto rng = make_rng(2);
  std::normal_distribution<double> normal;
  Eigen::VectorXd b3(K.rows());
  for (Eigen::Index i = 0; i < b3.size(); ++i) b3[i] = normal(rng);
  ASSERT_EQ(this->f->factorize(K), FactorStatus::Ok);
  EXPECT_LT(relative_residual(K, this->f->solve(b3), b3), kResidualTol);

  // The axisymmetric solver's pattern: 2 DOFs per node of a quad grid.
  const SpMat K2 = test::elasticity_2d_like(20, 0.1);
  ASSERT_EQ(K2.rows(), 2 * 400);
  EXPECT_LE(K2.nonZeros(), 18 * K2.rows());
  EXPECT_EQ((K2 - SpMat(K2.transpose())).norm(), 0.0);
  Eigen::VectorXd b4(K2.rows());
  for (Eigen::Index i = 0; i < b4.size(); ++i) b4[i] = normal(rng);
  ASSERT_EQ(this->f->factorize(K2), FactorStatus::Ok);
  EXPECT_LT(relative_residual(K2, this->f->solve(b4), b4), kResidualTol);
  EXPECT_EQ(this->f->counts().analyses, 3);
}

TYPED_TEST(FactorizationConformance, SolvesSeveralRightHandSidesAtOnce) {
  auto rng = make_rng(3);
  const SpMat A = random_spd(200, 5, rng);
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(200, 6);
  ASSERT_EQ(this->f->factorize(A), FactorStatus::Ok);
  const Eigen::MatrixXd X = this->f->solve(B);
  ASSERT_EQ(X.rows(), 200);
  ASSERT_EQ(X.cols(), 6);
  for (Eigen::Index c = 0; c < B.cols(); ++c) {
    EXPECT_LT(relative_residual(A, X.col(c), B.col(c)), kResidualTol) << "column " << c;
    const Eigen::VectorXd xc = this->f->solve(B.col(c));
    EXPECT_LT((xc - X.col(c)).norm(), 1e-14 * X.col(c).norm()) << "column " << c;
  }
  const Eigen::MatrixXd none = this->f->solve(Eigen::MatrixXd(200, 0));
  EXPECT_EQ(none.cols(), 0);
}

TYPED_TEST(FactorizationConformance, ReusesOneAnalysisForManyNumericFactorizations) {
  auto rng = make_rng(4);
  const SpMat A0 = random_spd(250, 4, rng);
  ASSERT_EQ(this->f->analyze(A0), FactorStatus::Ok);
  EXPECT_EQ(this->f->status(), FactorStatus::NotFactored);
  const Eigen::VectorXd b = Eigen::VectorXd::Random(250);
  Eigen::VectorXd previous;
  constexpr int kRounds = 20;
  for (int k = 0; k < kRounds; ++k) {
    const SpMat A = revalue(A0, rng);
    ASSERT_EQ(this->f->factorize(A), FactorStatus::Ok) << "round " << k;
    const Eigen::VectorXd x = this->f->solve(b);
    EXPECT_LT(relative_residual(A, x, b), kResidualTol) << "round " << k;
    if (k > 0) {
      EXPECT_GT((x - previous).norm(), 1e-3 * x.norm()) << "values did not change";
    }
    previous = x;
  }
  EXPECT_EQ(this->f->counts().analyses, 1);
  EXPECT_EQ(this->f->counts().factorizations, kRounds);
}

TYPED_TEST(FactorizationConformance, ReportsIndefiniteMatrixAsNotPositiveDefinite) {
  auto rng = make_rng(5);
  // A negative diagonal entry.
  SpMat A = random_spd(120, 3, rng);
  A.coeffRef(7, 7) = -1.0;
  EXPECT_EQ(this->f->factorize(A), FactorStatus::NotPositiveDefinite);
  EXPECT_EQ(this->f->status(), FactorStatus::NotPositiveDefinite);
  EXPECT_TRUE(test::throws_error([&] { (void)this->f->solve(Eigen::VectorXd::Ones(120)); },
                                 ErrorKind::Internal, {"solve", "not positive definite"}));

  // Positive diagonal, but a 2×2 principal minor [[1, 2], [2, 1]] is negative.
  SpMat B = Eigen::MatrixXd::Identity(50, 50).sparseView();
  B.coeffRef(20, 10) = 2.0;
  B.coeffRef(10, 20) = 2.0;
  EXPECT_EQ(this->f->factorize(B), FactorStatus::NotPositiveDefinite);

  // The object stays usable.
  const SpMat C = random_spd(120, 3, rng);
  const Eigen::VectorXd b = Eigen::VectorXd::Random(120);
  ASSERT_EQ(this->f->factorize(C), FactorStatus::Ok);
  EXPECT_LT(relative_residual(C, this->f->solve(b), b), kResidualTol);
}

TYPED_TEST(FactorizationConformance, AnalysesAgainWhenThePatternChanges) {
  auto rng = make_rng(6);
  const SpMat A = random_spd(150, 3, rng);
  const SpMat B = random_spd(150, 5, rng);  // same size, other pattern
  const SpMat C = random_spd(90, 3, rng);   // other size
  const Eigen::VectorXd b = Eigen::VectorXd::Random(150);
  ASSERT_EQ(this->f->factorize(A), FactorStatus::Ok);
  EXPECT_EQ(this->f->counts().analyses, 1);
  ASSERT_EQ(this->f->factorize(B), FactorStatus::Ok);
  EXPECT_EQ(this->f->counts().analyses, 2);
  EXPECT_LT(relative_residual(B, this->f->solve(b), b), kResidualTol);
  ASSERT_EQ(this->f->factorize(B), FactorStatus::Ok);
  EXPECT_EQ(this->f->counts().analyses, 2);
  ASSERT_EQ(this->f->factorize(C), FactorStatus::Ok);
  EXPECT_EQ(this->f->counts().analyses, 3);
  const Eigen::VectorXd c = Eigen::VectorXd::Random(90);
  EXPECT_LT(relative_residual(C, this->f->solve(c), c), kResidualTol);
  ASSERT_EQ(this->f->factorize(A), FactorStatus::Ok);
  EXPECT_EQ(this->f->counts().analyses, 4);
  EXPECT_LT(relative_residual(A, this->f->solve(b), b), kResidualTol);
  EXPECT_EQ(this->f->counts().factorizations, 5);
}

TYPED_TEST(FactorizationConformance, ReadsOnlyTheLowerTriangle) {
  auto rng = make_rng(7);
  const SpMat A = random_spd(160, 4, rng);
  const Eigen::VectorXd b = Eigen::VectorXd::Random(160);
  ASSERT_EQ(this->f->factorize(A), FactorStatus::Ok);
  const Eigen::VectorXd x_full = this->f->solve(b);
  ASSERT_EQ(this->f->factorize(lower_triangle(A)), FactorStatus::Ok);
  const Eigen::VectorXd x_lower = this->f->solve(b);
  EXPECT_LT((x_full - x_lower).norm(), 1e-13 * x_full.norm());
  // Garbage above the diagonal is ignored.
  SpMat garbage = lower_triangle(A);
  SpMat upper = SpMat(random_spd(160, 2, rng).triangularView<Eigen::StrictlyUpper>()) * 1e3;
  garbage += upper;
  ASSERT_EQ(this->f->factorize(garbage), FactorStatus::Ok);
  EXPECT_LT(relative_residual(A, this->f->solve(b), b), kResidualTol);
}

TYPED_TEST(FactorizationConformance, FactorsDiagonallyShiftedMatrix) {
  auto rng = make_rng(8);
  const SpMat A = random_spd(140, 4, rng);
  const Eigen::VectorXd b = Eigen::VectorXd::Random(140);
  const Eigen::VectorXd d =
      Eigen::VectorXd::Random(140).cwiseAbs() + Eigen::VectorXd::Constant(140, 0.1);
  const double sigma = 3.5;
  ASSERT_EQ(this->f->factorize(A, sigma, d), FactorStatus::Ok);
  SpMat shifted = A;
  for (int i = 0; i < 140; ++i) shifted.coeffRef(i, i) += sigma * d[i];
  EXPECT_LT(relative_residual(shifted, this->f->solve(b), b), kResidualTol);
  // Identity shift.
  ASSERT_EQ(this->f->factorize(A, sigma), FactorStatus::Ok);
  SpMat shifted_identity = A;
  for (int i = 0; i < 140; ++i) shifted_identity.coeffRef(i, i) += sigma;
  EXPECT_LT(relative_residual(shifted_identity, this->f->solve(b), b), kResidualTol);
  // A is not modified and no new analysis was needed.
  ASSERT_EQ(this->f->factorize(A), FactorStatus::Ok);
  EXPECT_LT(relative_residual(A, this->f->solve(b), b), kResidualTol);
  EXPECT_EQ(this->f->counts().analyses, 1);
  // A shift large enough turns an indefinite matrix definite.
  SpMat indefinite = A;
  indefinite.coeffRef(3, 3) = -1.0;
  EXPECT_EQ(this->f->factorize(indefinite), FactorStatus::NotPositiveDefinite);
  EXPECT_EQ(this->f->factorize(indefinite, 2.0 * A.coeff(3, 3)), FactorStatus::Ok);
}

TYPED_TEST(FactorizationConformance, ShiftFillsDiagonalEntriesMissingFromThePattern) {
  // [[0, 1], [1, 0]] repeated: no diagonal entries stored.
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < 10; ++k) {
    t.emplace_back(2 * k + 1, 2 * k, 1.0);
    t.emplace_back(2 * k, 2 * k + 1, 1.0);
  }
  SpMat A(20, 20);
  A.setFromTriplets(t.begin(), t.end());
  EXPECT_NE(this->f->factorize(A), FactorStatus::Ok);
  ASSERT_EQ(this->f->factorize(A, 2.0), FactorStatus::Ok);
  SpMat shifted = A;
  for (int i = 0; i < 20; ++i) shifted.coeffRef(i, i) += 2.0;
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(20, 1.0, 2.0);
  EXPECT_LT(relative_residual(shifted, this->f->solve(b), b), kResidualTol);
}

TYPED_TEST(FactorizationConformance, RejectsNonFiniteInput) {
  auto rng = make_rng(9);
  SpMat A = random_spd(80, 3, rng);
  SpMat bad = A;
  bad.coeffRef(5, 5) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(this->f->factorize(bad), FactorStatus::NonFiniteInput);
  EXPECT_EQ(this->f->factorize(A, std::numeric_limits<double>::infinity()),
            FactorStatus::NonFiniteInput);
  Eigen::VectorXd d = Eigen::VectorXd::Ones(80);
  d[3] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(this->f->factorize(A, 1.0, d), FactorStatus::NonFiniteInput);
  ASSERT_EQ(this->f->factorize(A), FactorStatus::Ok);
  const Eigen::VectorXd b = Eigen::VectorXd::Random(80);
  EXPECT_LT(relative_residual(A, this->f->solve(b), b), kResidualTol);
}

TYPED_TEST(FactorizationConformance, AcceptsUncompressedMatrices) {
  auto rng = make_rng(10);
  const SpMat A = random_spd(100, 3, rng);
  SpMat U = A;
  U.uncompress();
  ASSERT_FALSE(U.isCompressed());
  const Eigen::VectorXd b = Eigen::VectorXd::Random(100);
  ASSERT_EQ(this->f->factorize(U), FactorStatus::Ok);
  EXPECT_LT(relative_residual(A, this->f->solve(b), b), kResidualTol);
  ASSERT_EQ(this->f->factorize(A), FactorStatus::Ok);
  EXPECT_EQ(this->f->counts().analyses, 1);
}

TYPED_TEST(FactorizationConformance, ConcurrentSolvesAgreeWithOneMultiColumnSolve) {
  const SpMat A = test::elasticity_3d_like(5, 0.1);
  const Eigen::Index n = A.rows();
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(n, 16);
  ASSERT_EQ(this->f->factorize(A), FactorStatus::Ok);
  const Eigen::MatrixXd X = this->f->solve(B);
  Eigen::MatrixXd Y(n, 16);
  tbb::parallel_for(0, 16, [&](int c) { Y.col(c) = this->f->solve(B.col(c)); });
  EXPECT_LT((X - Y).norm(), 1e-14 * X.norm());
  EXPECT_LT(relative_residual(A, X, B), kResidualTol);
}

TYPED_TEST(FactorizationConformance, MisuseIsAnInternalError) {
  EXPECT_TRUE(test::throws_error([&] { (void)this->f->solve(Eigen::VectorXd::Ones(4)); },
                                 ErrorKind::Internal, {"not factored"}));
  auto rng = make_rng(12);
  const SpMat A = random_spd(30, 2, rng);
  ASSERT_EQ(this->f->factorize(A), FactorStatus::Ok);
  EXPECT_TRUE(test::throws_error([&] { (void)this->f->solve(Eigen::VectorXd::Ones(29)); },
                                 ErrorKind::Internal, {"29 rows", "expected 30"}));
  EXPECT_TRUE(
      test::throws_error([&] { (void)this->f->factorize(A, 1.0, Eigen::VectorXd::Ones(3)); },
                         ErrorKind::Internal, {"3 entries"}));
  EXPECT_TRUE(test::throws_error([&] { (void)this->f->factorize(SpMat(3, 4)); },
                                 ErrorKind::Internal, {"3x4"}));
}

// --- implementation-specific behaviour ---------------------------------------

TEST(SparseCholesky, MethodSelectsSupernodalOrSimplicialFactor) {
  const SpMat K = test::elasticity_3d_like(6);
  SparseCholesky super(SparseCholesky::Method::Supernodal);
  SparseCholesky simple(SparseCholesky::Method::Simplicial);
  ASSERT_EQ(super.factorize(K), FactorStatus::Ok);
  ASSERT_EQ(simple.factorize(K), FactorStatus::Ok);
  EXPECT_TRUE(super.is_supernodal());
  EXPECT_FALSE(simple.is_supernodal());
  // Same ordering, so the same fill; both at least the lower triangle of K.
  EXPECT_GE(super.factor_nonzeros(), static_cast<double>(lower_triangle(K).nonZeros()));
  EXPECT_DOUBLE_EQ(super.factor_nonzeros(), simple.factor_nonzeros());
  EXPECT_GT(super.factor_flops(), 0.0);
}

TEST(SparseCholesky, AutoPicksSimplicialForSparseFactorsAndSupernodalForDenseOnes) {
  SparseCholesky chol;
  // 2D Laplacian, 128²: about 130 flops per nonzero of L.
  ASSERT_EQ(chol.analyze(test::laplacian_2d(128)), FactorStatus::Ok);
  EXPECT_LT(chol.factor_flops() / chol.factor_nonzeros(), 170.0);
  EXPECT_FALSE(chol.is_supernodal());
  // 3D stiffness-like, 12³ nodes: about 580 flops per nonzero of L.
  ASSERT_EQ(chol.analyze(test::elasticity_3d_like(12)), FactorStatus::Ok);
  EXPECT_GT(chol.factor_flops() / chol.factor_nonzeros(), 170.0);
  EXPECT_TRUE(chol.is_supernodal());
}

TEST(SparseLdlt, AllowIndefiniteFactorsMatrixWithOneNegativeEigenvalue) {
  auto rng = make_rng(13);
  SpMat A = random_spd(120, 3, rng);
  // Row/column 0 replaced by a negative diagonal: the rest stays diagonally
  // dominant (positive definite), so by interlacing exactly one eigenvalue < 0.
  A.coeffRef(0, 0) = -1.0;
  SparseLdlt ldlt(SparseLdlt::Definiteness::AllowIndefinite);
  ASSERT_EQ(ldlt.factorize(A), FactorStatus::Ok);
  EXPECT_EQ(ldlt.negative_pivots(), 1);
  const Eigen::VectorXd b = Eigen::VectorXd::Random(120);
  EXPECT_LT(relative_residual(A, ldlt.solve(b), b), kResidualTol);

  // A singular matrix (a zero row and column) is reported, not solved.
  SpMat S = random_spd(40, 2, rng);
  S = SpMat(S.triangularView<Eigen::Lower>());
  S.prune([](const Eigen::Index& row, const Eigen::Index& col, const double&) {
    return row != 0 && col != 0;
  });
  EXPECT_EQ(ldlt.factorize(S), FactorStatus::Singular);
}

}  // namespace
}  // namespace palpa
