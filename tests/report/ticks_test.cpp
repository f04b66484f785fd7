// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/report/ticks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/test_support.hpp"
#include "palpa/report/svg_text.hpp"

namespace palpa::report {
namespace {

std::vector<double> values(const AxisTicks& t) {
  std::vector<double> v;
  for (const auto& k : t.major) v.push_back(k.value);
  return v;
}
std::vector<std::string> labels(const AxisTicks& t) {
  std::vector<std::string> v;
  for (const auto& k : t.major) v.push_back(k.label);
  return v;
}
// Tick values equal `expected` to 1e-12 relative.
void expect_values(const AxisTicks& t, const std::vector<double>& expected) {
  const auto v = values(t);
  ASSERT_EQ(v.size(), expected.size()) << ::testing::PrintToString(v);
  for (std::size_t i = 0; i < v.size(); ++i)
    EXPECT_NEAR(v[i], expected[i], 1e-12 * std::max(1.0, std::abs(expected[i]))) << "tick " << i;
}

TEST(ReportTicks, UnitInterval) {
  const AxisTicks t = choose_ticks(0, 1, false);
  expect_values(t, {0, 0.2, 0.4, 0.6, 0.8, 1});
  EXPECT_EQ(labels(t), (std::vector<std::string>{"0", "0.2", "0.4", "0.6", "0.8", "1"}));
  EXPECT_EQ(t.min, 0);
  EXPECT_EQ(t.max, 1);
  EXPECT_TRUE(t.minor.empty());
}

TEST(ReportTicks, SmallValuesGetPlainDecimals) {
  const AxisTicks t = choose_ticks(0.0013, 0.0047, false);
  expect_values(t, {0.001, 0.002, 0.003, 0.004, 0.005});
  EXPECT_EQ(labels(t), (std::vector<std::string>{"0.001", "0.002", "0.003", "0.004", "0.005"}));
  EXPECT_NEAR(t.min, 0.001, 1e-15);
  EXPECT_NEAR(t.max, 0.005, 1e-15);
}

TEST(ReportTicks, RangeAcrossZeroIsWidenedToTicks) {
  const AxisTicks t = choose_ticks(-3, 7, false);
  expect_values(t, {-4, -2, 0, 2, 4, 6, 8});
  EXPECT_EQ(labels(t), (std::vector<std::string>{"\u22124", "\u22122", "0", "2", "4", "6", "8"}));
  EXPECT_EQ(t.min, -4);
  EXPECT_EQ(t.max, 8);
}

TEST(ReportTicks, TenthsReadExactly) {
  // 3 × 0.1 must read "0.3" (not 0.30000000000000004) and be the double 0.3.
  const AxisTicks t = choose_ticks(0.05, 0.48, false);
  expect_values(t, {0, 0.1, 0.2, 0.3, 0.4, 0.5});
  EXPECT_EQ(labels(t)[3], "0.3");
  EXPECT_EQ(t.major[3].value, 0.3);
}

TEST(ReportTicks, ExtremeMagnitudesUseScientificLabels) {
  const AxisTicks small = choose_ticks(1.2e-5, 4.9e-5, false);
  expect_values(small, {1e-5, 2e-5, 3e-5, 4e-5, 5e-5});
  EXPECT_EQ(labels(small)[0], "1\u00d710\u207b\u2075");
  const AxisTicks big = choose_ticks(0, 2.9e6, false);
  expect_values(big, {0, 5e5, 1e6, 1.5e6, 2e6, 2.5e6, 3e6});
  EXPECT_EQ(labels(big), (std::vector<std::string>{"0", "5\u00d710\u2075", "1\u00d710\u2076",
                                                   "1.5\u00d710\u2076", "2\u00d710\u2076",
                                                   "2.5\u00d710\u2076", "3\u00d710\u2076"}));
}

TEST(ReportTicks, LogDecades) {
  const AxisTicks t = choose_ticks(1e-6, 3e-2, true);
  EXPECT_TRUE(t.log);
  expect_values(t, {1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1});
  EXPECT_EQ(labels(t),
            (std::vector<std::string>{"10\u207b\u2076", "10\u207b\u2075", "10\u207b\u2074",
                                      "10\u207b\u00b3", "10\u207b\u00b2", "10\u207b\u00b9"}));
  EXPECT_NEAR(t.min, 1e-6, 1e-21);
  EXPECT_NEAR(t.max, 0.1, 1e-16);
  // Minor ticks 2…9 in each of the 5 decades.
  ASSERT_EQ(t.minor.size(), 40u);
  EXPECT_NEAR(t.minor.front(), 2e-6, 1e-21);
  EXPECT_NEAR(t.minor.back(), 9e-2, 1e-17);
}

TEST(ReportTicks, LogUnderTwoDecadesLabels125) {
  const AxisTicks t = choose_ticks(0.3, 7, true);
  expect_values(t, {0.2, 0.5, 1, 2, 5, 10});
  EXPECT_EQ(labels(t), (std::vector<std::string>{"0.2", "0.5", "1", "2", "5", "10"}));
  for (double m : t.minor) EXPECT_TRUE(m > 0.2 && m < 10) << m;
}

TEST(ReportTicks, LogWellUnderADecadeUsesLinearSteps) {
  const AxisTicks t = choose_ticks(3, 3.5, true);
  EXPECT_TRUE(t.log);
  expect_values(t, {3, 3.1, 3.2, 3.3, 3.4, 3.5});
}

TEST(ReportTicks, LogManyDecadesSkipsDecades) {
  const AxisTicks t = choose_ticks(1e-12, 1e3, true);
  ASSERT_GE(t.major.size(), 5u);
  ASSERT_LE(t.major.size(), 8u);
  EXPECT_LE(t.min, 1e-12);
  EXPECT_GE(t.max, 1e3);
  // Equal steps in the exponent.
  const double step = std::log10(t.major[1].value / t.major[0].value);
  EXPECT_NEAR(step, std::round(step), 1e-9);
  EXPECT_GE(step, 2.0);
  for (std::size_t i = 1; i < t.major.size(); ++i)
    EXPECT_NEAR(std::log10(t.major[i].value / t.major[i - 1].value), step, 1e-9);
}

TEST(ReportTicks, FixedBoundsAreKept) {
  const AxisTicks t = choose_ticks(0.1, 0.2, false, 0.05, 0.95);
  EXPECT_EQ(t.min, 0.05);
  EXPECT_EQ(t.max, 0.95);
  expect_values(t, {0.2, 0.4, 0.6, 0.8});
  const AxisTicks one = choose_ticks(1, 7, false, 0.0, std::nullopt);
  EXPECT_EQ(one.min, 0);
  EXPECT_GE(one.max, 7);
}

TEST(ReportTicks, EqualValuesArePadded) {
  const AxisTicks a = choose_ticks(5, 5, false);
  EXPECT_LT(a.min, 5);
  EXPECT_GT(a.max, 5);
  EXPECT_NEAR(0.5 * (a.min + a.max), 5, 1e-12);
  const AxisTicks z = choose_ticks(0, 0, false);
  EXPECT_EQ(z.min, -1);
  EXPECT_EQ(z.max, 1);
  const AxisTicks l = choose_ticks(3, 3, true);
  EXPECT_LE(l.min, 0.3);
  EXPECT_GE(l.max, 30);
  EXPECT_GE(l.major.size(), 3u);
}

TEST(ReportTicks, RandomRangesGiveNiceEvenTicks) {
  auto rng = test::make_rng(7);
  std::uniform_real_distribution<double> exponent(-9, 9), unit(0, 1);
  for (int trial = 0; trial < 500; ++trial) {
    const double scale = std::pow(10.0, exponent(rng));
    const double a = (unit(rng) - 0.3) * scale;
    const double b = a + (0.05 + unit(rng)) * scale;
    const AxisTicks t = choose_ticks(a, b, false);
    SCOPED_TRACE("range [" + std::to_string(a) + ", " + std::to_string(b) + "]");
    ASSERT_GE(t.major.size(), 4u);
    ASSERT_LE(t.major.size(), 8u);
    EXPECT_LE(t.min, a);
    EXPECT_GE(t.max, b);
    EXPECT_EQ(t.major.front().value, t.min);
    EXPECT_EQ(t.major.back().value, t.max);
    const double step = t.major[1].value - t.major[0].value;
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-6 || std::abs(mantissa - 2) < 1e-6 ||
                std::abs(mantissa - 5) < 1e-6)
        << step;
    for (std::size_t i = 1; i < t.major.size(); ++i)
      EXPECT_NEAR(t.major[i].value - t.major[i - 1].value, step, 1e-9 * step);
    for (const auto& k : t.major) EXPECT_LE(utf8_length(k.label), 10u) << k.label;
  }
}

TEST(ReportTicks, FormatsDecimalsCompactly) {
  EXPECT_EQ(format_decimal(0, -3), "0");
  EXPECT_EQ(format_decimal(3, -1), "0.3");
  EXPECT_EQ(format_decimal(2, -3), "0.002");
  EXPECT_EQ(format_decimal(12345, -2), "123.45");
  EXPECT_EQ(format_decimal(-25, 3), "\u221225000");
  EXPECT_EQ(format_decimal(1500, -3), "1.5");
  EXPECT_EQ(format_decimal(5, -4), "5\u00d710\u207b\u2074");
  EXPECT_EQ(format_decimal(15, -6), "1.5\u00d710\u207b\u2075");
  EXPECT_EQ(format_decimal(1, 5), "1\u00d710\u2075");
  EXPECT_EQ(format_decimal(-12, 9), "\u22121.2\u00d710\u00b9\u2070");
  EXPECT_EQ(format_decimal(5, 0, true), "5\u00d710\u2070");
}

TEST(ReportTicks, RejectsBadRanges) {
  const double nan = std::nan("");
  EXPECT_TRUE(test::throws_error([] { choose_ticks(std::nan(""), 1, false); }, ErrorKind::Input,
                                 {"not a finite interval"}));
  EXPECT_TRUE(test::throws_error([] { choose_ticks(2, 1, false); }, ErrorKind::Input,
                                 {"not a finite interval"}));
  EXPECT_TRUE(test::throws_error([] { choose_ticks(0, 1, true); }, ErrorKind::Input, {"<= 0"}));
  EXPECT_TRUE(test::throws_error([] { choose_ticks(0, 1, false, 1.0, 0.5); }, ErrorKind::Input,
                                 {"not below"}));
  EXPECT_TRUE(test::throws_error([&] { choose_ticks(0, 1, false, nan); }, ErrorKind::Input,
                                 {"not finite"}));
  EXPECT_TRUE(test::throws_error([] { choose_ticks(-1.5e308, 1.5e308, false); }, ErrorKind::Input,
                                 {"too large"}));
}

}  // namespace
}  // namespace palpa::report
