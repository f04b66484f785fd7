// SPDX-License-Identifier: AGPL-3.0-or-later
// parallel_for_each_index: every iteration once; a throw cancels no loop nested
// in another iteration (a cancelled tbb::parallel_for returns as if it had
// finished, and the iteration around it would read results that never were);
// the error rethrown is the interrupt, else the lowest index's.
#include "palpa/core/parallel.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include "palpa/core/error.hpp"
#include "palpa/core/interrupt.hpp"

namespace palpa {
namespace {

TEST(ParallelForEachIndex, RunsEveryIterationOnce) {
  std::vector<std::atomic<int>> runs(1000);
  parallel_for_each_index(runs.size(), [&](std::size_t i) { ++runs[i]; });
  for (const auto& r : runs) EXPECT_EQ(r.load(), 1);
  parallel_for_each_index(0, [](std::size_t) { FAIL() << "no iteration in an empty loop"; });
}

// Outer iterations each run a nested loop and then read all of its results,
// as fit_modulus does inside the depth search. One nested iteration throws
// while the others are running: every outer iteration that returns has seen
// its nested loop complete, and the throw comes out of the outer loop.
TEST(ParallelForEachIndex, AFailureCancelsNoNestedLoop) {
  constexpr std::size_t kOuter = 8, kInner = 32;
  for (int round = 0; round < 5; ++round) {
    std::atomic<int> partial{0}, finished{0};
    try {
      parallel_for_each_index(kOuter, [&](std::size_t i) {
        std::vector<char> done(kInner, 0);
        parallel_for_each_index(kInner, [&](std::size_t j) {
          std::this_thread::sleep_for(std::chrono::microseconds(200));
          if (i == 3 && j == 5) throw std::runtime_error("inner failure");
          done[j] = 1;
        });
        for (char c : done) partial += c ? 0 : 1;
        ++finished;
      });
      ADD_FAILURE() << "the failure did not come out";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "inner failure");
    }
    EXPECT_EQ(partial.load(), 0)
        << "an outer iteration read a nested loop that was cancelled (round " << round << ")";
    EXPECT_LT(finished.load(), static_cast<int>(kOuter));
  }
}

TEST(ParallelForEachIndex, TheInterruptComesFirstThenTheLowestIndex) {
  std::vector<std::exception_ptr> errors(4);
  EXPECT_NO_THROW(rethrow_first(errors));
  errors[3] = std::make_exception_ptr(std::runtime_error("three"));
  errors[1] = std::make_exception_ptr(std::runtime_error("one"));
  try {
    rethrow_first(errors);
    ADD_FAILURE() << "no rethrow";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "one");
  }
  errors[2] = std::make_exception_ptr(Error(ErrorKind::Interrupted, "interrupted"));
  try {
    rethrow_first(errors);
    ADD_FAILURE() << "no rethrow";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Interrupted);
  }
}

TEST(Interrupt, AtTheNthCheck) {
  request_interrupt_at_check(3);
  EXPECT_NO_THROW(check_interrupt());
  EXPECT_NO_THROW(check_interrupt());
  EXPECT_THROW(check_interrupt(), Error);
  EXPECT_TRUE(interrupt_requested());
  clear_interrupt();
  EXPECT_FALSE(interrupt_requested());
  request_interrupt_at_check(2);
  clear_interrupt();  // disarms the countdown
  for (int i = 0; i < 4; ++i) EXPECT_NO_THROW(check_interrupt());
}

}  // namespace
}  // namespace palpa
