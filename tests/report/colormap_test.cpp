// SPDX-License-Identifier: AGPL-3.0-or-later
// The pressure pictures' colour map: viridis' ends and stops, clamping, and
// lightness rising all the way (a sequential map).

#include "palpa/report/colormap.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace palpa::report {
namespace {

// Relative luminance (WCAG) of an sRGB colour.
double luminance(Rgb c) {
  const auto linear = [](std::uint8_t v) {
    const double s = v / 255.0;
    return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
  };
  return 0.2126 * linear(c.r) + 0.7152 * linear(c.g) + 0.0722 * linear(c.b);
}

TEST(ReportColormap, IsViridisFromEndToEnd) {
  EXPECT_EQ(hex_color(viridis(0.0)), "#440154");
  EXPECT_EQ(hex_color(viridis(0.5)), "#21908c");
  EXPECT_EQ(hex_color(viridis(1.0)), "#fde725");
  for (int i = 0; i < kViridisStops; ++i)
    EXPECT_EQ(viridis(i / double(kViridisStops - 1)), viridis_stop(i)) << i;
  EXPECT_EQ(viridis(-1.0), viridis(0.0));
  EXPECT_EQ(viridis(std::numeric_limits<double>::quiet_NaN()), viridis(0.0));
  EXPECT_EQ(viridis(7.0), viridis(1.0));
  EXPECT_EQ(viridis_stop(99), viridis(1.0));
}

TEST(ReportColormap, GetsLighterAllTheWay) {
  constexpr int kSamples = 200;
  double previous = -1.0;
  for (int i = 0; i <= kSamples; ++i) {
    const double l = luminance(viridis(i / double(kSamples)));
    EXPECT_GE(l, previous) << i;
    previous = l;
  }
  EXPECT_GT(luminance(viridis(1.0)), 10 * luminance(viridis(0.0)));
}

}  // namespace
}  // namespace palpa::report
