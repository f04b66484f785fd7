// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The sequential colour map of the pressure pictures (report/pressure_map_svg.hpp):
// viridis (van der Walt & Smith, matplotlib's default map), perceptually
// uniform and rising in lightness from dark violet (low) to yellow (high), so
// it stays readable printed in grey and for the common colour-vision
// deficiencies. Here as its 11 sRGB stops at t = 0, 0.1, …, 1 (the values
// matplotlib's table takes there, rounded to bytes), linearly interpolated in
// between — exactly what an SVG linear gradient through the same stops draws.

#include <cstdint>
#include <string>

namespace palpa::report {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

inline constexpr int kViridisStops = 11;

// Stop i (0 <= i < kViridisStops, clamped), the colour at t = i / (kViridisStops − 1).
Rgb viridis_stop(int i) noexcept;

// The colour at t in [0, 1]: t below 0 (or NaN) gives the first stop, above 1 the last.
Rgb viridis(double t) noexcept;

// "#rrggbb", lower-case hex.
std::string hex_color(Rgb c);

}  // namespace palpa::report
