// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Small helpers shared by the benchmarks: repeat a kernel until enough time has
// passed, and print one JSON line per figure.

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <vector>
#include <nlohmann/json.hpp>

namespace palpa::bench {

// Calls `body()` (which does `per_call` units of work) repeatedly for at least
// `min_seconds` and returns the units per second.
template <class Body>
double throughput(Body&& body, double per_call, double min_seconds = 0.4) {
  using clock = std::chrono::steady_clock;
  body();  // warm up
  long calls = 0;
  const auto start = clock::now();
  double elapsed = 0.0;
  while (elapsed < min_seconds) {
    body();
    ++calls;
    elapsed = std::chrono::duration<double>(clock::now() - start).count();
  }
  return per_call * static_cast<double>(calls) / elapsed;
}

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Median wall time of `work`, repeated until 0.3 s were spent (at least 3, at
// most 25 times); `setup` runs untimed before each repetition. A first run
// longer than `long_run` seconds is measured once.
inline double median_seconds(const std::function<void()>& setup, const std::function<void()>& work,
                             double long_run = 1.0) {
  constexpr double kMinSeconds = 0.3;
  constexpr std::size_t kMinReps = 3;
  constexpr std::size_t kMaxReps = 25;
  std::vector<double> t;
  double total = 0.0;
  while (t.size() < kMaxReps && (t.size() < kMinReps || total < kMinSeconds)) {
    setup();
    const auto t0 = std::chrono::steady_clock::now();
    work();
    t.push_back(seconds_since(t0));
    total += t.back();
    if (t.size() == 1 && t.front() > long_run) break;
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

inline void emit(const nlohmann::json& j) { fmt::print("{}\n", j.dump()); }

}  // namespace palpa::bench
