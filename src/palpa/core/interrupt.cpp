// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/interrupt.hpp"

#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "palpa/core/error.hpp"

namespace palpa {

namespace {
// The one piece of process-wide mutable state palpa has: a signal can only
// communicate through a lock-free flag.
volatile std::sig_atomic_t g_interrupted = 0;
volatile std::sig_atomic_t g_signal = SIGINT;
std::atomic<long> g_checks_left{0};  // request_interrupt_at_check's countdown (0: off)

// When the first signal came [s, CLOCK_MONOTONIC]; written and read by the
// handler only (clock_gettime is async-signal-safe).
double g_first_signal_seconds = 0.0;

double monotonic_seconds() noexcept {
  timespec t{};
  ::clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

extern "C" void palpa_on_signal(int sig) {
  // A second Ctrl-C kills at once. A repeated SIGTERM does not: process
  // managers send it to the process and to its group at the same moment, and
  // the watchdog ends the run within the grace period anyway. Nor does a
  // SIGINT within 0.2 s of the first: the same signal sent to the process and
  // its group (`timeout -s INT`, `kill -INT 0`), not a person's second Ctrl-C.
  if (g_interrupted != 0 && sig == SIGINT && monotonic_seconds() - g_first_signal_seconds > 0.2) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  if (g_interrupted != 0) return;
  g_first_signal_seconds = monotonic_seconds();
  g_signal = sig;
  g_interrupted = 1;
}

struct Temporaries {
  std::mutex mutex;
  std::set<std::string> paths;
  std::map<std::size_t, std::function<void()>> tidy;
  std::size_t next_tidy = 0;
};

Temporaries& temporaries() {
  static Temporaries* t = new Temporaries;  // never destroyed: the watchdog may outlive main
  return *t;
}

// Waits for an interrupt, gives the cooperative path its grace period, then
// ends the process itself.
void watchdog() {
  using Clock = std::chrono::steady_clock;
  while (g_interrupted == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const auto deadline = Clock::now() + std::chrono::duration<double>(kInterruptGraceSeconds);
  while (Clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  if (g_interrupted == 0) return;  // cleared by a test
  {
    Temporaries& t = temporaries();
    std::lock_guard lock(t.mutex);
    for (const std::string& p : t.paths) std::remove(p.c_str());
    // The last registered first, as destructors run (a nested folder before its parent).
    for (auto it = t.tidy.rbegin(); it != t.tidy.rend(); ++it) it->second();
  }
  std::fprintf(stderr,
               "palpa: interrupted; stopped at once, inside a step that does not check for interrupts: no partial "
               "output was written (finished files and checkpoints are kept)\n");
  std::fflush(stderr);
  std::_Exit(interrupt_exit_code());
}
}  // namespace

void install_interrupt_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    std::signal(SIGINT, palpa_on_signal);
    std::signal(SIGTERM, palpa_on_signal);
    // Past a file-size limit (ulimit -f) a write fails (EFBIG) and is
    // reported as any failed write, its temporaries removed, instead of the
    // signal ending the run with them left behind.
    std::signal(SIGXFSZ, SIG_IGN);
    std::thread(watchdog).detach();
  });
}

int interrupt_exit_code() noexcept { return 128 + static_cast<int>(g_signal); }

void register_temporary(const std::string& path) {
  Temporaries& t = temporaries();
  std::lock_guard lock(t.mutex);
  t.paths.insert(path);
}

void unregister_temporary(const std::string& path) {
  Temporaries& t = temporaries();
  std::lock_guard lock(t.mutex);
  t.paths.erase(path);
}

std::size_t register_forced_exit_tidy(std::function<void()> tidy) {
  Temporaries& t = temporaries();
  std::lock_guard lock(t.mutex);
  t.tidy.emplace(t.next_tidy, std::move(tidy));
  return t.next_tidy++;
}

void unregister_forced_exit_tidy(std::size_t handle) {
  Temporaries& t = temporaries();
  std::lock_guard lock(t.mutex);
  t.tidy.erase(handle);
}

bool interrupt_requested() noexcept { return g_interrupted != 0; }

void check_interrupt() {
  if (g_checks_left.load(std::memory_order_relaxed) > 0 && g_checks_left.fetch_sub(1) == 1) request_interrupt();
  if (g_interrupted != 0) {
    throw Error(ErrorKind::Interrupted, "interrupted");
  }
}

void request_interrupt() noexcept {
  g_signal = SIGINT;
  g_interrupted = 1;
}
void clear_interrupt() noexcept {
  g_checks_left = 0;
  g_interrupted = 0;
}
void request_interrupt_at_check(long n) noexcept { g_checks_left = std::max(n, 1L); }

}  // namespace palpa
