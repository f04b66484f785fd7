// SPDX-License-Identifier: AGPL-3.0-or-later
// The 1D line searches on analytic functions with known minimizers.

#include "palpa/solve/line_search.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace palpa {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// --- Armijo backtracking -----------------------------------------------------

// φ(s) = ½ a s² − s: φ(0) = 0, φ'(0) = −1, minimizer 1/a. With c1 = 1e-4 the
// Armijo condition ½ a s² − s ≤ −1e-4 s holds for s ≤ 2(1 − 1e-4)/a.
LineFunction quadratic(double a) {
  return [a](double s) { return 0.5 * a * s * s - s; };
}

TEST(Backtracking, AcceptsTheFullStepWhenItDecreasesEnough) {
  const LineSearchResult r = backtracking_armijo(quadratic(1.0), 0.0, -1.0);
  EXPECT_TRUE(r.success);
  EXPECT_EQ(r.step, 1.0);
  EXPECT_EQ(r.value, -0.5);
  EXPECT_EQ(r.evaluations, 1);
}

TEST(Backtracking, HalvesUntilArmijoHolds) {
  // a = 10: accepted for s ≤ 0.19998, so s = 1, 0.5, 0.25 fail, 0.125 passes.
  const LineSearchResult r = backtracking_armijo(quadratic(10.0), 0.0, -1.0);
  EXPECT_TRUE(r.success);
  EXPECT_EQ(r.step, 0.125);
  EXPECT_DOUBLE_EQ(r.value, 0.5 * 10.0 * 0.125 * 0.125 - 0.125);
  EXPECT_EQ(r.evaluations, 4);
}

TEST(Backtracking, UsesShrinkFactorAndC1) {
  BacktrackingOptions o;
  o.shrink = 0.1;
  o.c1 = 0.5;
  // a = 3: ½·3 s² − s ≤ −½ s ⇔ s ≤ 1/3: s = 1 fails, s = 0.1 passes.
  const LineSearchResult r = backtracking_armijo(quadratic(3.0), 0.0, -1.0, o);
  EXPECT_TRUE(r.success);
  EXPECT_DOUBLE_EQ(r.step, 0.1);
  EXPECT_EQ(r.evaluations, 2);
}

TEST(Backtracking, ShrinksOutOfAnInadmissibleRegion) {
  // φ = +inf for s > 0.3 (e.g. an inverted element), else the a = 1 quadratic:
  // s = 1 and 0.5 are inadmissible, 0.25 is accepted.
  int infinite = 0;
  const LineFunction phi = [&](double s) {
    if (s > 0.3) {
      ++infinite;
      return kInf;
    }
    return 0.5 * s * s - s;
  };
  const LineSearchResult r = backtracking_armijo(phi, 0.0, -1.0);
  EXPECT_TRUE(r.success);
  EXPECT_EQ(r.step, 0.25);
  EXPECT_EQ(infinite, 2);
  // NaN is treated as inadmissible too.
  const LineFunction nan_beyond = [](double s) {
    return s > 0.3 ? std::numeric_limits<double>::quiet_NaN() : 0.5 * s * s - s;
  };
  EXPECT_EQ(backtracking_armijo(nan_beyond, 0.0, -1.0).step, 0.25);
}

TEST(Backtracking, ReportsFailureWithTheBestSampleOrNothing) {
  BacktrackingOptions o;
  o.max_evaluations = 5;
  // Increasing everywhere despite the claimed slope: nothing below φ(0) = 0.
  const LineSearchResult none = backtracking_armijo([](double s) { return s; }, 0.0, -1.0, o);
  EXPECT_FALSE(none.success);
  EXPECT_EQ(none.step, 0.0);
  EXPECT_EQ(none.value, 0.0);
  EXPECT_EQ(none.evaluations, 5);
  // A decrease too small for Armijo (c1 = 0.9): the best sample is returned.
  o.c1 = 0.9;
  const LineFunction shallow = [](double s) { return -0.1 * s * (1.0 - s); };
  const LineSearchResult best = backtracking_armijo(shallow, 0.0, -1.0, o);
  EXPECT_FALSE(best.success);
  EXPECT_EQ(best.step, 0.5);  // samples 1, .5, .25, .125, .0625: lowest at .5
  EXPECT_DOUBLE_EQ(best.value, -0.025);
}

// --- interval searches (typed over the two methods) --------------------------

struct Golden {
  static LineSearchResult run(const LineFunction& phi, double a, double b,
                              const IntervalOptions& o = {}) {
    return golden_section_minimize(phi, a, b, o);
  }
};
struct Brent {
  static LineSearchResult run(const LineFunction& phi, double a, double b,
                              const IntervalOptions& o = {}) {
    return brent_minimize(phi, a, b, o);
  }
};

template <typename Method>
class IntervalSearch : public ::testing::Test {};
struct MethodName {
  template <typename T>
  static std::string GetName(int) {
    return std::is_same_v<T, Golden> ? "Golden" : "Brent";
  }
};
using Methods = ::testing::Types<Golden, Brent>;
TYPED_TEST_SUITE(IntervalSearch, Methods, MethodName);

// Default tolerance: 1e-8·|s| + 1e-12 on the minimizer's position.
constexpr double kStepTol = 2e-8;

TYPED_TEST(IntervalSearch, FindsTheMinimumOfAQuadratic) {
  const LineSearchResult r =
      TypeParam::run([](double s) { return (s - 0.7) * (s - 0.7) + 2.0; }, 0.0, 2.0);
  EXPECT_TRUE(r.success);
  EXPECT_NEAR(r.step, 0.7, kStepTol);
  EXPECT_NEAR(r.value, 2.0, 1e-14);
}

TYPED_TEST(IntervalSearch, FindsTheMinimumOfAQuartic) {
  // φ = (s − 1.3)⁴ + 0.01 (s − 1.3)²: flat bottom, minimizer 1.3.
  const LineFunction phi = [](double s) {
    const double u = s - 1.3;
    return u * u * u * u + 0.01 * u * u;
  };
  const LineSearchResult r = TypeParam::run(phi, 0.0, 3.0);
  EXPECT_TRUE(r.success);
  // Around a minimum φ is flat to second order: the position is known only to
  // about sqrt(machine epsilon · φ/φ'') relative; 1e-6 holds comfortably.
  EXPECT_NEAR(r.step, 1.3, 1e-6);
}

TYPED_TEST(IntervalSearch, FindsAMinimumAtTheEndOfTheInterval) {
  // Decreasing on [0, 1]: the minimizer is the right end.
  const LineSearchResult r = TypeParam::run([](double s) { return -s; }, 0.0, 1.0);
  EXPECT_TRUE(r.success);
  EXPECT_NEAR(r.step, 1.0, kStepTol);
}

TYPED_TEST(IntervalSearch, StaysInTheAdmissibleRegionOfABarrier) {
  // φ = −3s − ln(0.8 − s), +inf for s ≥ 0.8; minimizer 0.8 − 1/3.
  int inadmissible = 0;
  const LineFunction phi = [&](double s) {
    if (s >= 0.8) {
      ++inadmissible;
      return kInf;
    }
    return -3.0 * s - std::log(0.8 - s);
  };
  const LineSearchResult r = TypeParam::run(phi, 0.0, 2.0);
  EXPECT_TRUE(r.success);
  EXPECT_NEAR(r.step, 0.8 - 1.0 / 3.0, 1e-7);
  EXPECT_TRUE(std::isfinite(r.value));
  EXPECT_GT(inadmissible, 0);  // the search did meet the wall
}

TYPED_TEST(IntervalSearch, ApproachesTheWallWhenTheMinimumIsBeyondIt) {
  // φ = −s, admissible only for s < 0.6: the infimum is at the wall.
  const LineFunction phi = [](double s) { return s < 0.6 ? -s : kInf; };
  IntervalOptions o;
  o.relative_tolerance = 1e-6;
  o.max_evaluations = 200;
  const LineSearchResult r = TypeParam::run(phi, 0.0, 1.0, o);
  EXPECT_LT(r.step, 0.6);
  EXPECT_GT(r.step, 0.6 - 1e-5);
  EXPECT_TRUE(std::isfinite(r.value));
}

TYPED_TEST(IntervalSearch, ShrinksTowardTheStartWhenTheFirstPointsAreInadmissible) {
  // Only s < 0.01 is admissible; there φ = (s − 0.004)².
  const LineFunction phi = [](double s) { return s < 0.01 ? (s - 0.004) * (s - 0.004) : kInf; };
  const LineSearchResult r = TypeParam::run(phi, 0.0, 1.0);
  EXPECT_TRUE(r.success);
  EXPECT_NEAR(r.step, 0.004, 1e-8);
}

TYPED_TEST(IntervalSearch, RespectsTheEvaluationBudgetAndTolerance) {
  int calls = 0;
  const LineFunction phi = [&](double s) {
    ++calls;
    return std::cosh(s - 0.37);
  };
  IntervalOptions loose;
  loose.relative_tolerance = 1e-3;
  loose.absolute_tolerance = 0.0;
  const LineSearchResult r = TypeParam::run(phi, 0.0, 1.0, loose);
  EXPECT_TRUE(r.success);
  EXPECT_NEAR(r.step, 0.37, 2e-3 * 0.37);
  EXPECT_EQ(r.evaluations, calls);
  IntervalOptions tiny_budget;
  tiny_budget.max_evaluations = 4;
  calls = 0;
  const LineSearchResult cut = TypeParam::run(phi, 0.0, 1.0, tiny_budget);
  EXPECT_FALSE(cut.success);
  EXPECT_LE(cut.evaluations, 4);
  EXPECT_EQ(cut.evaluations, calls);
  EXPECT_NEAR(cut.step, 0.37, 0.25);  // still the best point seen
}

TEST(BrentVsGolden, BrentNeedsFarFewerEvaluationsOnSmoothFunctions) {
  const LineFunction phi = [](double s) { return std::exp(s) - 2.0 * s; };  // min at ln 2
  const LineSearchResult brent = brent_minimize(phi, 0.0, 2.0);
  const LineSearchResult golden = golden_section_minimize(phi, 0.0, 2.0);
  EXPECT_NEAR(brent.step, std::log(2.0), 2e-8);
  EXPECT_NEAR(golden.step, std::log(2.0), 2e-8);
  EXPECT_LT(brent.evaluations, golden.evaluations / 2);
}

}  // namespace
}  // namespace palpa
