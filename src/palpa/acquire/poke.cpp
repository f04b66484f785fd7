// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/acquire/poke.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "palpa/acquire/filter.hpp"
#include "palpa/acquire/penalized_spline.hpp"
#include "palpa/core/error.hpp"

namespace palpa::acquire {

namespace {

std::string describe(const Log& log, const char* role) {
  return fmt::format("{} log '{}' (column {})", role, log.file, log.value.name);
}

PokeWindow find_window(const Signal& s, const std::optional<TimeWindow>& manual, const PokeOptions& o,
                       const std::string& what, const std::string& option) {
  if (manual) return poke_from_window(s, manual->start, manual->end, o.plateau.min_duration, what, option);
  return detect_poke(s, o.plateau, what, option);
}

// The fine alignment looks at the poke and this fraction of its duration on
// either side, on a grid no finer than kAlignStep [s] (a parabola through the
// best three grid shifts refines it).
constexpr double kAlignMargin = 0.1;
constexpr double kAlignStep = 1e-3;

// Below this fraction of its peak an excursion counts as rest for the
// alignment: the rest noise then ties instead of adding random ranks.
constexpr double kAlignFloor = 0.02;

// The excursion above the rest levels, with the rest (below kAlignFloor of the
// peak) flattened.
Signal above_rest(Signal s, const PokeWindow& w) {
  double peak = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    s.v[i] -= w.rest_level(s.t[i]);
    peak = std::max(peak, s.v[i]);
  }
  for (double& v : s.v) v = std::max(v, kAlignFloor * peak);
  return s;
}

Signal negated(Signal s) {
  for (double& v : s.v) v = -v;
  return s;
}

}  // namespace

Curve uniform_curve(std::span<const double> indentation, std::span<const double> force, double x_max,
                    std::size_t points, PenalizedSpline* spline) {
  Curve c;
  const double h = x_max / static_cast<double>(points - 1);
  for (std::size_t j = 0; j < points; ++j) c.indentation.push_back(static_cast<double>(j) * h);
  const PenalizedSplineOptions o;
  if (indentation.size() > static_cast<std::size_t>(o.penalty_order) + 1) {
    try {
      const PenalizedSpline s = fit_penalized_spline(indentation, force, 0.0, x_max, o);
      for (double x : c.indentation) c.force.push_back(s(x));
      if (spline) *spline = s;
      return c;
    } catch (const std::invalid_argument&) {
      // (pairs at fewer than three distinct indentations: a coarse laser)
    }
  }
  // Too few pairs, or too few distinct indentations, for a smooth curve:
  // straight lines between them.
  std::vector<std::size_t> order(indentation.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return indentation[a] < indentation[b]; });
  std::vector<double> xs, ys;
  for (std::size_t i : order) {
    if (!xs.empty() && !(indentation[i] > xs.back())) continue;
    xs.push_back(indentation[i]);
    ys.push_back(force[i]);
  }
  for (double x : c.indentation) c.force.push_back(interpolate(xs, ys, x));
  return c;
}

PokeResult process_poke(const std::filesystem::path& force_file, const std::filesystem::path& laser_file,
                        const std::optional<std::filesystem::path>& calibration_file, const PokeOptions& o) {
  if (o.points < 3 || o.points > kMaxCurvePoints) {
    throw_input_error(fmt::format("{} grid points", o.points), ErrorContext{"", 0, 0, "option --points"},
                      fmt::format("3 to {}", kMaxCurvePoints));
  }
  PokeResult r;
  const Dimension force_kind[] = {Dimension::Force};
  const Dimension laser_kinds[] = {Dimension::Voltage, Dimension::Length};
  r.force_log = read_log(force_file, o.force_time, o.force_value, force_kind, "force", o.check);
  r.laser_log = read_log(laser_file, o.laser_time, o.laser_value, laser_kinds, "laser", o.check);
  const Log& fl = r.force_log;
  const Log& ll = r.laser_log;
  check_not_clipped(fl, Extreme::Max, o.saturation);

  // Laser value -> distance; the poke is where the distance is smallest.
  r.laser_distance_raw.t = ll.signal.t;
  if (ll.value.dimension == Dimension::Voltage) {
    if (!calibration_file) {
      throw_input_error(fmt::format("the laser column '{}' holds voltages", ll.value.name),
                        ErrorContext{ll.file, 0, 0, "option --calibration"},
                        "a calibration table (voltage -> distance) or a laser column holding distances");
    }
    const Calibration cal = read_calibration(*calibration_file, o.calibration_voltage, Dimension::Voltage,
                                             o.calibration_distance, Dimension::Length);
    const bool rising = cal(cal.x_max(), "") > cal(cal.x_min(), "");
    check_not_clipped(ll, rising ? Extreme::Min : Extreme::Max, o.saturation);
    for (std::size_t i = 0; i < ll.signal.size(); ++i) {
      r.laser_distance_raw.v.push_back(
          cal(ll.signal.v[i], fmt::format("{}:{}: column '{}'", ll.file, ll.lines[i], ll.value.name)));
    }
  } else {
    if (calibration_file) {
      throw_input_error(fmt::format("the laser column '{}' already holds distances", ll.value.name),
                        ErrorContext{calibration_file->string(), 0, 0, "option --calibration"},
                        "no calibration for a distance column");
    }
    check_not_clipped(ll, Extreme::Min, o.saturation);
    r.laser_distance_raw.v = ll.signal.v;
  }

  // Uniform, filtered; the laser's "activity" is minus the distance (rises with the poke).
  r.force_filtered = lowpass(fl.signal, o.order, o.cutoff);
  r.distance_filtered = lowpass(r.laser_distance_raw, o.order, o.cutoff);
  const Signal activity = negated(r.distance_filtered);
  r.force_window = find_window(r.force_filtered, o.force_window, o, describe(fl, "force"), "--force-window");
  r.laser_window = find_window(activity, o.laser_window, o, describe(ll, "laser"), "--laser-window");
  const PokeWindow& fw = r.force_window;
  const PokeWindow& lw = r.laser_window;

  // Clocks: laser time + shift = force time.
  r.coarse_shift = fw.start - lw.start;
  const double duration = fw.end - fw.start;
  const double dt = std::max(kAlignStep, std::min(1.0 / fl.rate, 1.0 / ll.rate));
  const double margin = kAlignMargin * duration;
  const double a0 = std::max(fw.start - margin, r.force_filtered.t.front());
  const double a1 = std::min(fw.end + margin, r.force_filtered.t.back());
  // Align the excursions above the rest levels: a drift of either reading
  // during the rests would otherwise pull the correlation.
  const Alignment al = align_by_rank(above_rest(r.force_filtered, fw), above_rest(activity, lw), a0, a1, dt,
                                     r.coarse_shift, std::max(o.search * duration, 3.0 * dt));
  // Then to a fraction of a millisecond by how well the pairs over the poke
  // lie on one curve (a millisecond of the ramp is a few µm of indentation).
  r.clock_shift = refine_shift_by_fit(above_rest(r.force_filtered, fw), above_rest(activity, lw), fw.start, fw.end,
                                      kAlignStep, al.shift, 3.0 * dt, 0.1 * kAlignStep);
  r.correlation = al.correlation;
  r.rest_distance = -lw.before.level;

  // Common clock (the force clock at the faster rate) from the loading start to the unloading end.
  r.common_rate = std::max(fl.rate, ll.rate);
  // A little of each rest is kept: it anchors the curve at zero.
  const double t_begin = std::max(fw.before.t0, fw.start - kAlignMargin * duration);
  const double t_end = std::min(fw.after.t1, fw.end + kAlignMargin * duration);
  const double laser_first = r.distance_filtered.t.front() + r.clock_shift;
  const double laser_last = r.distance_filtered.t.back() + r.clock_shift;
  if (t_begin < laser_first || t_end > laser_last) {
    throw_input_error(fmt::format("after aligning the clocks (laser + {:.4g} s), the laser log covers {:.4g} .. {:.4g} s "
                                  "of the force clock but the poke lasts from {:.4g} to {:.4g} s",
                                  r.clock_shift, laser_first, laser_last, t_begin, t_end),
                      ErrorContext{ll.file, 0, 0, ""}, "a laser log that covers the whole poke");
  }
  const std::size_t n = static_cast<std::size_t>(std::floor((t_end - t_begin) * r.common_rate)) + 1;
  double peak_force = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const double t = t_begin + static_cast<double>(i) / r.common_rate;
    const double tl = t - r.clock_shift;
    double f = interpolate(r.force_filtered.t, r.force_filtered.v, t);
    if (o.tare) f -= fw.rest_level(t);
    const double d = interpolate(activity.t, activity.v, tl) - lw.rest_level(tl);
    r.time.push_back(t);
    r.force.push_back(f);
    r.indentation.push_back(d);
    if (f > peak_force) {
      peak_force = f;
      r.peak = i;
    }
  }
  const double d_peak = r.indentation[r.peak];
  if (!(d_peak > 0.0)) {
    throw_input_error(fmt::format("at the force peak ({:.4g} N at {:.4g} s) the laser is not closer than at rest "
                                  "(indentation {:.4g} mm)",
                                  peak_force, r.time[r.peak], d_peak * 1e3),
                      ErrorContext{ll.file, 0, 0, "column '" + ll.value.name + "'"},
                      "a laser distance that shrinks while the force rises (check the calibration's direction)");
  }
  // The curves come from the raw samples, not the filtered signals: each force
  // sample with the laser's distance at its time. A filter in time mixes
  // force and indentation from neighbouring instants, which a tremor near the
  // cut-off or a bend of the ramp turns into a bias of several percent at small
  // indentation; the pairs lie on the curve whatever the motion, and a smooth
  // curve along the indentation (a P-spline, its smoothness chosen by
  // cross-validation) averages the gauge's noise instead.
  const double t_peak = r.time[r.peak];
  for (std::size_t i = 0; i < fl.signal.size(); ++i) {
    const double t = fl.signal.t[i];
    if (t < t_begin || t > t_end) continue;
    const double tl = t - r.clock_shift;
    double f = fl.signal.v[i];
    if (o.tare) f -= fw.rest_level(t);
    const double d = -interpolate_cubic(r.laser_distance_raw.t, r.laser_distance_raw.v, tl) - lw.rest_level(tl);
    if (t <= t_peak) r.pairs_peak = r.pair_time.size() + 1;
    r.pair_time.push_back(t);
    r.pair_indentation.push_back(d);
    r.pair_force.push_back(f);
  }
  // (The log checks, the filter's Nyquist limit and the rest plateaus refuse
  // such a log first in every case tried; this keeps the curve from being
  // drawn through a single sample should one get through.)
  if (r.pairs_peak < 2) {
    throw_input_error(fmt::format("{} force sample{} between the poke's start ({:.4g} s) and its maximum force ({:.4g} s)",
                                  r.pairs_peak, r.pairs_peak == 1 ? "" : "s", t_begin, t_peak),
                      ErrorContext{fl.file, 0, 0, "column '" + fl.value.name + "'"},
                      "a force log sampled often enough to follow the loading (tens of samples)");
  }
  const auto first_i = std::span(r.pair_indentation).first(r.pairs_peak);
  const auto first_f = std::span(r.pair_force).first(r.pairs_peak);
  r.loading = uniform_curve(first_i, first_f, d_peak, o.points, &r.loading_spline);
  const auto rest_i = std::span(r.pair_indentation).subspan(r.pairs_peak > 0 ? r.pairs_peak - 1 : 0);
  const auto rest_f = std::span(r.pair_force).subspan(r.pairs_peak > 0 ? r.pairs_peak - 1 : 0);
  r.unloading = uniform_curve(rest_i, rest_f, d_peak, o.points, &r.unloading_spline);
  return r;
}

report::Figure poke_signals_figure(const PokeResult& r) {
  report::Figure fig;
  fig.title = "poke signals (force clock; laser shifted by " + fmt::format("{:.4g} s)", r.clock_shift);
  fig.columns = 1;
  fig.plot_width = 720;
  auto window_series = [](const PokeWindow& w, double shift, double lo, double hi, double scale) {
    report::Series s{"poke window", {}, {}, report::Mark::Line, 6, true};
    for (double t : {w.start, w.end}) {
      s.x.insert(s.x.end(), {t + shift, t + shift, std::numeric_limits<double>::quiet_NaN()});
      s.y.insert(s.y.end(), {lo * scale, hi * scale, std::numeric_limits<double>::quiet_NaN()});
    }
    return s;
  };
  {
    report::Plot& p = fig.plots.emplace_back();
    p.title = "force";
    p.x.label = "time [s]";
    p.y.label = "force [N]";
    p.series.push_back({"raw", r.force_log.signal.t, r.force_log.signal.v, report::Mark::Dots, 0});
    p.series.push_back({"filtered", r.force_filtered.t, r.force_filtered.v, report::Mark::Line, 1});
    const auto [lo, hi] = std::minmax_element(r.force_filtered.v.begin(), r.force_filtered.v.end());
    p.series.push_back(window_series(r.force_window, 0.0, *lo, *hi, 1.0));
  }
  {
    report::Plot& p = fig.plots.emplace_back();
    p.title = "laser distance";
    p.x.label = "time [s]";
    p.y.label = "distance [mm]";
    auto shifted_mm = [&](const Signal& s) {
      report::Series out;
      for (std::size_t i = 0; i < s.size(); ++i) {
        out.x.push_back(s.t[i] + r.clock_shift);
        out.y.push_back(s.v[i] * 1e3);
      }
      return out;
    };
    report::Series raw = shifted_mm(r.laser_distance_raw);
    raw.label = "raw";
    raw.mark = report::Mark::Dots;
    raw.color = 0;
    report::Series filt = shifted_mm(r.distance_filtered);
    filt.label = "filtered";
    filt.color = 1;
    p.series.push_back(std::move(raw));
    p.series.push_back(std::move(filt));
    const auto [lo, hi] = std::minmax_element(r.distance_filtered.v.begin(), r.distance_filtered.v.end());
    p.series.push_back(window_series(r.laser_window, r.clock_shift, *lo, *hi, 1e3));
  }
  // One time axis for both plots.
  const double t0 = std::min(r.force_log.signal.t.front(), r.laser_distance_raw.t.front() + r.clock_shift);
  const double t1 = std::max(r.force_log.signal.t.back(), r.laser_distance_raw.t.back() + r.clock_shift);
  for (report::Plot& p : fig.plots) {
    p.x.min = t0;
    p.x.max = t1;
  }
  return fig;
}

report::Figure poke_curve_figure(const PokeResult& r) {
  report::Figure fig;
  report::Plot& p = fig.plots.emplace_back();
  p.title = "force-indentation";
  p.x.label = "indentation [mm]";
  p.y.label = "force [N]";
  auto mm = [](std::span<const double> v) {
    std::vector<double> out(v.begin(), v.end());
    for (double& x : out) x *= 1e3;
    return out;
  };
  p.series.push_back({"samples", mm(r.pair_indentation), r.pair_force, report::Mark::Dots, 5});
  p.series.push_back({"loading", mm(r.loading.indentation), r.loading.force, report::Mark::Line, 1});
  p.series.push_back({"unloading", mm(r.unloading.indentation), r.unloading.force, report::Mark::Line, 2, true});
  return fig;
}

}  // namespace palpa::acquire
