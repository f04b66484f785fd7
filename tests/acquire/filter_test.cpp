// SPDX-License-Identifier: AGPL-3.0-or-later
// The Butterworth design against its analytic magnitude, and filtfilt's zero
// phase, squared magnitude and edge handling.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/test_support.hpp"
#include "palpa/acquire/filter.hpp"

namespace palpa::acquire {
namespace {

TEST(Butterworth, MatchesTheAnalyticMagnitudeForEveryOrder) {
  const double rate = 1000.0;
  for (int order = 1; order <= 8; ++order) {
    for (double cutoff : {2.0, 5.0, 40.0, 300.0}) {
      const auto sections = butterworth_lowpass(order, cutoff, rate);
      EXPECT_EQ(sections.size(), static_cast<std::size_t>((order + 1) / 2));
      for (double f : {0.0, 0.5 * cutoff, cutoff, 1.7 * cutoff, 0.45 * rate}) {
        const double got = std::abs(frequency_response(sections, 2.0 * std::numbers::pi * f / rate));
        const double want = butterworth_magnitude(order, cutoff, rate, f);
        EXPECT_NEAR(got, want, 1e-9 * std::max(1.0, want)) << "order " << order << " fc " << cutoff << " f " << f;
      }
      // Half power at the cut-off, unit gain at DC.
      EXPECT_NEAR(std::abs(frequency_response(sections, 2.0 * std::numbers::pi * cutoff / rate)), std::sqrt(0.5), 1e-9);
      EXPECT_NEAR(std::abs(frequency_response(sections, 0.0)), 1.0, 1e-10);
    }
  }
}

TEST(Butterworth, RefusesACutoffAtOrAboveNyquist) {
  EXPECT_TRUE(test::throws_error([] { butterworth_lowpass(4, 500.0, 1000.0); }, ErrorKind::Input,
                                 {"--cutoff", "Nyquist"}));
  EXPECT_TRUE(test::throws_error([] { butterworth_lowpass(4, 0.0, 1000.0); }, ErrorKind::Input, {"--cutoff"}));
  EXPECT_TRUE(test::throws_error([] { butterworth_lowpass(13, 5.0, 1000.0); }, ErrorKind::Input, {"--order"}));
}

TEST(Filtfilt, HasZeroPhaseAndTheSquaredMagnitude) {
  const double rate = 500.0, cutoff = 10.0;
  const auto sections = butterworth_lowpass(4, cutoff, rate);
  for (double f : {3.0, 8.0, 10.0, 14.0}) {
    std::vector<double> x(5000);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(2.0 * std::numbers::pi * f * i / rate);
    const auto y = filtfilt(sections, x);
    // Least-squares fit of a sin + b cos over the middle part: amplitude and phase.
    double ss = 0, sc = 0, cc = 0, ys = 0, yc = 0;
    for (std::size_t i = 1000; i < 4000; ++i) {
      const double s = std::sin(2.0 * std::numbers::pi * f * i / rate), c = std::cos(2.0 * std::numbers::pi * f * i / rate);
      ss += s * s;
      sc += s * c;
      cc += c * c;
      ys += y[i] * s;
      yc += y[i] * c;
    }
    const double det = ss * cc - sc * sc;
    const double a = (ys * cc - yc * sc) / det, b = (yc * ss - ys * sc) / det;
    const double h = butterworth_magnitude(4, cutoff, rate, f);
    EXPECT_NEAR(a, h * h, 1e-6) << f;  // |H|², in phase
    EXPECT_NEAR(b, 0.0, 1e-6) << f;    // no quadrature part: zero phase
  }
}

TEST(Filtfilt, KeepsConstantsExactlyAndLinearTrendsAtTheEnds) {
  const auto sections = butterworth_lowpass(4, 5.0, 1000.0);
  const std::vector<double> c(300, 2.5);
  for (double v : filtfilt(sections, c)) EXPECT_NEAR(v, 2.5, 1e-10);
  std::vector<double> ramp(3000);
  for (std::size_t i = 0; i < ramp.size(); ++i) ramp[i] = 0.1 + 0.002 * static_cast<double>(i);
  const auto y = filtfilt(sections, ramp);
  for (std::size_t i = 0; i < ramp.size(); ++i) EXPECT_NEAR(y[i], ramp[i], 1e-4) << i;  // the ramp spans 6
  // A step well inside: the filtered step is symmetric about its middle (zero phase).
  std::vector<double> step(2000, 0.0);
  for (std::size_t i = 1000; i < step.size(); ++i) step[i] = 1.0;
  const auto s = filtfilt(sections, step);
  for (std::size_t k = 1; k < 200; ++k) EXPECT_NEAR(s[999 - k] + s[1000 + k], 1.0, 1e-6) << k;
}

TEST(Filtfilt, PadsAsLongAsTheSlowestPoleNeeds) {
  const auto slow = butterworth_lowpass(4, 5.0, 1000.0);
  const auto fast = butterworth_lowpass(4, 100.0, 1000.0);
  EXPECT_GT(filtfilt_padding(slow, 100000), 300u);
  EXPECT_LT(filtfilt_padding(fast, 100000), 60u);
  EXPECT_EQ(filtfilt_padding(slow, 50), 49u);
}

}  // namespace
}  // namespace palpa::acquire
