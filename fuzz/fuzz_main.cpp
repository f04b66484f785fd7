// SPDX-License-Identifier: AGPL-3.0-or-later
// A libFuzzer program for one target of targets.hpp (PALPA_FUZZ_TARGET).
#include <spdlog/spdlog.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "targets.hpp"

namespace {
const palpa::fuzz::Target* target = nullptr;
}

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  spdlog::set_level(spdlog::level::off);  // readers warn about unlikely units
  target = palpa::fuzz::find_target(PALPA_FUZZ_TARGET);
  if (target == nullptr) {
    std::fprintf(stderr, "palpa fuzz: no target '%s'\n", PALPA_FUZZ_TARGET);
    std::abort();
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  palpa::fuzz::run_target(*target, data, size);
  return 0;
}
