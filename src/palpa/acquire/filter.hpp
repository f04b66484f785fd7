// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Zero-phase low-pass filtering of uniformly sampled signals (thesis §3.2: "we
// post-process the curves using low-pass filtering to remove vibrations and
// noise").
//
// A digital Butterworth low-pass is designed from the analog prototype with the
// bilinear transform (cut-off pre-warped so the digital filter has exactly half
// power at the cut-off), as second-order sections. filtfilt() runs it forward
// and backward: no phase lag, magnitude |H|² (−6 dB at the cut-off).

#include <complex>
#include <span>
#include <vector>

#include "palpa/acquire/signal.hpp"

namespace palpa::acquire {

// One second-order section, transposed direct form II:
//   y = b0 x + z1;  z1 <- b1 x − a1 y + z2;  z2 <- b2 x − a2 y   (a0 = 1).
// A first-order section has b2 = a2 = 0.
struct Biquad {
  double b0 = 1.0, b1 = 0.0, b2 = 0.0;
  double a1 = 0.0, a2 = 0.0;
};

// Butterworth low-pass of `order` (1..12) with cut-off `cutoff_hz` for samples at
// `rate_hz` (0 < cutoff < rate/2), as ceil(order/2) sections (a first-order one
// first when the order is odd). Unit gain at DC. Throws palpa::Error (Input)
// naming the option ("--cutoff") for a cut-off at or above the Nyquist
// frequency or not positive, and for an order outside 1..12.
std::vector<Biquad> butterworth_lowpass(int order, double cutoff_hz, double rate_hz);

// H(e^{iω}) of the cascade at normalized angular frequency ω = 2π f / rate.
std::complex<double> frequency_response(std::span<const Biquad> sections, double omega);

// The analytic magnitude of the digital Butterworth low-pass designed above:
// |H|² = 1 / (1 + (tan(ω/2) / tan(ωc/2))^(2·order)), returned as |H|.
double butterworth_magnitude(int order, double cutoff_hz, double rate_hz, double frequency_hz);

// Runs the cascade once over `x` (forward), starting from the steady state of
// the input value `initial` (so a constant input gives a constant output).
std::vector<double> filter_forward(std::span<const Biquad> sections, std::span<const double> x,
                                   double initial);

// Zero-phase filtering: forward then backward over `x` extended at both ends by
// `padding(sections, n)` samples reflected through the end values (x₀ − (x_k −
// x₀)), which keeps the level and slope at the ends; each pass starts from the
// steady state of its first padded value. Returns x.size() values. Requires
// x.size() >= 2 (programmer error otherwise).
std::vector<double> filtfilt(std::span<const Biquad> sections, std::span<const double> x);

// The number of padding samples filtfilt uses for a signal of n samples: as
// many as the slowest pole of the cascade needs to decay to 1e-3 (at least
// 3·(2·sections + 1)), at most n − 1.
std::size_t filtfilt_padding(std::span<const Biquad> sections, std::size_t n) noexcept;

// `s` resampled on a uniform clock at its median time step (from its first to
// its last sample) and filtered zero-phase by a Butterworth low-pass of `order`
// and `cutoff_hz` (palpa::Error naming --cutoff if the cut-off is not below
// half the sample rate).
Signal lowpass(const Signal& s, int order, double cutoff_hz);

}  // namespace palpa::acquire
