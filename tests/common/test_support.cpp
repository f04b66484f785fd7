// SPDX-License-Identifier: AGPL-3.0-or-later
#include "common/test_support.hpp"

#include <fmt/format.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>

namespace palpa::test {

std::uint64_t test_seed() {
  static const std::uint64_t seed = [] {
    std::uint64_t s = 20261123;
    if (const char* env = std::getenv("PALPA_TEST_SEED")) s = std::strtoull(env, nullptr, 10);
    std::cout << "[palpa] test seed " << s << " (override with PALPA_TEST_SEED)\n";
    return s;
  }();
  return seed;
}

std::mt19937_64 make_rng(std::uint64_t salt) { return std::mt19937_64(test_seed() ^ (salt * 0x9E3779B97F4A7C15ull)); }

ScratchDir::ScratchDir() {
  std::string templ = (std::filesystem::temp_directory_path() / "palpa-test-XXXXXX").string();
  if (mkdtemp(templ.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
  path_ = templ;
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

std::filesystem::path ScratchDir::write(const std::string& name, const std::string& content) const {
  const auto p = path_ / name;
  std::filesystem::create_directories(p.parent_path());
  std::ofstream out(p, std::ios::binary);
  out << content;
  return p;
}

std::size_t ScratchDir::entry_count() const {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(path_)) ++n;
  return n;
}

::testing::AssertionResult throws_error(const std::function<void()>& f, ErrorKind kind,
                                        const std::vector<std::string>& fragments) {
  try {
    f();
  } catch (const Error& e) {
    if (e.kind() != kind) {
      return ::testing::AssertionFailure()
             << "palpa::Error of another kind (" << static_cast<int>(e.kind()) << "): " << e.what();
    }
    const std::string msg = e.what();
    for (const auto& frag : fragments) {
      if (msg.find(frag) == std::string::npos) {
        return ::testing::AssertionFailure() << "message '" << msg << "' lacks '" << frag << "'";
      }
    }
    return ::testing::AssertionSuccess() << msg;
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << "not a palpa::Error: " << e.what();
  }
  return ::testing::AssertionFailure() << "no exception was thrown";
}

std::filesystem::path source_path(const std::string& relative) {
  return std::filesystem::path(PALPA_SOURCE_DIR) / relative;
}

const char* palpa_binary() { return PALPA_BINARY; }

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

CommandResult run_shell(const std::string& command, const std::filesystem::path& cwd) {
  ScratchDir capture;
  const auto out = capture / "stdout";
  const auto err = capture / "stderr";
  std::string cmd;
  if (!cwd.empty()) cmd += fmt::format("cd '{}' && ", cwd.string());
  cmd += fmt::format("{} >'{}' 2>'{}' </dev/null", command, out.string(), err.string());
  const int status = std::system(cmd.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  return r;
}

CommandResult run_palpa(const std::string& args, const std::filesystem::path& cwd) {
  return run_shell(fmt::format("'{}' {}", palpa_binary(), args), cwd);
}

CommandResult run_palpa_mpi(int processes, const std::string& args, const std::filesystem::path& cwd) {
  return run_shell(fmt::format("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np {} "
                               "'{}' {}",
                               processes, palpa_binary(), args),
                   cwd);
}

CommandResult check_page_in_browser(const std::filesystem::path& page) {
  return run_shell(fmt::format("/usr/bin/python3 {} {}", shell_quote(source_path("tests/browser/check_page.py")),
                               shell_quote(page)),
                   {});
}

bool run_palpa_killed_after(const std::string& args, const std::filesystem::path& cwd, double seconds) {
  return run_palpa_signalled_after(args, cwd, seconds, SIGKILL) == 128 + SIGKILL;
}

int run_palpa_signalled_after(const std::string& args, const std::filesystem::path& cwd, double seconds, int signal) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  return run_palpa_signalled_when(args, cwd, [&] { return std::chrono::steady_clock::now() >= deadline; }, signal,
                                  seconds + 1.0);
}

int run_palpa_signalled_when(const std::string& args, const std::filesystem::path& cwd,
                             const std::function<bool()>& ready, int signal, double timeout) {
  const std::string cmd =
      fmt::format("cd '{}' && exec '{}' {} >/dev/null 2>&1 </dev/null", cwd.string(), palpa_binary(), args);
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  if (pid < 0) return -1;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
  int status = 0;
  while (!ready()) {
    if (waitpid(pid, &status, WNOHANG) == pid) return -1;
    if (std::chrono::steady_clock::now() >= deadline) break;
    usleep(2000);
  }
  kill(pid, signal);
  waitpid(pid, &status, 0);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string shell_quote(const std::filesystem::path& p) { return fmt::format("'{}'", p.string()); }

}  // namespace palpa::test
