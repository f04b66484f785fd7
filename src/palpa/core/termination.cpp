// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/termination.hpp"

#include <fmt/format.h>

#include <array>
#include <utility>

namespace palpa {

namespace {

constexpr std::array<std::pair<Termination, std::string_view>, 5> kNames{{
    {Termination::Converged, "converged"},
    {Termination::IterationLimit, "iteration_limit"},
    {Termination::NoProgress, "no_progress"},
    {Termination::Failed, "failed"},
    {Termination::NotRun, "not_run"},
}};

}  // namespace

std::string_view to_string(Termination t) noexcept {
  for (const auto& [value, name] : kNames) {
    if (value == t) return name;
  }
  return "failed";
}

Termination parse_termination(std::string_view text, const ErrorContext& where) {
  for (const auto& [value, name] : kNames) {
    if (name == text) return value;
  }
  throw_input_error(fmt::format("unknown termination '{}'", text), where,
                    "converged, iteration_limit, no_progress, failed or not_run");
}

}  // namespace palpa
