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
  // Bytes of a file quoted in a message (a NUL would end it where it is
  // printed; other control bytes are invisible) are shown as \xNN.
  std::string shown;
  shown.reserve(out.size());
  for (const char c : out) {
    const auto u = static_cast<unsigned char>(c);
    if ((u < 0x20 && c != '\n' && c != '\t') || u == 0x7f) {
      shown += fmt::format("\\x{:02x}", u);
    } else {
      shown += c;
    }
  }
  return shown;
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
