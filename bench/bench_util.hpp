#pragma once
// Small helpers shared by the benchmarks: repeat a kernel until enough time has
// passed, and print one JSON line per figure.

#include <fmt/format.h>

#include <chrono>
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

inline void emit(const nlohmann::json& j) { fmt::print("{}\n", j.dump()); }

}  // namespace palpa::bench
