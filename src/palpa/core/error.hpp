// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// palpa's error type. Three channels (see the style notes):
//  - programmer errors: assert;
//  - bad user input (files, options, values): palpa::Error with kind Input, naming
//    the file, line/column or field and what was expected;
//  - numerical failure (no convergence, singular system): kind Solver, with
//    diagnostics in the message.
// The command line turns each kind into one message on stderr and a distinct exit
// code (exit_code()).

#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

namespace palpa {

enum class ErrorKind {
  Input,        // bad input: file, option, value, unit, mesh
  Solver,       // numerical failure: non-convergence, singular or indefinite system
  Internal,     // a bug in palpa
  Interrupted,  // the user asked to stop (Ctrl-C, SIGTERM)
};

// Where an error happened. Every member is optional; message() prints those set.
struct ErrorContext {
  std::string file;        // path of the file being read or written
  std::size_t line = 0;    // 1-based line (0: not known)
  std::size_t column = 0;  // 1-based column (0: not known)
  std::string field;       // CSV column name, JSON field path, option name, ...

  ErrorContext& at_line(std::size_t l) {
    line = l;
    return *this;
  }
  ErrorContext& with_field(std::string f) {
    field = std::move(f);
    return *this;
  }
};

// The context of a problem with a whole file (no line, column or field).
inline ErrorContext in_file(std::string file) {
  ErrorContext c;
  c.file = std::move(file);
  return c;
}

class Error : public std::runtime_error {
 public:
  // what: what is wrong ("'abc' is not a number");
  // expected: what would have been accepted ("a finite number") — may be empty.
  Error(ErrorKind kind, std::string what, ErrorContext context = {}, std::string expected = {});

  ErrorKind kind() const noexcept { return kind_; }
  const ErrorContext& context() const noexcept { return context_; }
  const std::string& problem() const noexcept { return problem_; }
  const std::string& expected() const noexcept { return expected_; }

 private:
  ErrorKind kind_;
  ErrorContext context_;
  std::string problem_;
  std::string expected_;
};

// Full message: "file:line:column: field 'x': problem (expected ...)".
std::string format_error_message(const ErrorContext& context, const std::string& problem,
                                 const std::string& expected);

// Process exit codes of the command line, one per kind.
inline constexpr int kExitOk = 0;
inline constexpr int kExitInternal = 1;
inline constexpr int kExitInput = 2;
inline constexpr int kExitSolver = 3;
inline constexpr int kExitInterrupted = 130;
int exit_code(ErrorKind kind) noexcept;

// Shorthands for the common cases.
[[noreturn]] void throw_input_error(std::string what, ErrorContext context = {},
                                    std::string expected = {});
[[noreturn]] void throw_solver_error(std::string what, ErrorContext context = {});

}  // namespace palpa
