// SPDX-License-Identifier: AGPL-3.0-or-later
// The fuzzed parsers on the inputs kept in fuzz/: the seed corpus (bundled
// and hand-made files, which must read) and the regression corpus (inputs
// that once crashed, hung or leaked, which must now read or be refused with
// palpa::Error, quickly).
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <sstream>
#include <string>

#include "common/test_support.hpp"
#include "targets.hpp"

namespace palpa {
namespace {

std::filesystem::path fuzz_dir() { return test::source_path("fuzz"); }

TEST(FuzzTargets, EveryTargetHasAProgramAndASeedCorpusThatReads) {
  std::istringstream names(PALPA_FUZZ_TARGET_NAMES);
  std::string name;
  std::size_t programs = 0;
  while (std::getline(names, name, ',')) {
    ++programs;
    EXPECT_NE(fuzz::find_target(name), nullptr) << name << " has a program but no target";
  }
  EXPECT_EQ(programs, fuzz::targets().size()) << "fuzz/CMakeLists.txt and targets() list different targets";
  for (const auto& t : fuzz::targets()) {
    const auto seeds = fuzz_dir() / "corpus" / t.name;
    ASSERT_TRUE(std::filesystem::is_directory(seeds)) << seeds;
    std::size_t n = 0;
    for (const auto& e : std::filesystem::directory_iterator(seeds)) {
      const std::string bytes = test::read_text(e.path());
      // The seeds are good files: a reader that refuses one has regressed.
      // The files they name beside them are the targets' companions.
      std::string refusal;
      EXPECT_TRUE(fuzz::run_target(t, bytes.data(), bytes.size(), &refusal)) << e.path() << ": " << refusal;
      ++n;
    }
    EXPECT_GE(n, 1u) << t.name << " has no seed";
  }
}

TEST(FuzzTargets, RegressionInputsAreReadOrRefusedQuickly) {
  const auto root = fuzz_dir() / "regressions";
  if (!std::filesystem::exists(root)) GTEST_SKIP() << "no regression inputs yet";
  for (const auto& dir : std::filesystem::directory_iterator(root)) {
    const fuzz::Target* t = fuzz::find_target(dir.path().filename().string());
    ASSERT_NE(t, nullptr) << dir.path() << " is no target's folder";
    for (const auto& e : std::filesystem::directory_iterator(dir.path())) {
      const std::string bytes = test::read_text(e.path());
      const auto start = std::chrono::steady_clock::now();
      EXPECT_NO_THROW(fuzz::run_target(*t, bytes.data(), bytes.size())) << e.path();
      // A hang found by the fuzzer (> 1 s there) must be gone; the sanitizer
      // build is a few times slower than the fuzzer's.
      EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0) << e.path();
    }
  }
}

}  // namespace
}  // namespace palpa
