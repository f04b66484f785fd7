// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/input_file.hpp"

#include <gtest/gtest.h>

#include "common/test_support.hpp"

namespace palpa {
namespace {

TEST(InputFile, ReadsARegularFileWhole) {
  test::ScratchDir dir;
  const std::string bytes("a\0b\r\nc", 6);
  dir.write("f.bin", bytes);
  EXPECT_EQ(read_input_file(dir / "f.bin"), bytes);
  dir.write("empty", "");
  EXPECT_EQ(read_input_file(dir / "empty"), "");
}

// A device never ends (/dev/zero once ran until memory was exhausted): only
// regular files are read.
TEST(InputFile, RefusesDevicesFoldersAndMissingFilesByName) {
  test::ScratchDir dir;
  EXPECT_TRUE(test::throws_error([] { read_input_file("/dev/zero"); }, ErrorKind::Input,
                                 {"/dev/zero", "is not a regular file"}));
  EXPECT_TRUE(test::throws_error([&] { read_input_file(dir.path()); }, ErrorKind::Input, {"is a folder"}));
  EXPECT_TRUE(test::throws_error([&] { read_input_file(dir / "none.csv"); }, ErrorKind::Input,
                                 {"none.csv", "file not found"}));
}

}  // namespace
}  // namespace palpa
