// SPDX-License-Identifier: AGPL-3.0-or-later
#include <gtest/gtest.h>

#include "palpa/core/error.hpp"

namespace palpa {
namespace {

TEST(Error, MessageNamesFileLineFieldAndExpectation) {
  ErrorContext ctx;
  ctx.file = "curve.csv";
  ctx.line = 12;
  ctx.column = 2;
  ctx.field = "column 'force_N'";
  const Error e(ErrorKind::Input, "'abc' is not a number", ctx, "a finite number");
  EXPECT_EQ(std::string(e.what()),
            "curve.csv:12:2: column 'force_N': 'abc' is not a number (expected a finite number)");
  EXPECT_EQ(e.kind(), ErrorKind::Input);
  EXPECT_EQ(e.problem(), "'abc' is not a number");
}

// Bytes of a file quoted in a message are shown: a NUL no longer ends the
// message where it is printed, a carriage return or escape is visible.
TEST(Error, ControlBytesInAMessageAreShown) {
  const Error e(ErrorKind::Input, std::string("'3\0" "4' is not a number\r", 22), ErrorContext{"a.csv", 3, 0, ""},
                "a finite\tnumber\x1b");
  EXPECT_EQ(std::string(e.what()), "a.csv:3: '3\\x004' is not a number\\x0d (expected a finite\tnumber\\x1b)");
}

TEST(Error, MessageWithoutContextIsTheProblemOnly) {
  const Error e(ErrorKind::Solver, "Newton did not converge");
  EXPECT_EQ(std::string(e.what()), "Newton did not converge");
}

TEST(Error, ExitCodesAreDistinctPerKind) {
  EXPECT_EQ(exit_code(ErrorKind::Input), 2);
  EXPECT_EQ(exit_code(ErrorKind::Solver), 3);
  EXPECT_EQ(exit_code(ErrorKind::Internal), 1);
  EXPECT_EQ(exit_code(ErrorKind::Interrupted), 130);
}

TEST(Error, ThrowHelpersSetTheKind) {
  try {
    throw_solver_error("diverged");
    FAIL() << "no throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Solver);
  }
  try {
    throw_input_error("bad", ErrorContext{"f.json", 3, 0, ""});
    FAIL() << "no throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Input);
    EXPECT_EQ(std::string(e.what()), "f.json:3: bad");
  }
}

}  // namespace
}  // namespace palpa
