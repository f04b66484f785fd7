// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Axis ranges and tick marks for the SVG plots (report/plot.hpp).
//
// Linear axes get "nice" steps, 1, 2 or 5 × 10^k, with about 5 to 8 labelled
// ticks. An automatic bound is widened to the next tick ("loose" labelling), so
// [-3, 7] becomes [-4, 8] with ticks -4, -2, …, 8; a bound the caller fixes is
// kept and only ticks inside it are labelled.
//
// Log axes get decade ticks (every k-th decade when there are many), plus 2 and 5
// labels when the data span at most 2 decades, plus unlabelled minor ticks at
// 2…9 × 10^k. Data spanning well under a decade get linear nice ticks placed on
// the log scale.
//
// Labels are exact decimal strings built from the integer multiple of the step,
// so a tick at 3 × 0.1 reads "0.3", never "0.30000000000000004". Labels use
// plain decimals ("0.5", "1500", "0.002") for magnitudes in [1e-3, 1e5) and a
// compact scientific form otherwise ("1.5×10⁻⁵", "10⁻⁶" on log axes), the same
// form for every label of one axis.

#include <optional>
#include <string>
#include <vector>

namespace palpa::report {

struct Tick {
  double value = 0;   // data value
  std::string label;  // "" for a minor (unlabelled) tick
};

struct AxisTicks {
  double min = 0, max = 1;  // the axis range (data units), min < max
  bool log = false;
  std::vector<Tick> major;    // labelled ticks with grid lines, increasing
  std::vector<double> minor;  // unlabelled tick marks (log axes), increasing
};

// Chooses the range and ticks of an axis.
// data_min, data_max: finite range of the data (data_min <= data_max); on a log
//   axis both must be > 0 (callers drop non-positive values first).
// fixed_min, fixed_max: bounds the caller fixes (kept as given; on a log axis
//   they must be > 0). When both are set, fixed_min < fixed_max.
// max_labels: at most this many labelled ticks (>= 2); about 5–8 are aimed for.
// Equal data bounds are padded: ±50 % of |value| (±1 around 0) on linear axes,
// one decade each way on log axes.
// Throws palpa::Error (Input) for non-finite or invalid bounds.
AxisTicks choose_ticks(double data_min, double data_max, bool log,
                       std::optional<double> fixed_min = std::nullopt,
                       std::optional<double> fixed_max = std::nullopt, int max_labels = 8);

// The decimal number n × 10^e as compact text: plain decimals when
// 1e-3 <= |value| < 1e5 (and for 0), otherwise "m×10ᵖ" with Unicode
// superscripts; trailing zeros are dropped ("1.5", "2×10⁻⁴", "−3"). Negative
// numbers take the minus sign U+2212.
// `scientific` forces the scientific form (0 stays "0").
std::string format_decimal(long long n, int e, bool scientific = false);

}  // namespace palpa::report
