// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Sampled signals: interpolation and resampling, rest-plateau and poke
// detection, saturation (clipping) runs and the alignment of two clocks
// (thesis §3.1–3.2).
//
// The poke protocol: the device rests at the "just touching" position for about
// two seconds, pokes slowly to a maximum force and back, and rests again for
// about two seconds. Both devices see the same two rest plateaus around one
// excursion; the plateaus give the rest levels and the excursion the poke.

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace palpa::acquire {

// Samples of one quantity: strictly increasing times t [s] and values v (SI).
struct Signal {
  std::vector<double> t;
  std::vector<double> v;

  std::size_t size() const noexcept { return t.size(); }
};

// Linear interpolation of (t, v) at `x`; the end values outside [t₀, t_last].
// t strictly increasing, same length as v, at least one sample.
double interpolate(std::span<const double> t, std::span<const double> v, double x);

// The cubic through the four samples around `x` (two on either side; the end
// four near an end); linear with fewer than four samples, the end values
// outside [t₀, t_last]. Follows motion between samples that a straight line
// cuts short (a ±150 µm, 10 Hz tremor sampled at 50 Hz: off by up to 29 µm
// linearly, 8 µm cubically).
double interpolate_cubic(std::span<const double> t, std::span<const double> v, double x);

// The median of t[i+1] − t[i] [s] (t with at least 2 samples).
double median_step(std::span<const double> t);

// `s` linearly interpolated at t₀ + i·dt, i = 0..n−1.
Signal resample(const Signal& s, double t0, double dt, std::size_t n);

// A rest plateau: the time span [t0, t1] [s] and the signal's mean over it.
struct Plateau {
  double t0 = 0.0, t1 = 0.0;
  double level = 0.0;
};

// One poke found in a signal, on that signal's own clock.
struct PokeWindow {
  Plateau before, after;  // rest plateaus around the poke
  double start = 0.0;     // the signal leaves the rest level [s]
  double peak = 0.0;      // the signal's maximum [s]
  double end = 0.0;       // the signal is back at the rest level [s]
  bool manual = false;    // start/end given by the user

  // The rest level at time x: linear between the plateaus' centres (corrects a
  // slow drift), constant outside them.
  double rest_level(double x) const;
};

struct PlateauOptions {
  // A rest plateau lasts at least this long [s] (the protocol rests ~2 s).
  double min_duration = 1.0;
  // On a plateau the signal stays within this fraction of the poke's amplitude.
  double tolerance = 0.05;
};

// Finds the poke in `s`, a uniformly sampled, low-pass filtered signal that
// rises during the poke (force, or minus the laser distance): the maximum, the
// last plateau before it and the first after it (each a window of
// min_duration whose spread is within tolerance·amplitude and whose level is in
// the lower quarter of the signal's range), and where the signal leaves and
// rejoins those rest levels (by half the tolerance). Throws palpa::Error
// (Input) naming `what` (e.g. "force log 'f.csv', column force_N") when there
// is no excursion or no plateau on either side, saying where it looked and
// suggesting `override_option` to give the window by hand.
PokeWindow detect_poke(const Signal& s, const PlateauOptions& options, const std::string& what,
                       const std::string& override_option);

// The poke with start and end given by hand [s, on the signal's clock]: the
// plateaus are the min_duration before the start and after the end (cut at the
// ends of the signal), the peak the maximum between. Throws palpa::Error (Input)
// naming `what` and `option` if start >= end, if the window is not inside the
// signal, or a plateau has fewer than 2 samples.
PokeWindow poke_from_window(const Signal& s, double start, double end, double min_duration, const std::string& what,
                            const std::string& option);

// A run of identical samples at the signal's extreme: a saturated (clipped)
// sensor.
struct ClippedRun {
  std::size_t first = 0, last = 0;  // sample indices, inclusive
  double value = 0.0;
};
enum class Extreme { Max, Min };
// The first run of at least `min_run` (>= 2) consecutive samples exactly equal
// to the maximum (Extreme::Max) or minimum of `v`, or nullopt.
std::optional<ClippedRun> find_clipped_run(std::span<const double> v, std::size_t min_run, Extreme extreme);

// Clock alignment of two recordings of the same poke: the shift τ [s] such that
// b's time + τ is a's time. Both signals rise with the poke but may be related
// by any increasing function (force = g(indentation)), so the shift maximizes
// Spearman's rank correlation between a(t) and b(t − τ) over the grid
// t = t0, t0 + dt, ..., t1, for τ in coarse ± search (a grid of step dt refined
// by a parabola through the best three). Returns τ and the correlation at the
// best grid shift.
struct Alignment {
  double shift = 0.0;
  double correlation = 0.0;
};
Alignment align_by_rank(const Signal& a, const Signal& b, double t0, double t1, double dt, double coarse,
                        double search);

// Refines a shift τ from align_by_rank for two recordings related by one
// smooth increasing function (force = g(indentation)) over [t0, t1] (the poke,
// loading and unloading): on the grid t = t0, t0 + dt, ..., the pairs
// (b(t − τ), a(t)) lie on one curve at the right τ, while a wrong one opens
// the loading and unloading branches (and tremor) into loops. The residual of
// a local straight-line fit of a against b (sorted by b, in runs of
// `run` pairs) measures the opening; the τ that minimizes it, within ±search
// of `shift` on a grid of step `step` refined by a parabola, is returned.
// Unlike the rank correlation it weighs how far apart the branches are, not
// only their order: sub-millisecond where ranks are good to a few.
double refine_shift_by_fit(const Signal& a, const Signal& b, double t0, double t1, double dt, double shift,
                           double search, double step, std::size_t run = 25);

// Ranks of v (1-based; ties get their mean rank).
std::vector<double> ranks(std::span<const double> v);

// A time for messages, "12.5 s".
std::string format_seconds(double t);

}  // namespace palpa::acquire
