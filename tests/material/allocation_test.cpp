// SPDX-License-Identifier: AGPL-3.0-or-later
// The inner-loop evaluations allocate nothing: counted with a replaced global
// operator new in this test program only.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "model_fixtures.hpp"
#include "palpa/material/kinematics.hpp"

namespace {
std::atomic<long> g_allocations{0};
}

#if !defined(__SANITIZE_ADDRESS__)
void* operator new(std::size_t n) {
  g_allocations.fetch_add(1);
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#endif

namespace palpa::material {
namespace {

TEST(Allocation, EvaluationsAllocateNothing) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "allocation counting is replaced by the sanitizer's allocator";
#endif
  for (const auto& c : test::all_model_cases()) {
    const auto m = c.make();
    Eigen::MatrixXd work(3, m->num_params());
    Eigen::MatrixXd dp(9, m->num_params());
    Eigen::MatrixXd dpa(5, m->num_params());
    Stress3 s;
    StressAxisym sa;
    const Mat3 F = (Mat3() << 1.1, 0.1, 0.0, -0.05, 0.9, 0.2, 0.0, 0.1, 1.05).finished();
    const Mat2 F2 = (Mat2() << 1.1, 0.1, -0.05, 0.9).finished();
    const long before = g_allocations.load();
    stress(*m, F, EvalOrder::Hessian, PsdProjection::Clamp, s);
    stress(*m, F, EvalOrder::Hessian, PsdProjection::None, s);
    stress_axisymmetric(*m, F2, 1.05, EvalOrder::Hessian, PsdProjection::Clamp, sa);
    dP_dparam(*m, F, work, dp);
    dP_dparam_axisymmetric(*m, F2, 1.05, work, dpa);
    EXPECT_EQ(g_allocations.load() - before, 0) << c.name;
  }
}

}  // namespace
}  // namespace palpa::material
