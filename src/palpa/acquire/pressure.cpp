// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/acquire/pressure.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include "palpa/acquire/signal.hpp"
#include "palpa/core/error.hpp"
#include "palpa/geometry/edge_distance.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/io/csv.hpp"

namespace palpa::acquire {

namespace {

// The values of the column named `name` exactly, or of the one column whose
// base name is `name` (reading_V), as stored: only ratios matter.
const std::vector<double>* find_raw_column(const CsvTable& table, const std::string& name, std::string* found) {
  if (table.has_column(name)) {
    *found = name;
    return &table.column(name);
  }
  const std::vector<double>* out = nullptr;
  for (const std::string& c : table.names()) {
    if (split_quantity_name(c).base == name && !split_quantity_name(c).suffix.empty()) {
      if (out != nullptr) {
        throw_input_error(fmt::format("several columns are named '{}_<unit>'", name),
                          ErrorContext{table.source(), 0, 0, ""}, "one column per quantity");
      }
      out = &table.column(c);
      *found = c;
    }
  }
  return out;
}

long location_id(const CsvTable& table, std::size_t row, double value) {
  if (value != std::floor(value) || std::abs(value) > 1e15) {
    throw_input_error(fmt::format("location {} is not an integer", value), table.context_of(row, "location"),
                      "integer location ids");
  }
  return static_cast<long>(value);
}

// The largest distance from a location to its nearest other location: a
// vertex farther than this from every location lies outside the mat.
double sensor_spacing(const Eigen::MatrixX3d& positions) {
  double spacing = 0.0;
  for (Eigen::Index i = 0; i < positions.rows(); ++i) {
    double nearest = std::numeric_limits<double>::infinity();
    for (Eigen::Index j = 0; j < positions.rows(); ++j) {
      if (j != i) nearest = std::min(nearest, (positions.row(j) - positions.row(i)).norm());
    }
    spacing = std::max(spacing, nearest);
  }
  return spacing > 0.0 ? spacing : std::numeric_limits<double>::infinity();
}

}  // namespace

TrimmedStats trimmed_stats(std::span<const double> v, std::size_t trim) {
  assert(v.size() >= 2 * trim + 2);
  std::vector<double> s(v.begin(), v.end());
  std::sort(s.begin(), s.end());
  const auto first = s.begin() + static_cast<std::ptrdiff_t>(trim);
  const auto last = s.end() - static_cast<std::ptrdiff_t>(trim);
  TrimmedStats out;
  out.kept = static_cast<std::size_t>(last - first);
  out.mean = std::accumulate(first, last, 0.0) / static_cast<double>(out.kept);
  double ss = 0.0;
  for (auto it = first; it != last; ++it) ss += (*it - out.mean) * (*it - out.mean);
  out.std = std::sqrt(ss / static_cast<double>(out.kept - 1));
  return out;
}

PressureMap pressure_map(const SurfaceMesh& mesh, const std::filesystem::path& locations_file,
                         const std::filesystem::path& samples_file, const PressureOptions& o) {
  if (!(o.load > 0.0) || !std::isfinite(o.load)) {
    throw_input_error(fmt::format("load {} N is not positive", o.load), ErrorContext{"", 0, 0, "option --load"},
                      "the net force the support carries, e.g. half the body weight");
  }
  // Locations.
  const CsvTable lt = read_csv(locations_file);
  const std::vector<double>& ids = lt.column("location");
  const std::vector<double> x = lt.quantity("x", Dimension::Length);
  const std::vector<double> y = lt.quantity("y", Dimension::Length);
  const std::vector<double> z = lt.quantity("z", Dimension::Length);
  PressureMap map;
  std::map<long, std::size_t> index;
  std::vector<std::string> labels;
  for (std::size_t i = 0; i < lt.rows(); ++i) {
    SensorLocation loc;
    loc.id = location_id(lt, i, ids[i]);
    loc.position = {x[i], y[i], z[i]};
    if (!index.emplace(loc.id, i).second) {
      throw_input_error(fmt::format("location {} is listed twice", loc.id), lt.context_of(i, "location"),
                        "one row per location");
    }
    map.locations.push_back(loc);
    labels.push_back(fmt::format("location {} ({}:{})", loc.id, locations_file.string(), lt.line_of_row(i)));
  }

  // Samples, grouped per location in file order.
  const CsvTable st = read_csv(samples_file);
  const std::vector<double>& sample_ids = st.column("location");
  std::string reading_name, reference_name;
  const std::vector<double>* reading = find_raw_column(st, o.reading_column, &reading_name);
  if (reading == nullptr) {
    throw_input_error(fmt::format("no column '{}'", o.reading_column), ErrorContext{st.source(), 0, 0, ""},
                      "columns location, reading and (optionally) reference");
  }
  const std::vector<double>* reference = find_raw_column(st, o.reference_column, &reference_name);
  map.compensated = reference != nullptr;
  std::vector<std::vector<double>> readings(map.locations.size()), references(map.locations.size());
  std::vector<std::vector<std::size_t>> rows(map.locations.size());
  for (std::size_t r = 0; r < st.rows(); ++r) {
    const long id = location_id(st, r, sample_ids[r]);
    const auto it = index.find(id);
    if (it == index.end()) {
      throw_input_error(fmt::format("location {} is not in the locations file '{}'", id, locations_file.string()),
                        st.context_of(r, "location"), "samples of listed locations only");
    }
    readings[it->second].push_back((*reading)[r]);
    if (reference) references[it->second].push_back((*reference)[r]);
    rows[it->second].push_back(r);
  }
  for (std::size_t i = 0; i < map.locations.size(); ++i) {
    SensorLocation& loc = map.locations[i];
    loc.samples = readings[i].size();
    if (loc.samples < 2 * o.trim + 2) {
      throw_input_error(fmt::format("location {} has {} samples", loc.id, loc.samples),
                        ErrorContext{samples_file.string(), 0, 0, ""},
                        fmt::format("at least {} (2 × --trim {} + 2)", 2 * o.trim + 2, o.trim));
    }
    const auto check_clipped = [&](const std::vector<double>& v, const std::string& column) {
      if (const auto run = find_clipped_run(v, std::max<std::size_t>(o.clip_run, 2), Extreme::Max)) {
        throw_input_error(fmt::format("the sensor is saturated at location {}: {} samples in a row read exactly {}",
                                      loc.id, run->last - run->first + 1, run->value),
                          st.context_of(rows[i][run->first], column),
                          "readings inside the sensor's range (a lighter load or a larger range)");
      }
    };
    check_clipped(readings[i], reading_name);
    loc.reading = trimmed_stats(readings[i], o.trim);
    // A pressure sensor reads zero unloaded: a negative mean would become a
    // negative pressure (a pull) on the map.
    if (loc.reading.mean < 0.0) {
      throw_input_error(fmt::format("the mean reading at location {} is {:.4g}, below zero", loc.id, loc.reading.mean),
                        ErrorContext{samples_file.string(), 0, 0, fmt::format("column '{}'", reading_name)},
                        "readings of zero or more (with the sensors' unloaded offset removed)");
    }
    if (reference) {
      check_clipped(references[i], reference_name);
      loc.reference = trimmed_stats(references[i], o.trim);
      if (!(loc.reference.mean > 0.0)) {
        throw_input_error(fmt::format("the reference sensor's mean at location {} is {}", loc.id, loc.reference.mean),
                          ErrorContext{samples_file.string(), 0, 0, fmt::format("column '{}'", reference_name)},
                          "a positive reference reading to compensate the posture with");
      }
    } else {
      loc.reference = {1.0, 0.0, loc.samples};
    }
  }

  // Interpolate the compensated ratios, then scale to the load.
  const auto n = static_cast<Eigen::Index>(map.locations.size());
  Eigen::MatrixX3d positions(n, 3);
  Eigen::MatrixXd values(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    const SensorLocation& loc = map.locations[static_cast<std::size_t>(i)];
    positions.row(i) = loc.position.transpose();
    values(i, 0) = loc.reading.mean / loc.reference.mean;
    values(i, 1) = loc.reading.std / loc.reference.mean;
  }
  geometry::InterpolationOptions io = o.interpolation;
  io.source = locations_file.string();
  io.sample_labels = labels;
  const geometry::SurfaceInterpolator interp(mesh, positions, io);
  Eigen::MatrixXd field = interp.interpolate_columns(values);
  // Only the covered part of the surface was measured: 0 beyond the reach.
  map.reach = o.reach > 0.0 ? o.reach : sensor_spacing(positions);
  const Eigen::VectorXd along = geometry::edge_path_distance(mesh, interp.sample_vertices(), map.reach);
  const Eigen::VectorXd areas = geometry::vertex_areas(mesh);
  for (Eigen::Index v = 0; v < field.rows(); ++v) {
    if (along(v) <= map.reach) {
      map.covered_area += areas(v);
    } else {
      field.row(v).setZero();
    }
  }
  const Eigen::Vector3d unit_force = geometry::pressure_force(mesh.V, mesh.F, field.col(0));
  if (!(unit_force.norm() > 0.0)) {
    throw_input_error("the interpolated readings carry no net force (all zero, or cancelling)",
                      ErrorContext{samples_file.string(), 0, 0, ""}, "readings that increase with the pressure");
  }
  map.constant = o.load / unit_force.norm();
  map.pressure = map.constant * field.col(0);
  map.pressure_std = map.constant * field.col(1);
  map.net_force = map.constant * unit_force;
  for (Eigen::Index v = 0; v < map.pressure.size(); ++v) {
    if (map.pressure(v) > 0.0) map.contact_area += areas(v);
  }
  for (std::size_t i = 0; i < map.locations.size(); ++i) {
    SensorLocation& loc = map.locations[i];
    loc.pressure = map.constant * values(static_cast<Eigen::Index>(i), 0);
    loc.pressure_std = map.constant * values(static_cast<Eigen::Index>(i), 1);
    loc.distance = interp.sample_points()[i].distance;
  }
  return map;
}

}  // namespace palpa::acquire
