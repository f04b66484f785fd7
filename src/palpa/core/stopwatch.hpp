// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Wall time of a step, as the logs and results report it.

#include <chrono>

namespace palpa {

using Clock = std::chrono::steady_clock;

// Seconds from t0 to now.
inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace palpa
