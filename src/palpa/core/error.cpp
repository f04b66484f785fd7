// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/error.hpp"

#include "palpa/core/interrupt.hpp"

#include <fmt/format.h>

namespace palpa {

std::string format_error_message(const ErrorContext& context, const std::string& problem,
                                 const std::string& expected) {
  std::string out;
  if (!context.file.empty()) {
    out += context.file;
    if (context.line > 0) {
      out += fmt::format(":{}", context.line);
      if (context.column > 0) out += fmt::format(":{}", context.column);
    }
    out += ": ";
  } else if (context.line > 0) {
    out += fmt::format("line {}: ", context.line);
  }
  if (!context.field.empty()) out += fmt::format("{}: ", context.field);
  out += problem;
  if (!expected.empty()) out += fmt::format(" (expected {})", expected);
  return out;
}

Error::Error(ErrorKind kind, std::string what, ErrorContext context, std::string expected)
    : std::runtime_error(format_error_message(context, what, expected)),
      kind_(kind),
      context_(std::move(context)),
      problem_(std::move(what)),
      expected_(std::move(expected)) {}

int exit_code(ErrorKind kind) noexcept {
  switch (kind) {
    case ErrorKind::Input:
      return kExitInput;
    case ErrorKind::Solver:
      return kExitSolver;
    case ErrorKind::Interrupted:
      return interrupt_exit_code();
    case ErrorKind::Internal:
      return kExitInternal;
  }
  return kExitInternal;
}

void throw_input_error(std::string what, ErrorContext context, std::string expected) {
  throw Error(ErrorKind::Input, std::move(what), std::move(context), std::move(expected));
}

void throw_solver_error(std::string what, ErrorContext context) {
  throw Error(ErrorKind::Solver, std::move(what), std::move(context));
}

}  // namespace palpa
