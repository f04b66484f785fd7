// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/report/colormap.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace palpa::report {
namespace {

constexpr std::array<Rgb, kViridisStops> kViridis = {{{0x44, 0x01, 0x54},
                                                      {0x48, 0x25, 0x76},
                                                      {0x41, 0x44, 0x87},
                                                      {0x35, 0x60, 0x8d},
                                                      {0x2a, 0x78, 0x8e},
                                                      {0x21, 0x90, 0x8c},
                                                      {0x22, 0xa8, 0x84},
                                                      {0x43, 0xbf, 0x71},
                                                      {0x7a, 0xd1, 0x51},
                                                      {0xbb, 0xdf, 0x27},
                                                      {0xfd, 0xe7, 0x25}}};

std::uint8_t mix_channel(std::uint8_t a, std::uint8_t b, double f) {
  return static_cast<std::uint8_t>(std::lround(a + f * (static_cast<double>(b) - a)));
}

}  // namespace

Rgb viridis_stop(int i) noexcept {
  return kViridis[static_cast<std::size_t>(std::clamp(i, 0, kViridisStops - 1))];
}

Rgb viridis(double t) noexcept {
  if (!(t > 0.0)) return kViridis.front();
  if (t >= 1.0) return kViridis.back();
  const double x = t * (kViridisStops - 1);
  const int i = std::min(static_cast<int>(x), kViridisStops - 2);
  const double f = x - i;
  const Rgb& a = kViridis[static_cast<std::size_t>(i)];
  const Rgb& b = kViridis[static_cast<std::size_t>(i + 1)];
  return {mix_channel(a.r, b.r, f), mix_channel(a.g, b.g, f), mix_channel(a.b, b.b, f)};
}

std::string hex_color(Rgb c) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s = "#";
  for (const std::uint8_t v : {c.r, c.g, c.b}) {
    s += kDigits[v >> 4];
    s += kDigits[v & 0xF];
  }
  return s;
}

}  // namespace palpa::report
