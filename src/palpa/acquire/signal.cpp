// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/acquire/signal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>

#include "palpa/core/error.hpp"
#include "palpa/core/pearson.hpp"
#include "palpa/core/units.hpp"

namespace palpa::acquire {

namespace {

// Plateau levels must lie in this lower fraction of the signal's range.
constexpr double kRestBand = 0.25;
// The smallest departure from a rest level that counts as the poke's start.
constexpr double kDepartureFraction = 0.01;

// Median of v[first, last).
double median_of(std::span<const double> v, std::size_t first, std::size_t last) {
  std::vector<double> part(v.begin() + static_cast<std::ptrdiff_t>(first), v.begin() + static_cast<std::ptrdiff_t>(last));
  const auto mid = part.begin() + static_cast<std::ptrdiff_t>(part.size() / 2);
  std::nth_element(part.begin(), mid, part.end());
  return *mid;
}

double mean_over(const Signal& s, double t0, double t1, std::size_t& count) {
  double sum = 0.0;
  count = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.t[i] >= t0 && s.t[i] <= t1) {
      sum += s.v[i];
      ++count;
    }
  }
  return count == 0 ? 0.0 : sum / static_cast<double>(count);
}

// max − min of v over each window [i, i + w − 1], i = 0..n−w (monotone deques).
std::vector<double> window_spread(std::span<const double> v, std::size_t w) {
  std::vector<double> spread;
  if (w == 0 || v.size() < w) return spread;
  spread.resize(v.size() - w + 1);
  std::deque<std::size_t> hi, lo;
  for (std::size_t i = 0; i < v.size(); ++i) {
    while (!hi.empty() && v[hi.back()] <= v[i]) hi.pop_back();
    while (!lo.empty() && v[lo.back()] >= v[i]) lo.pop_back();
    hi.push_back(i);
    lo.push_back(i);
    if (i + 1 >= w) {
      const std::size_t first = i + 1 - w;
      while (hi.front() < first) hi.pop_front();
      while (lo.front() < first) lo.pop_front();
      spread[first] = v[hi.front()] - v[lo.front()];
    }
  }
  return spread;
}

}  // namespace

double interpolate(std::span<const double> t, std::span<const double> v, double x) {
  assert(!t.empty() && t.size() == v.size());
  if (x <= t.front()) return v.front();
  if (x >= t.back()) return v.back();
  const auto it = std::upper_bound(t.begin(), t.end(), x);
  const std::size_t i = static_cast<std::size_t>(it - t.begin());
  const double w = (x - t[i - 1]) / (t[i] - t[i - 1]);
  return (1.0 - w) * v[i - 1] + w * v[i];
}

double interpolate_cubic(std::span<const double> t, std::span<const double> v, double x) {
  assert(!t.empty() && t.size() == v.size());
  if (t.size() < 4) return interpolate(t, v, x);
  if (x <= t.front()) return v.front();
  if (x >= t.back()) return v.back();
  const auto i = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), x) - t.begin());
  const std::size_t first = std::min(i < 2 ? 0 : i - 2, t.size() - 4);
  double y = 0.0;
  for (std::size_t a = first; a < first + 4; ++a) {
    double w = 1.0;
    for (std::size_t b = first; b < first + 4; ++b) {
      if (b != a) w *= (x - t[b]) / (t[a] - t[b]);
    }
    y += w * v[a];
  }
  return y;
}

double median_step(std::span<const double> t) {
  assert(t.size() >= 2);
  std::vector<double> d(t.size() - 1);
  for (std::size_t i = 0; i + 1 < t.size(); ++i) d[i] = t[i + 1] - t[i];
  const auto mid = d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2);
  std::nth_element(d.begin(), mid, d.end());
  return *mid;
}

Signal resample(const Signal& s, double t0, double dt, std::size_t n) {
  Signal r;
  r.t.resize(n);
  r.v.resize(n);
  // Walk both sequences together (the grid is increasing).
  std::size_t j = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = t0 + static_cast<double>(i) * dt;
    r.t[i] = x;
    while (j + 1 < s.size() && s.t[j + 1] <= x) ++j;
    if (x <= s.t.front()) {
      r.v[i] = s.v.front();
    } else if (j + 1 >= s.size()) {
      r.v[i] = s.v.back();
    } else {
      const double w = (x - s.t[j]) / (s.t[j + 1] - s.t[j]);
      r.v[i] = (1.0 - w) * s.v[j] + w * s.v[j + 1];
    }
  }
  return r;
}

double PokeWindow::rest_level(double x) const {
  const double c0 = 0.5 * (before.t0 + before.t1);
  const double c1 = 0.5 * (after.t0 + after.t1);
  if (x <= c0 || c1 <= c0) return before.level;
  if (x >= c1) return after.level;
  const double w = (x - c0) / (c1 - c0);
  return (1.0 - w) * before.level + w * after.level;
}

PokeWindow detect_poke(const Signal& s, const PlateauOptions& options, const std::string& what,
                       const std::string& override_option) {
  const std::size_t n = s.size();
  const auto peak_it = std::max_element(s.v.begin(), s.v.end());
  const std::size_t p = static_cast<std::size_t>(peak_it - s.v.begin());
  const double lowest = *std::min_element(s.v.begin(), s.v.end());
  const double amplitude = *peak_it - lowest;
  const std::string hint = fmt::format("give the poke's start and end by hand with {} START,END", override_option);
  if (!(amplitude > 0.0) || n < 4) {
    throw_input_error(fmt::format("{}: the signal is constant: there is no poke", what), {}, hint);
  }
  const double dt = (s.t.back() - s.t.front()) / static_cast<double>(n - 1);
  const std::size_t w = std::max<std::size_t>(2, static_cast<std::size_t>(std::lround(options.min_duration / dt)) + 1);
  const double tolerance = options.tolerance * amplitude;
  const std::vector<double> spread = window_spread(s.v, w);
  std::vector<double> prefix(n + 1, 0.0);  // prefix sums: window means in O(1)
  for (std::size_t i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + s.v[i];
  auto level_of = [&](std::size_t i) { return (prefix[i + w] - prefix[i]) / static_cast<double>(w); };
  auto is_rest = [&](std::size_t i) {
    return spread[i] <= tolerance && level_of(i) <= lowest + kRestBand * amplitude;
  };
  const std::string expected =
      fmt::format("a rest of at least {} within {:.3g} ({}% of the poke) before and after the peak at {}; {}",
                  format_seconds(options.min_duration), tolerance, options.tolerance * 100.0, format_seconds(s.t[p]), hint);
  std::optional<std::size_t> before, after;
  for (std::size_t i = 0; i + w <= p && i < spread.size(); ++i) {
    if (is_rest(i)) before = i;
  }
  for (std::size_t i = p + 1; i < spread.size(); ++i) {
    if (is_rest(i)) {
      after = i;
      break;
    }
  }
  if (!before || !after) {
    throw_input_error(
        fmt::format("{}: no rest plateau found {} the poke (signal from {} to {})", what,
                    !before && !after ? "before or after" : (!before ? "before" : "after"), format_seconds(s.t.front()),
                    format_seconds(s.t.back())),
        {}, expected);
  }
  // The signal leaves the rest where it rises above the window's median by
  // max(4 standard deviations of the window, 1% of the poke); the poke starts
  // where, before that, it last crossed the median. The plateau is the
  // min_duration before the start (after the end for the second one), and its
  // level the median there.
  auto departure_band = [&](std::size_t i) {
    const double m = level_of(i);
    double var = 0.0;
    for (std::size_t k = i; k < i + w; ++k) var += (s.v[k] - m) * (s.v[k] - m);
    return std::min(0.5 * tolerance, std::max(4.0 * std::sqrt(var / static_cast<double>(w)), kDepartureFraction * amplitude));
  };
  const double level0 = median_of(s.v, *before, *before + w);
  const double level1 = median_of(s.v, *after, *after + w);
  const double band0 = departure_band(*before), band1 = departure_band(*after);
  std::size_t k0 = p;
  while (k0 > *before && s.v[k0] > level0 + band0) --k0;
  // Back to where it crossed the rest level, at most a quarter plateau further.
  for (std::size_t left = w / 4; left > 0 && k0 > *before && s.v[k0] > level0; --left) --k0;
  std::size_t k1 = p;
  while (k1 < *after + w - 1 && s.v[k1] > level1 + band1) ++k1;
  for (std::size_t left = w / 4; left > 0 && k1 < *after + w - 1 && s.v[k1] > level1; --left) ++k1;
  PokeWindow win;
  win.peak = s.t[p];
  win.start = s.t[k0];
  win.end = s.t[k1];
  const std::size_t b1 = std::min(k0, *before + w - 1);
  const std::size_t b0 = b1 + 1 >= w ? b1 + 1 - w : 0;
  const std::size_t a0 = std::max(k1, *after);
  const std::size_t a1 = std::min(n - 1, a0 + w - 1);
  win.before = {s.t[b0], s.t[b1], median_of(s.v, b0, b1 + 1)};
  win.after = {s.t[a0], s.t[a1], median_of(s.v, a0, a1 + 1)};
  return win;
}

PokeWindow poke_from_window(const Signal& s, double start, double end, double min_duration, const std::string& what,
                            const std::string& option) {
  const ErrorContext where{"", 0, 0, "option " + option};
  if (!(start < end)) {
    throw_input_error(fmt::format("{}: the poke window starts at {} and ends at {}", what, format_seconds(start), format_seconds(end)),
                      where, "START before END");
  }
  if (start < s.t.front() || end > s.t.back()) {
    throw_input_error(fmt::format("{}: the poke window {} .. {} is not inside the recording {} .. {}", what,
                                  format_seconds(start), format_seconds(end), format_seconds(s.t.front()), format_seconds(s.t.back())),
                      where, "a window on the log's own clock");
  }
  PokeWindow win;
  win.manual = true;
  win.start = start;
  win.end = end;
  std::size_t nb = 0, na = 0;
  win.before.t0 = std::max(s.t.front(), start - min_duration);
  win.before.t1 = start;
  win.before.level = mean_over(s, win.before.t0, win.before.t1, nb);
  win.after.t0 = end;
  win.after.t1 = std::min(s.t.back(), end + min_duration);
  win.after.level = mean_over(s, win.after.t0, win.after.t1, na);
  if (nb < 2 || na < 2) {
    throw_input_error(fmt::format("{}: the poke window {} .. {} leaves no rest samples {} it", what, format_seconds(start),
                                  format_seconds(end), nb < 2 ? "before" : "after"),
                      where, "a window with rest samples on both sides");
  }
  double best = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.t[i] >= start && s.t[i] <= end && s.v[i] > best) {
      best = s.v[i];
      win.peak = s.t[i];
    }
  }
  return win;
}

std::optional<ClippedRun> find_clipped_run(std::span<const double> v, std::size_t min_run, Extreme extreme) {
  if (v.empty() || min_run < 2) return std::nullopt;
  const double target =
      extreme == Extreme::Max ? *std::max_element(v.begin(), v.end()) : *std::min_element(v.begin(), v.end());
  std::size_t run = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    run = v[i] == target ? run + 1 : 0;
    if (run >= min_run) {
      std::size_t last = i;
      while (last + 1 < v.size() && v[last + 1] == target) ++last;
      return ClippedRun{i + 1 - run, last, target};
    }
  }
  return std::nullopt;
}

std::vector<double> ranks(std::span<const double> v) {
  std::vector<std::size_t> order(v.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
  std::vector<double> r(v.size());
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i;
    while (j + 1 < order.size() && v[order[j + 1]] == v[order[i]]) ++j;
    const double mean_rank = 0.5 * static_cast<double>(i + j) + 1.0;
    for (std::size_t k = i; k <= j; ++k) r[order[k]] = mean_rank;
    i = j + 1;
  }
  return r;
}

Alignment align_by_rank(const Signal& a, const Signal& b, double t0, double t1, double dt, double coarse,
                        double search) {
  assert(dt > 0.0 && t1 > t0);
  const std::size_t n = static_cast<std::size_t>(std::floor((t1 - t0) / dt)) + 1;
  const Signal ga = resample(a, t0, dt, n);
  const std::vector<double> ra = ranks(ga.v);
  const long steps = static_cast<long>(std::ceil(search / dt));
  std::vector<double> corr(static_cast<std::size_t>(2 * steps + 1));
  for (long k = -steps; k <= steps; ++k) {
    const double shift = coarse + static_cast<double>(k) * dt;
    const Signal gb = resample(b, t0 - shift, dt, n);
    corr[static_cast<std::size_t>(k + steps)] = pearson(ra, ranks(gb.v));
  }
  const std::size_t best = static_cast<std::size_t>(std::max_element(corr.begin(), corr.end()) - corr.begin());
  Alignment out;
  out.correlation = corr[best];
  out.shift = coarse + static_cast<double>(static_cast<long>(best) - steps) * dt;
  if (best > 0 && best + 1 < corr.size()) {
    const double c0 = corr[best - 1], c1 = corr[best], c2 = corr[best + 1];
    const double denom = c0 - 2.0 * c1 + c2;
    if (denom < 0.0) out.shift += 0.5 * (c0 - c2) / denom * dt;
  }
  return out;
}

namespace {

// Σ of squared residuals of straight lines fitted to consecutive runs of the
// pairs (x, y) sorted by x.
double local_line_residual(std::vector<std::pair<double, double>>& pairs, std::size_t run) {
  std::sort(pairs.begin(), pairs.end());
  double total = 0.0;
  for (std::size_t first = 0; first < pairs.size(); first += run) {
    const std::size_t last = std::min(pairs.size(), first + run);
    const double n = static_cast<double>(last - first);
    if (n < 3) break;
    double mx = 0.0, my = 0.0;
    for (std::size_t i = first; i < last; ++i) {
      mx += pairs[i].first;
      my += pairs[i].second;
    }
    mx /= n;
    my /= n;
    double sxx = 0.0, sxy = 0.0, syy = 0.0;
    for (std::size_t i = first; i < last; ++i) {
      const double dx = pairs[i].first - mx, dy = pairs[i].second - my;
      sxx += dx * dx;
      sxy += dx * dy;
      syy += dy * dy;
    }
    total += sxx > 0.0 ? syy - sxy * sxy / sxx : syy;
  }
  return total;
}

}  // namespace

double refine_shift_by_fit(const Signal& a, const Signal& b, double t0, double t1, double dt, double shift,
                           double search, double step, std::size_t run) {
  assert(dt > 0.0 && t1 > t0 && step > 0.0 && run >= 3);
  const std::size_t n = static_cast<std::size_t>(std::floor((t1 - t0) / dt)) + 1;
  const Signal ga = resample(a, t0, dt, n);
  const long steps = static_cast<long>(std::ceil(search / step));
  std::vector<double> rss(static_cast<std::size_t>(2 * steps + 1));
  std::vector<std::pair<double, double>> pairs(n);
  for (long k = -steps; k <= steps; ++k) {
    const double tau = shift + static_cast<double>(k) * step;
    const Signal gb = resample(b, t0 - tau, dt, n);
    for (std::size_t i = 0; i < n; ++i) pairs[i] = {gb.v[i], ga.v[i]};
    rss[static_cast<std::size_t>(k + steps)] = local_line_residual(pairs, run);
  }
  const std::size_t best = static_cast<std::size_t>(std::min_element(rss.begin(), rss.end()) - rss.begin());
  double out = shift + static_cast<double>(static_cast<long>(best) - steps) * step;
  if (best > 0 && best + 1 < rss.size()) {
    const double c0 = rss[best - 1], c1 = rss[best], c2 = rss[best + 1];
    const double denom = c0 - 2.0 * c1 + c2;
    if (denom > 0.0) out += 0.5 * (c0 - c2) / denom * step;
  }
  return out;
}

std::string format_seconds(double t) { return fmt::format("{:.4g} s", t); }

}  // namespace palpa::acquire
