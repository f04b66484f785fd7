// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/acquire/filter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

#include "palpa/core/error.hpp"

namespace palpa::acquire {

namespace {

constexpr int kMaxOrder = 12;
// filtfilt pads until the slowest pole's response has decayed to this fraction.
constexpr double kPaddingDecay = 1e-3;

// Steady-state states (z1, z2) of a section whose input has been `u` forever.
void steady_state(const Biquad& s, double u, double& z1, double& z2) {
  const double gain = (s.b0 + s.b1 + s.b2) / (1.0 + s.a1 + s.a2);
  const double y = gain * u;
  z2 = s.b2 * u - s.a2 * y;
  z1 = y - s.b0 * u;
}

// Largest pole radius of a section (< 1 for a stable filter).
double pole_radius(const Biquad& s) {
  if (s.a2 == 0.0) return std::abs(s.a1);
  const double disc = s.a1 * s.a1 - 4.0 * s.a2;
  if (disc < 0.0) return std::sqrt(s.a2);  // complex pair: |p|² = a2
  const double r = std::sqrt(disc);
  return std::max(std::abs((-s.a1 + r) / 2.0), std::abs((-s.a1 - r) / 2.0));
}

}  // namespace

std::vector<Biquad> butterworth_lowpass(int order, double cutoff_hz, double rate_hz) {
  if (order < 1 || order > kMaxOrder) {
    throw_input_error(fmt::format("filter order {} is out of range", order), ErrorContext{"", 0, 0, "option --order"},
                      fmt::format("an order from 1 to {}", kMaxOrder));
  }
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) {
    throw_input_error(fmt::format("sample rate {} Hz is not positive", rate_hz), ErrorContext{"", 0, 0, "sample rate"},
                      "a positive sample rate");
  }
  if (!(cutoff_hz > 0.0) || !(cutoff_hz < 0.5 * rate_hz)) {
    throw_input_error(fmt::format("cut-off {} Hz is not between 0 and the Nyquist frequency {} Hz of samples at {} Hz",
                                  cutoff_hz, 0.5 * rate_hz, rate_hz),
                      ErrorContext{"", 0, 0, "option --cutoff"}, "a cut-off below half the sample rate");
  }
  // Pre-warped analog cut-off, in units where the bilinear map is s = (z−1)/(z+1).
  const double k = std::tan(std::numbers::pi * cutoff_hz / rate_hz);
  const double k2 = k * k;
  std::vector<Biquad> sections;
  if (order % 2 == 1) {
    // 1/(s/Ωc + 1) -> first-order section.
    Biquad s;
    s.b0 = s.b1 = k / (1.0 + k);
    s.a1 = (k - 1.0) / (k + 1.0);
    sections.push_back(s);
  }
  for (int i = 0; i < order / 2; ++i) {
    // The prototype poles exp(iπ(2j + order + 1)/(2·order)), j = 0..order−1, in
    // conjugate pairs: s² + 2ζ s + 1 with 2ζ = 2 sin(π (2i+1) / (2·order)); for an
    // odd order the remaining pole is the real one at −1 (above).
    const double two_zeta = 2.0 * std::sin(std::numbers::pi * (2 * i + 1) / (2.0 * order));
    const double d = 1.0 + two_zeta * k + k2;
    Biquad s;
    s.b0 = k2 / d;
    s.b1 = 2.0 * k2 / d;
    s.b2 = k2 / d;
    s.a1 = 2.0 * (k2 - 1.0) / d;
    s.a2 = (1.0 - two_zeta * k + k2) / d;
    sections.push_back(s);
  }
  return sections;
}

std::complex<double> frequency_response(std::span<const Biquad> sections, double omega) {
  const std::complex<double> zi = std::polar(1.0, -omega);  // z^-1
  const std::complex<double> zi2 = zi * zi;
  std::complex<double> h = 1.0;
  for (const Biquad& s : sections) {
    h *= (s.b0 + s.b1 * zi + s.b2 * zi2) / (1.0 + s.a1 * zi + s.a2 * zi2);
  }
  return h;
}

double butterworth_magnitude(int order, double cutoff_hz, double rate_hz, double frequency_hz) {
  const double ratio =
      std::tan(std::numbers::pi * frequency_hz / rate_hz) / std::tan(std::numbers::pi * cutoff_hz / rate_hz);
  return 1.0 / std::sqrt(1.0 + std::pow(ratio, 2.0 * order));
}

std::vector<double> filter_forward(std::span<const Biquad> sections, std::span<const double> x, double initial) {
  std::vector<double> y(x.begin(), x.end());
  double level = initial;
  for (const Biquad& s : sections) {
    double z1 = 0.0, z2 = 0.0;
    steady_state(s, level, z1, z2);
    level *= (s.b0 + s.b1 + s.b2) / (1.0 + s.a1 + s.a2);
    for (double& v : y) {
      const double in = v;
      const double out = s.b0 * in + z1;
      z1 = s.b1 * in - s.a1 * out + z2;
      z2 = s.b2 * in - s.a2 * out;
      v = out;
    }
  }
  return y;
}

std::size_t filtfilt_padding(std::span<const Biquad> sections, std::size_t n) noexcept {
  double radius = 0.0;
  for (const Biquad& s : sections) radius = std::max(radius, pole_radius(s));
  std::size_t pad = 3 * (2 * sections.size() + 1);
  if (radius > 0.0 && radius < 1.0) {
    const double decay = std::ceil(std::log(kPaddingDecay) / std::log(radius));
    if (decay < 1e9) pad = std::max(pad, static_cast<std::size_t>(decay));
  }
  return n == 0 ? 0 : std::min(pad, n - 1);
}

std::vector<double> filtfilt(std::span<const Biquad> sections, std::span<const double> x) {
  assert(x.size() >= 2);
  const std::size_t n = x.size();
  const std::size_t pad = filtfilt_padding(sections, n);
  std::vector<double> ext(n + 2 * pad);
  for (std::size_t k = 0; k < pad; ++k) {
    ext[k] = 2.0 * x.front() - x[pad - k];
    ext[pad + n + k] = 2.0 * x.back() - x[n - 2 - k];
  }
  std::copy(x.begin(), x.end(), ext.begin() + static_cast<std::ptrdiff_t>(pad));
  std::vector<double> forward = filter_forward(sections, ext, ext.front());
  std::reverse(forward.begin(), forward.end());
  std::vector<double> backward = filter_forward(sections, forward, forward.front());
  std::reverse(backward.begin(), backward.end());
  return {backward.begin() + static_cast<std::ptrdiff_t>(pad), backward.begin() + static_cast<std::ptrdiff_t>(pad + n)};
}

Signal lowpass(const Signal& s, int order, double cutoff_hz) {
  assert(s.size() >= 2);
  const double dt = median_step(s.t);
  const std::size_t n = static_cast<std::size_t>(std::floor((s.t.back() - s.t.front()) / dt + 1e-9)) + 1;
  Signal u = resample(s, s.t.front(), dt, std::max<std::size_t>(n, 2));
  const std::vector<Biquad> sections = butterworth_lowpass(order, cutoff_hz, 1.0 / dt);
  u.v = filtfilt(sections, u.v);
  return u;
}

}  // namespace palpa::acquire
