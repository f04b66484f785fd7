// SPDX-License-Identifier: AGPL-3.0-or-later
// Interpolation, poke and plateau detection, clipping runs and clock alignment.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/test_support.hpp"
#include "palpa/acquire/filter.hpp"
#include "palpa/acquire/signal.hpp"

namespace palpa::acquire {
namespace {

// Rest 2 s, a smooth 1.2 s poke of height `height`, rest 2 s, sampled at `rate`,
// starting at t0 on its clock.
Signal protocol(double rate, double t0, double height, double noise, std::uint64_t salt) {
  auto rng = test::make_rng(salt);
  std::normal_distribution<double> unit(0.0, 1.0);
  Signal s;
  for (double t = 0.0; t <= 5.2; t += 1.0 / rate) {
    const double u = std::clamp((t - 2.0) / 1.2, 0.0, 1.0);
    s.t.push_back(t0 + t);
    s.v.push_back(height * 0.5 * (1.0 - std::cos(2.0 * std::numbers::pi * u)) + noise * unit(rng));
  }
  return s;
}

TEST(Signal, CubicInterpolationIsExactOnCubicsAndFollowsATremorALineCutsShort) {
  const Signal s{{0.0, 0.1, 0.35, 0.4, 0.7, 1.0}, {}};
  auto cubic = [](double t) { return 1.0 - t + 2.0 * t * t - 3.0 * t * t * t; };
  std::vector<double> v;
  for (double t : s.t) v.push_back(cubic(t));
  for (double t = 0.0; t <= 1.0; t += 0.01) EXPECT_NEAR(interpolate_cubic(s.t, v, t), cubic(t), 1e-12) << t;
  EXPECT_DOUBLE_EQ(interpolate_cubic(s.t, v, -1.0), v.front());
  EXPECT_DOUBLE_EQ(interpolate_cubic(s.t, v, 2.0), v.back());
  const std::vector<double> t3{0.0, 1.0, 3.0}, v3{0.0, 2.0, 3.0};
  EXPECT_DOUBLE_EQ(interpolate_cubic(t3, v3, 2.0), 2.5);  // linear with three samples
  // ±150 µm at 10 Hz sampled at 50 Hz, anywhere between samples and any phase.
  double worst_cubic = 0.0, worst_line = 0.0;
  for (double phase = 0.0; phase < 6.3; phase += 0.1) {
    std::vector<double> t, x;
    for (int i = 0; i < 50; ++i) {
      t.push_back(i / 50.0);
      x.push_back(150e-6 * std::sin(2.0 * std::numbers::pi * 10.0 * t.back() + phase));
    }
    for (double u = 0.1; u < 0.9; u += 0.001) {
      const double truth = 150e-6 * std::sin(2.0 * std::numbers::pi * 10.0 * u + phase);
      worst_cubic = std::max(worst_cubic, std::abs(interpolate_cubic(t, x, u) - truth));
      worst_line = std::max(worst_line, std::abs(interpolate(t, x, u) - truth));
    }
  }
  EXPECT_NEAR(worst_line, 29e-6, 1e-6);
  EXPECT_LT(worst_cubic, 8e-6);
}

TEST(Signal, InterpolatesAndResamplesLinearDataExactly) {
  const Signal s{{0.0, 0.1, 0.35, 0.4, 1.0}, {1.0, 1.2, 1.7, 1.8, 3.0}};  // v = 1 + 2t
  const Signal r = resample(s, -0.1, 0.05, 25);
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double t = -0.1 + 0.05 * static_cast<double>(i);
    const double want = t < 0.0 ? 1.0 : (t > 1.0 ? 3.0 : 1.0 + 2.0 * t);  // end values outside
    EXPECT_NEAR(r.v[i], want, 1e-12) << t;
    EXPECT_NEAR(interpolate(s.t, s.v, t), want, 1e-12) << t;
  }
  EXPECT_DOUBLE_EQ(median_step(s.t), 0.25);  // steps 0.1, 0.25, 0.05, 0.6
}

TEST(Signal, RanksTiesByTheirMeanRank) {
  const std::vector<double> v{3.0, 1.0, 3.0, 2.0, 3.0};
  const std::vector<double> want{4.0, 1.0, 4.0, 2.0, 4.0};
  EXPECT_EQ(ranks(v), want);
}

TEST(Signal, FindsThePokeBetweenTheRestPlateaus) {
  for (double rate : {50.0, 200.0, 1000.0}) {
    const Signal raw = protocol(rate, 7.0, 8.0, 0.02, static_cast<std::uint64_t>(rate));
    const Signal s = lowpass(raw, 4, 5.0);
    const PokeWindow w = detect_poke(s, {}, "test signal", "--window");
    EXPECT_NEAR(w.peak, 7.0 + 2.6, 0.05) << rate;
    EXPECT_NEAR(w.start, 7.0 + 2.0, 0.2) << rate;  // leaves the rest by 2.5% of the poke
    EXPECT_NEAR(w.end, 7.0 + 3.2, 0.2) << rate;
    EXPECT_GE(w.start, 7.0 + 2.0 - 0.06) << rate;
    EXPECT_LE(w.before.t1, w.start + 1e-9) << rate;
    EXPECT_GE(w.after.t0, w.end - 1e-9) << rate;
    EXPECT_NEAR(w.before.level, 0.0, 0.01) << rate;
    EXPECT_NEAR(w.after.level, 0.0, 0.01) << rate;
    EXPECT_NEAR(w.before.t1 - w.before.t0, 1.0, 2.0 / rate) << rate;
  }
}

TEST(Signal, SaysWhenThereIsNoRestPlateau) {
  // A poke that starts right away: no rest before it.
  Signal s;
  for (double t = 0.0; t <= 4.0; t += 0.01) {
    s.t.push_back(t);
    s.v.push_back(std::sin(std::numbers::pi * std::min(t, 1.5) / 3.0) * (t < 1.5 ? 1.0 : std::max(0.0, 2.5 - t)));
  }
  EXPECT_TRUE(test::throws_error([&] { detect_poke(s, {}, "force log 'f.csv'", "--force-window"); }, ErrorKind::Input,
                                 {"force log 'f.csv'", "no rest plateau found before the poke", "--force-window"}));
  const Signal flat{{0.0, 1.0, 2.0, 3.0, 4.0}, {1.0, 1.0, 1.0, 1.0, 1.0}};
  EXPECT_TRUE(test::throws_error([&] { detect_poke(flat, {}, "laser", "--laser-window"); }, ErrorKind::Input,
                                 {"there is no poke"}));
}

TEST(Signal, TakesAPokeWindowGivenByHand) {
  const Signal s = lowpass(protocol(100.0, 0.0, 3.0, 0.0, 1), 4, 5.0);
  const PokeWindow w = poke_from_window(s, 1.9, 3.3, 1.0, "force", "--force-window");
  EXPECT_TRUE(w.manual);
  EXPECT_NEAR(w.peak, 2.6, 0.011);
  EXPECT_NEAR(w.before.t0, 0.9, 1e-12);
  EXPECT_NEAR(w.after.t1, 4.3, 1e-12);
  EXPECT_NEAR(w.before.level, 0.0, 1e-3);
  EXPECT_TRUE(test::throws_error([&] { poke_from_window(s, 3.0, 2.0, 1.0, "force", "--force-window"); },
                                 ErrorKind::Input, {"--force-window", "START before END"}));
  EXPECT_TRUE(test::throws_error([&] { poke_from_window(s, 1.0, 9.0, 1.0, "force", "--force-window"); },
                                 ErrorKind::Input, {"not inside the recording"}));
}

TEST(Signal, RestLevelFollowsALinearDrift) {
  PokeWindow w;
  w.before = {0.0, 2.0, 1.0};
  w.after = {4.0, 6.0, 2.0};
  EXPECT_DOUBLE_EQ(w.rest_level(3.0), 1.5);
  EXPECT_DOUBLE_EQ(w.rest_level(0.5), 1.0);
  EXPECT_DOUBLE_EQ(w.rest_level(5.5), 2.0);
}

TEST(Signal, FindsClippedRunsAtTheExtreme) {
  const std::vector<double> v{0.0, 1.0, 5.0, 5.0, 5.0, 5.0, 2.0, 0.0, 0.0};
  const auto run = find_clipped_run(v, 3, Extreme::Max);
  ASSERT_TRUE(run);
  EXPECT_EQ(run->first, 2u);
  EXPECT_EQ(run->last, 5u);
  EXPECT_EQ(run->value, 5.0);
  EXPECT_FALSE(find_clipped_run(v, 5, Extreme::Max));
  EXPECT_FALSE(find_clipped_run(v, 3, Extreme::Min));  // two zeros at the minimum only
  EXPECT_TRUE(find_clipped_run(v, 2, Extreme::Min));
}

TEST(Signal, AlignsTwoClocksThroughANonlinearRelation) {
  // a = g(b) with g increasing and nonlinear; b is recorded on a clock 3.21 s
  // ahead and at another rate.
  const Signal b0 = protocol(1000.0, 0.0, 5e-3, 0.0, 2);
  Signal a, b;
  for (double t = 0.0; t <= 5.2; t += 1.0 / 200.0) {
    a.t.push_back(t);
    const double d = interpolate(b0.t, b0.v, t);
    a.v.push_back(400.0 * d + 2e5 * d * d);
  }
  for (std::size_t i = 0; i < b0.size(); ++i) {
    b.t.push_back(b0.t[i] + 3.21);
    b.v.push_back(b0.v[i]);
  }
  const Alignment al = align_by_rank(a, b, 1.5, 3.7, 1e-3, -3.21 + 0.07, 0.3);
  EXPECT_NEAR(al.shift, -3.21, 1e-3);
  EXPECT_GT(al.correlation, 0.999);
}

}  // namespace
}  // namespace palpa::acquire
