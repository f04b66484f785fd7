// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/acquire/ultrasound.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cassert>
#include <cmath>

#include "palpa/acquire/filter.hpp"
#include "palpa/core/error.hpp"

namespace palpa::acquire {

namespace {

// Samples per second of a spline, and of the grid, for the clock alignment.
constexpr double kSplineRate = 1000.0;

}  // namespace

CatmullRom::CatmullRom(std::vector<double> t, std::vector<double> y) : t_(std::move(t)), y_(std::move(y)) {
  assert(t_.size() >= 2 && t_.size() == y_.size());
  const std::size_t n = t_.size();
  slope_.resize(n);
  slope_.front() = (y_[1] - y_[0]) / (t_[1] - t_[0]);
  slope_.back() = (y_[n - 1] - y_[n - 2]) / (t_[n - 1] - t_[n - 2]);
  for (std::size_t i = 1; i + 1 < n; ++i) slope_[i] = (y_[i + 1] - y_[i - 1]) / (t_[i + 1] - t_[i - 1]);
}

double CatmullRom::operator()(double t) const {
  if (t <= t_.front()) return y_.front() + slope_.front() * (t - t_.front());
  if (t >= t_.back()) return y_.back() + slope_.back() * (t - t_.back());
  const std::size_t i = static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin()) - 1;
  const double h = t_[i + 1] - t_[i];
  const double s = (t - t_[i]) / h;
  const double s2 = s * s, s3 = s2 * s;
  // Cubic Hermite basis.
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  return h00 * y_[i] + h10 * h * slope_[i] + h01 * y_[i + 1] + h11 * h * slope_[i + 1];
}

InterfacePicks read_interface_picks(const std::string& name, const std::filesystem::path& path,
                                    const ColumnSpec& time, const ColumnSpec& depth) {
  const CsvTable table = read_csv(path);
  const Dimension tk[] = {Dimension::Time};
  const Dimension dk[] = {Dimension::Length};
  const std::string role = fmt::format("interface '{}'", name);
  Column t = read_column(table, time, tk, role + " time");
  Column d = read_column(table, depth, dk, role + " depth");
  if (table.rows() < 2) {
    throw_input_error(fmt::format("interface '{}' has {} pick(s)", name, table.rows()),
                      ErrorContext{path.string(), 0, 0, ""}, "at least 2 control points (time, depth)");
  }
  for (std::size_t i = 0; i < table.rows(); ++i) {
    if (i > 0 && !(t.si[i] > t.si[i - 1])) {
      throw_input_error(fmt::format("pick time {} s is not after the previous pick's {} s", t.si[i], t.si[i - 1]),
                        table.context_of(i, t.name), "picks sorted by strictly increasing time");
    }
    if (d.si[i] < 0.0) {
      throw_input_error(fmt::format("depth {} m is negative", d.si[i]), table.context_of(i, d.name),
                        "depths below the skin (>= 0)");
    }
  }
  return {name, path.string(), std::move(t.si), std::move(d.si)};
}

UltrasoundResult process_ultrasound(const std::filesystem::path& force_file,
                                    const std::vector<std::pair<std::string, std::filesystem::path>>& interfaces,
                                    const UltrasoundOptions& o) {
  if (interfaces.empty()) {
    throw_input_error("no interface picks were given", ErrorContext{"", 0, 0, "option --interface"},
                      "at least one NAME=FILE");
  }
  UltrasoundResult r;
  const Dimension force_kind[] = {Dimension::Force};
  r.force_log = read_log(force_file, o.force_time, o.force_value, force_kind, "force", o.check);
  check_not_clipped(r.force_log, Extreme::Max, o.saturation);
  r.force_filtered = lowpass(r.force_log.signal, o.order, o.cutoff);
  const std::string what = fmt::format("force log '{}' (column {})", r.force_log.file, r.force_log.value.name);
  r.force_window = o.force_window ? poke_from_window(r.force_filtered, o.force_window->start, o.force_window->end,
                                                     o.plateau.min_duration, what, "--force-window")
                                  : detect_poke(r.force_filtered, o.plateau, what, "--force-window");
  const PokeWindow& fw = r.force_window;
  std::vector<CatmullRom> splines;
  for (const auto& [name, path] : interfaces) {
    r.interfaces.push_back(read_interface_picks(name, path, o.pick_time, o.pick_depth));
    splines.emplace_back(r.interfaces.back().t, r.interfaces.back().depth);
  }

  // Clocks: the first interface is compressed while the force rises.
  r.clock_shift = o.offset;
  if (o.align) {
    const CatmullRom& s0 = splines.front();
    Signal compression;
    const std::size_t n = static_cast<std::size_t>(std::floor((s0.t_last() - s0.t_first()) * kSplineRate)) + 1;
    for (std::size_t i = 0; i < n; ++i) {
      const double t = s0.t_first() + static_cast<double>(i) / kSplineRate;
      compression.t.push_back(t);
      compression.v.push_back(-s0(t));
    }
    const double margin = 0.1 * (fw.end - fw.start);
    const double dt = 1.0 / kSplineRate;
    const Alignment al = align_by_rank(r.force_filtered, compression, std::max(fw.start - margin, fw.before.t0),
                                       std::min(fw.end + margin, fw.after.t1), dt, o.offset, o.search);
    r.clock_shift = al.shift;
    r.correlation = al.correlation;
  }

  // Loading samples on the force clock.
  const Signal& f = r.force_filtered;
  std::size_t peak = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (f.t[i] >= fw.start && f.t[i] <= fw.end && (peak == 0 || f.v[i] > f.v[peak])) peak = i;
  }
  for (std::size_t i = 0; i <= peak; ++i) {
    if (f.t[i] < fw.start) continue;
    r.time.push_back(f.t[i]);
    r.force.push_back(f.v[i] - (o.tare ? fw.rest_level(f.t[i]) : 0.0));
  }
  if (r.time.size() < 2) {
    throw_input_error(fmt::format("{}: the poke from {} to its maximum at {} holds fewer than 2 samples", what,
                                  format_seconds(fw.start), format_seconds(f.t[peak])),
                      ErrorContext{"", 0, 0, "option --force-window"}, "a poke window around the loading");
  }
  const double load0 = r.time.front() - r.clock_shift, load1 = r.time.back() - r.clock_shift;
  for (std::size_t k = 0; k < splines.size(); ++k) {
    const CatmullRom& s = splines[k];
    const InterfacePicks& picks = r.interfaces[k];
    const double rest0 = std::max(fw.before.t0 - r.clock_shift, s.t_first());
    const double rest1 = fw.before.t1 - r.clock_shift;
    if (s.t_first() > load0 || s.t_last() < load1 || rest0 > rest1) {
      throw_input_error(
          fmt::format("the picks of interface '{}' cover {} .. {} on the ultrasound clock, but the rest before the poke "
                      "ends at {} and the loading lasts until {} (ultrasound time + {:.4g} s = force time)",
                      picks.name, format_seconds(s.t_first()), format_seconds(s.t_last()), format_seconds(rest1), format_seconds(load1),
                      r.clock_shift),
          ErrorContext{picks.file, 0, 0, ""},
          "picks from the rest before the poke to the maximum force (or give the clock offset with --offset)");
    }
    // Mean over the covered part of the rest plateau.
    constexpr int kRestSamples = 50;
    double sum = 0.0;
    for (int j = 0; j <= kRestSamples; ++j) sum += s(rest0 + (rest1 - rest0) * j / kRestSamples);
    r.rest_depth.push_back(sum / (kRestSamples + 1));
    std::vector<double> d;
    for (double t : r.time) d.push_back(s(t - r.clock_shift));
    r.depth.push_back(std::move(d));
  }
  return r;
}

CsvTable add_depth_row(const CsvTable& existing, const std::array<double, 3>& position,
                       const std::vector<std::string>& names, const std::vector<double>& rest_depth,
                       std::size_t main_interface) {
  std::vector<std::string> columns{"x_m", "y_m", "z_m", "depth_m"};
  for (const std::string& n : names) columns.push_back(n + "_depth_m");
  std::vector<std::vector<double>> values(columns.size());
  if (existing.column_count() > 0) {
    if (existing.names() != columns) {
      std::string want;
      for (const std::string& c : columns) want += (want.empty() ? "" : ",") + c;
      throw_input_error("the depth table has other columns than this measurement",
                        ErrorContext{existing.source(), 0, 0, ""},
                        fmt::format("the header {} (the same interfaces in the same order)", want));
    }
    for (std::size_t row = 0; row < existing.rows(); ++row) {
      if (existing.column(std::size_t{0})[row] == position[0] && existing.column(std::size_t{1})[row] == position[1] &&
          existing.column(std::size_t{2})[row] == position[2]) {
        continue;  // replaced below
      }
      for (std::size_t c = 0; c < columns.size(); ++c) values[c].push_back(existing.column(c)[row]);
    }
  }
  for (std::size_t k = 0; k < 3; ++k) values[k].push_back(position[k]);
  values[3].push_back(rest_depth.at(main_interface));
  for (std::size_t k = 0; k < names.size(); ++k) values[4 + k].push_back(rest_depth[k]);
  CsvTable out(existing.source());
  out.add_comment(existing.comments().empty() ? "rest depths below the skin per location (palpa acquire ultrasound)"
                                              : existing.comments().front());
  for (std::size_t c = 0; c < columns.size(); ++c) out.add_column(columns[c], std::move(values[c]));
  return out;
}

report::Figure ultrasound_figure(const UltrasoundResult& r) {
  report::Figure fig;
  report::Plot& p = fig.plots.emplace_back();
  p.title = "interface depth while loading";
  p.x.label = "force [N]";
  p.y.label = "depth below the skin [mm]";
  for (std::size_t k = 0; k < r.interfaces.size(); ++k) {
    std::vector<double> mm = r.depth[k];
    for (double& v : mm) v *= 1e3;
    p.series.push_back({r.interfaces[k].name, r.force, mm, report::Mark::Line, static_cast<int>(k)});
  }
  return fig;
}

}  // namespace palpa::acquire
