// SPDX-License-Identifier: AGPL-3.0-or-later
#include <gtest/gtest.h>

#include "palpa/core/text.hpp"

namespace palpa {
namespace {

TEST(Text, ParseFiniteDoubleIsStrict) {
  EXPECT_EQ(parse_finite_double(" 1.5 "), 1.5);
  EXPECT_EQ(parse_finite_double("+2e-3"), 2e-3);
  EXPECT_EQ(parse_finite_double("-7"), -7.0);
  EXPECT_FALSE(parse_finite_double(""));
  EXPECT_FALSE(parse_finite_double("1.5x"));
  EXPECT_FALSE(parse_finite_double("nan"));
  EXPECT_FALSE(parse_finite_double("NaN"));
  EXPECT_FALSE(parse_finite_double("inf"));
  EXPECT_FALSE(parse_finite_double("-Infinity"));
  EXPECT_FALSE(parse_finite_double("1e400"));
  EXPECT_FALSE(parse_finite_double("+-1"));
  EXPECT_FALSE(parse_finite_double("1,5"));
}

TEST(Text, ParseIntegerIsStrict) {
  EXPECT_EQ(parse_integer("42"), 42);
  EXPECT_EQ(parse_integer("-3"), -3);
  EXPECT_FALSE(parse_integer("4.2"));
  EXPECT_FALSE(parse_integer("x"));
  EXPECT_FALSE(parse_integer("99999999999999999999999"));
}

TEST(Text, SplitKeepsEmptyFields) {
  const auto f = split("a,,b", ',');
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f[1], "");
  EXPECT_EQ(split_whitespace("  a \t b\r\n").size(), 2u);
  EXPECT_EQ(trim(" \t x \r\n"), "x");
}

}  // namespace
}  // namespace palpa
