// SPDX-License-Identifier: AGPL-3.0-or-later
// A libFuzzer program for one target of targets.hpp: the one named by the
// compile definition PALPA_FUZZ_TARGET (the fuzz preset's palpa_fuzz_<name>),
// or else by the environment variable of that name (the sanitizer build's
// palpa_fuzz_smoke, one program that the unit tests run on every target).
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
#ifdef PALPA_FUZZ_TARGET
  const char* name = PALPA_FUZZ_TARGET;
#else
  const char* name = std::getenv("PALPA_FUZZ_TARGET");
  if (name == nullptr) name = "";
#endif
  target = palpa::fuzz::find_target(name);
  if (target == nullptr) {
    std::fprintf(stderr, "palpa fuzz: no target '%s' (set PALPA_FUZZ_TARGET)\n", name);
    std::abort();
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  palpa::fuzz::run_target(*target, data, size);
  return 0;
}
