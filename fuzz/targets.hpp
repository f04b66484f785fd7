// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The fuzzed parsers: one target per file format and JSON schema, each a
// function that reads one input file the way palpa's commands do. Shared by
// the libFuzzer programs (fuzz_main.cpp) and by the unit test that replays
// the regression corpus (tests/fuzz), so a crash found once stays fixed.
//
// A target may throw palpa::Error (the input was refused, as it should be);
// anything else escaping it (another exception, a crash, a sanitizer report,
// a hang) is a bug.

#include <filesystem>
#include <string>
#include <vector>

namespace palpa::fuzz {

struct Target {
  std::string name;       // palpa_fuzz_<name>, fuzz/corpus/<name>, fuzz/regressions/<name>
  std::string file_name;  // the input is written to a file of this name (its extension picks the reader)
  void (*read)(const std::filesystem::path& input);
};

const std::vector<Target>& targets();
const Target* find_target(const std::string& name);

// Writes `size` bytes to a file named `file_name` in a folder of this
// process's own, and returns its path.
std::filesystem::path write_input(const std::string& file_name, const void* data, std::size_t size);

// Runs one target on one input: true if it was read, false if refused with
// palpa::Error (its message then goes to `refusal`, if given); anything else
// propagates.
bool run_target(const Target& t, const void* data, std::size_t size, std::string* refusal = nullptr);

}  // namespace palpa::fuzz
