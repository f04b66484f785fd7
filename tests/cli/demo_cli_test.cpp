// SPDX-License-Identifier: AGPL-3.0-or-later
// `palpa demo` keeps to the output contract (the README test runs the demo
// itself): a non-empty folder is refused without --overwrite.
#include <gtest/gtest.h>

#include "common/test_support.hpp"

namespace palpa {
namespace {

using test::run_palpa;
using test::ScratchDir;

TEST(DemoCli, RefusesANonEmptyFolderWithoutOverwrite) {
  ScratchDir dir;
  std::filesystem::create_directories(dir / "out");
  dir.write("out/summary.txt", "the user's own notes\n");
  const auto r = run_palpa("demo -o out", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("'out' is not empty"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--overwrite"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("--resume"), std::string::npos) << "the demo has no --resume: " << r.err;
  EXPECT_EQ(test::read_text(dir / "out" / "summary.txt"), "the user's own notes\n");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir / "out"), {}), 1);
}

}  // namespace
}  // namespace palpa
