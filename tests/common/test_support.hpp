// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Shared test support: a seeded random generator (the seed is printed and can be
// overridden with PALPA_TEST_SEED), scratch folders, and helpers to assert that
// a call fails with a palpa::Error naming the right place.

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <random>
#include <string>

#include "palpa/core/error.hpp"

namespace palpa::test {

// The seed for this test run: PALPA_TEST_SEED if set, else a fixed default.
// Printed once per test program so a failure can be replayed.
std::uint64_t test_seed();
std::mt19937_64 make_rng(std::uint64_t salt = 0);

// A fresh, empty folder under the system temp dir, removed by the destructor.
class ScratchDir {
 public:
  ScratchDir();
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const noexcept { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  // Writes `content` to a file in the folder (creating the folders its name
  // holds) and returns its path.
  std::filesystem::path write(const std::string& name, const std::string& content) const;
  // Number of entries (files and folders, hidden ones included).
  std::size_t entry_count() const;

 private:
  std::filesystem::path path_;
};

// Runs `f` and checks it throws palpa::Error of `kind` whose message contains
// every string in `fragments`.
::testing::AssertionResult throws_error(const std::function<void()>& f, ErrorKind kind,
                                        const std::vector<std::string>& fragments);

// The whole content of a file ("" if it cannot be read).
std::string read_text(const std::filesystem::path& path);

// Path of a file in the source tree (examples, test data).
std::filesystem::path source_path(const std::string& relative);

// The palpa program the command-line tests run ("palpa-not-built" where the
// build has none).
const char* palpa_binary();

// A path in single quotes, for the command lines of run_palpa.
std::string shell_quote(const std::filesystem::path& p);

// Result of running the palpa binary.
struct CommandResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};
// Runs a /bin/sh command line in `cwd`.
CommandResult run_shell(const std::string& command, const std::filesystem::path& cwd = {});
// Runs `palpa <args>` (args are passed to /bin/sh, quote as needed) in `cwd`.
CommandResult run_palpa(const std::string& args, const std::filesystem::path& cwd = {});
// Runs `mpirun -np <processes> palpa <args>` (Open MPI; allowed as root, as
// CI runs).
CommandResult run_palpa_mpi(int processes, const std::string& args, const std::filesystem::path& cwd = {});

// Starts `palpa <args>` in `cwd` (output discarded) and kills it with SIGKILL
// `seconds` after the start, as a crash or an out-of-memory killer would.
// Returns true if it was killed, false if it had ended by then.
// Opens an HTML page in headless Chromium (tests/browser/check_page.py):
// exit 0 and "ok: ..." on stdout when it is one self-contained file that
// loads with nothing on the browser's console and is not blank; else exit 1
// and why.
CommandResult check_page_in_browser(const std::filesystem::path& page);
bool run_palpa_killed_after(const std::string& args, const std::filesystem::path& cwd, double seconds);
// The same with `signal` (e.g. SIGINT, as Ctrl-C): the exit code palpa gave
// (128 + signal if the signal killed it), or -1 if it had ended by then.
int run_palpa_signalled_after(const std::string& args, const std::filesystem::path& cwd, double seconds, int signal);
// The same, signalled as soon as `ready()` holds (polled every 2 ms), or
// -1 if palpa ends first or `timeout` seconds pass.
int run_palpa_signalled_when(const std::string& args, const std::filesystem::path& cwd,
                             const std::function<bool()>& ready, int signal, double timeout = 600.0);

}  // namespace palpa::test
