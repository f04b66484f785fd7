// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/acquire/log.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "palpa/core/error.hpp"
#include "palpa/core/text.hpp"

namespace palpa::acquire {

namespace {

std::string kinds_text(std::span<const Dimension> kinds) {
  std::string out;
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    if (i > 0) out += i + 1 == kinds.size() ? " or " : ", ";
    out += dimension_name(kinds[i]);
  }
  return out;
}

bool allowed_kind(std::span<const Dimension> kinds, Dimension d) {
  return std::find(kinds.begin(), kinds.end(), d) != kinds.end();
}

ErrorContext header_of(const CsvTable& table, const std::string& column) {
  ErrorContext c = table.context_of(0, column);
  c.line = 0;  // the header, not a data row
  return c;
}

}  // namespace

ColumnSpec parse_column_spec(std::string_view text, const std::string& option) {
  const ErrorContext where{"", 0, 0, "option " + option};
  const std::string_view t = trim(text);
  const auto colon = t.rfind(':');
  ColumnSpec spec;
  spec.name = std::string(trim(t.substr(0, colon)));
  if (colon != std::string_view::npos) spec.unit = std::string(trim(t.substr(colon + 1)));
  if (spec.name.empty() || (colon != std::string_view::npos && spec.unit.empty())) {
    throw_input_error(fmt::format("'{}' is not a column spec", text), where,
                      "NAME or NAME:UNIT, e.g. force_N or Force:gf");
  }
  if (!spec.unit.empty() && find_unit(spec.unit) == nullptr) {
    throw_input_error(fmt::format("unknown unit '{}' in column spec '{}'", spec.unit, text), where,
                      "a unit palpa knows (see palpa units)");
  }
  return spec;
}

std::vector<ColumnSpec> parse_column_specs(std::string_view text, std::size_t count, const std::string& option) {
  const std::vector<std::string_view> parts = split(text, ',');
  if (parts.size() != count) {
    throw_input_error(fmt::format("'{}' names {} column(s)", text, parts.size()),
                      ErrorContext{"", 0, 0, "option " + option},
                      fmt::format("{} comma-separated column specs (NAME or NAME:UNIT)", count));
  }
  std::vector<ColumnSpec> specs;
  for (const auto p : parts) specs.push_back(parse_column_spec(p, option));
  return specs;
}

Column read_column(const CsvTable& table, const ColumnSpec& spec, std::span<const Dimension> allowed,
                   const std::string& role) {
  Column out;
  const std::string expected = fmt::format("a {} column ({})", role, kinds_text(allowed));
  if (!spec.unit.empty()) {
    const Unit* u = find_unit(spec.unit);
    const std::vector<double>& raw = table.column(spec.name);  // names the file and lists columns if missing
    if (u == nullptr || !allowed_kind(allowed, u->dimension)) {
      throw_input_error(fmt::format("unit '{}' is not a {}", spec.unit, kinds_text(allowed)),
                        header_of(table, spec.name), expected);
    }
    out.name = spec.name;
    out.dimension = u->dimension;
    out.si.reserve(raw.size());
    for (double v : raw) out.si.push_back(v * u->to_si);
    return out;
  }
  std::string name = spec.name;
  if (!table.has_column(name)) {
    // A base name: the one column "<name>_<unit>".
    std::vector<std::string> matches;
    for (const std::string& c : table.names()) {
      if (split_quantity_name(c).base == name && !split_quantity_name(c).suffix.empty()) matches.push_back(c);
    }
    if (matches.size() != 1) {
      std::string present;
      for (const std::string& c : table.names()) present += (present.empty() ? "" : ", ") + c;
      throw_input_error(matches.empty() ? fmt::format("no column '{}' or '{}_<unit>' (columns: {})", name, name, present)
                                        : fmt::format("several columns are named '{}_<unit>' (columns: {})", name,
                                                      present),
                        ErrorContext{table.source(), 0, 0, role + " column"},
                        expected + "; name it with the column options as NAME or NAME:UNIT");
    }
    name = matches.front();
  }
  const QuantityName q = split_quantity_name(name);
  if (q.unit == nullptr || !allowed_kind(allowed, q.unit->dimension)) {
    throw_input_error(q.suffix.empty() ? fmt::format("column '{}' has no unit in its name", name)
                                       : fmt::format("'{}' is not a unit of a {}", q.suffix, kinds_text(allowed)),
                      header_of(table, name), expected + "; give the unit as NAME:UNIT");
  }
  out.name = name;
  out.dimension = q.unit->dimension;
  for (double v : table.column(name)) out.si.push_back(v * q.unit->to_si);
  return out;
}

Log read_log(const std::filesystem::path& path, const ColumnSpec& time, const ColumnSpec& value,
             std::span<const Dimension> value_kinds, const std::string& role, const LogCheck& check) {
  const CsvTable table = read_csv(path);
  Log log;
  log.file = path.string();
  const Dimension time_kind[] = {Dimension::Time};
  log.time = read_column(table, time, time_kind, role + " time");
  log.value = read_column(table, value, value_kinds, role);
  const std::size_t n = table.rows();
  if (n < check.min_samples) {
    throw_input_error(fmt::format("the {} log has {} samples", role, n), ErrorContext{log.file, 0, 0, ""},
                      fmt::format("at least {} samples", check.min_samples));
  }
  const std::vector<double>& t = log.time.si;
  for (std::size_t i = 1; i < n; ++i) {
    if (!(t[i] > t[i - 1])) {
      throw_input_error(fmt::format("time {} s is not after the previous sample's {} s (line {})", t[i], t[i - 1],
                                    table.line_of_row(i - 1)),
                        table.context_of(i, log.time.name), "strictly increasing times (a sorted log)");
    }
  }
  log.signal.t = t;
  log.signal.v = log.value.si;
  const double step = median_step(t);
  log.rate = 1.0 / step;
  for (std::size_t i = 1; i < n; ++i) {
    if (t[i] - t[i - 1] > check.max_gap_steps * step) {
      throw_input_error(fmt::format("a gap of {:.4g} s in the recording from {} s to {} s ({:.0f} samples missing at "
                                    "{:.4g} Hz)",
                                    t[i] - t[i - 1], t[i - 1], t[i], std::round((t[i] - t[i - 1]) / step) - 1.0,
                                    log.rate),
                        table.context_of(i, log.time.name),
                        fmt::format("no step longer than {} median steps ({:.4g} s)", check.max_gap_steps,
                                    check.max_gap_steps * step));
    }
  }
  log.lines.resize(n);
  for (std::size_t i = 0; i < n; ++i) log.lines[i] = table.line_of_row(i);
  return log;
}

void check_not_clipped(const Log& log, Extreme extreme, double min_duration) {
  const std::size_t run = std::max<std::size_t>(3, static_cast<std::size_t>(std::ceil(min_duration * log.rate)));
  const auto clipped = find_clipped_run(log.signal.v, run, extreme);
  if (!clipped) return;
  const double si = clipped->value;
  throw_input_error(
      fmt::format("the sensor is saturated: {} samples in a row ({} s to {} s) sit exactly at the {} value {} (SI)",
                  clipped->last - clipped->first + 1, log.signal.t[clipped->first], log.signal.t[clipped->last],
                  extreme == Extreme::Max ? "largest" : "smallest", si),
      ErrorContext{log.file, log.lines[clipped->first], 0, fmt::format("column '{}'", log.value.name)},
      "a signal that stays inside the sensor's range (repeat the measurement with less force or a larger range)");
}

Calibration::Calibration(std::vector<double> x, std::vector<double> y, std::string file,
                         std::vector<std::size_t> lines)
    : file_(std::move(file)) {
  const std::size_t n = x.size();
  auto line = [&](std::size_t i) { return i < lines.size() ? lines[i] : 0; };
  if (n < 2 || y.size() != n) {
    throw_input_error(fmt::format("the calibration table has {} row(s)", n), ErrorContext{file_, 0, 0, ""},
                      "at least 2 rows");
  }
  for (const auto* v : {&x, &y}) {
    const bool up = (*v)[1] > (*v)[0];
    for (std::size_t i = 1; i < n; ++i) {
      const bool ok = up ? (*v)[i] > (*v)[i - 1] : (*v)[i] < (*v)[i - 1];
      if (!ok) {
        throw_input_error(fmt::format("the calibration is not monotone: {} {} follows {} ({} at the rows before)",
                                      v == &x ? "input" : "output", (*v)[i], (*v)[i - 1],
                                      up ? "increasing" : "decreasing"),
                          ErrorContext{file_, line(i), 0, v == &x ? "input column" : "output column"},
                          "strictly increasing or strictly decreasing values in both columns");
      }
    }
  }
  if (x[1] < x[0]) {
    std::reverse(x.begin(), x.end());
    std::reverse(y.begin(), y.end());
  }
  x_ = std::move(x);
  y_ = std::move(y);
}

double Calibration::x_min() const noexcept { return x_.front(); }
double Calibration::x_max() const noexcept { return x_.back(); }

double Calibration::operator()(double x, const std::string& where) const {
  if (!(x >= x_.front() && x <= x_.back())) {
    throw_input_error(fmt::format("{}: value {} (SI) is outside the calibration table '{}' ({} .. {})", where, x, file_,
                                  x_.front(), x_.back()),
                      {}, "values inside the calibrated range (a reading outside it is a saturated or misaimed laser)");
  }
  return interpolate(x_, y_, x);
}

Calibration read_calibration(const std::filesystem::path& path, const ColumnSpec& from, Dimension from_kind,
                             const ColumnSpec& to, Dimension to_kind) {
  const CsvTable table = read_csv(path);
  const Dimension fk[] = {from_kind};
  const Dimension tk[] = {to_kind};
  Column x = read_column(table, from, fk, "calibration input");
  Column y = read_column(table, to, tk, "calibration output");
  std::vector<std::size_t> lines(table.rows());
  for (std::size_t i = 0; i < lines.size(); ++i) lines[i] = table.line_of_row(i);
  return Calibration(std::move(x.si), std::move(y.si), path.string(), std::move(lines));
}

}  // namespace palpa::acquire
