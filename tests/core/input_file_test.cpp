// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/input_file.hpp"

#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "palpa/core/atomic_file.hpp"

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

// With the guard on (as in every palpa run), an output that would replace a
// file read as an input is refused, whatever path names it; state the run
// reads and rewrites is not an input; a file that took an input's path later
// is a new file.
TEST(InputFile, TheGuardRefusesAnOutputOverAnInputUnderAnyName) {
  test::ScratchDir dir;
  guard_inputs(true);
  const auto input = dir.write("material.json", "{}");
  const auto state = dir.write("checkpoint.json", "{}");
  const auto other = dir.write("other.json", "{}");
  std::filesystem::create_symlink(input, dir / "link.json");
  std::filesystem::create_hard_link(input, dir / "hard.json");
  read_input_file(dir / "link.json");
  read_input_file(state, InputUse::RunState);
  for (const auto& target : {input, dir / "link.json", dir / "hard.json"}) {
    EXPECT_TRUE(test::throws_error([&] { AtomicFile f(target); }, ErrorKind::Input,
                                   {target.filename().string(), "is one of this run's inputs"}))
        << target;
  }
  EXPECT_EQ(test::read_text(input), "{}");
  EXPECT_NO_THROW(write_file_atomic(state, [](std::ostream& o) { o << "{\"step\": 1}"; }));
  EXPECT_NO_THROW(write_file_atomic(other, [](std::ostream& o) { o << "[]"; }));
  std::filesystem::remove(dir / "hard.json");
  std::filesystem::remove(dir / "link.json");
  std::filesystem::remove(input);
  dir.write("material.json", "{\"new\": 1}");  // not the file that was read
  EXPECT_NO_THROW(write_file_atomic(input, [](std::ostream& o) { o << "{}"; }));
  guard_inputs(false);
  read_input_file(other);
  EXPECT_NO_THROW(write_file_atomic(other, [](std::ostream& o) { o << "{}"; }));
}

}  // namespace
}  // namespace palpa
