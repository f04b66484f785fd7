// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/report/pressure_metrics.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <cmath>
#include <numbers>
#include <numeric>
#include <utility>
#include <vector>

#include "palpa/core/error.hpp"
#include "palpa/geometry/surface_operators.hpp"

namespace palpa::report {

namespace {

// Vertices with area hashed into cubes of side `cell`, for the windows'
// nearest-vertex queries.
class VertexGrid {
 public:
  VertexGrid(const Eigen::MatrixX3d& V, const std::vector<Eigen::Index>& vertices, double cell) : V_(V), cell_(cell) {
    for (Eigen::Index v : vertices) cells_[key(cell_of(V.row(v)))].push_back(v);
  }
  // Appends (squared distance, vertex) of every vertex within `radius` of x.
  void within(const Eigen::Vector3d& x, double radius, std::vector<std::pair<double, Eigen::Index>>& out) const {
    const Eigen::Vector3i c = cell_of(x.transpose());
    const int reach = static_cast<int>(std::ceil(radius / cell_));
    for (int i = -reach; i <= reach; ++i) {
      for (int j = -reach; j <= reach; ++j) {
        for (int k = -reach; k <= reach; ++k) {
          const auto it = cells_.find(key(c + Eigen::Vector3i(i, j, k)));
          if (it == cells_.end()) continue;
          for (Eigen::Index v : it->second) {
            const double d2 = (V_.row(v).transpose() - x).squaredNorm();
            if (d2 <= radius * radius) out.emplace_back(d2, v);
          }
        }
      }
    }
  }

 private:
  Eigen::Vector3i cell_of(const Eigen::RowVector3d& x) const {
    return (x / cell_).array().floor().cast<int>().transpose();
  }
  static std::int64_t key(const Eigen::Vector3i& c) {
    // 21 bits per coordinate: cubes of a few cm over kilometres.
    const auto part = [](int v) { return static_cast<std::int64_t>(v) & ((std::int64_t{1} << 21) - 1); };
    return part(c.x()) | (part(c.y()) << 21) | (part(c.z()) << 42);
  }

  const Eigen::MatrixX3d& V_;
  double cell_;
  std::unordered_map<std::int64_t, std::vector<Eigen::Index>> cells_;
};

// The window around vertex c: the nearest vertices until their areas reach
// `window` (all of them if there is not that much area). Returns (Σ A p, Σ A)
// over it; `order` is scratch.
std::pair<double, double> window_sums(const VertexGrid& grid, const Eigen::MatrixX3d& V, const Eigen::VectorXd& area,
                                      const Eigen::VectorXd& p, double total_area, Eigen::Index c, double window,
                                      std::vector<std::pair<double, Eigen::Index>>& order) {
  // A little more than the radius of a disc of the window's area, grown
  // until it holds enough area (a curved or ragged surface).
  double radius = 1.15 * std::sqrt(window / std::numbers::pi);
  for (;;) {
    order.clear();
    grid.within(V.row(c).transpose(), radius, order);
    double held = 0.0;
    for (const auto& [d2, j] : order) held += area[j];
    if (held >= std::min(window, total_area)) break;
    radius *= 1.5;
  }
  std::sort(order.begin(), order.end());
  double force = 0.0, a = 0.0;
  for (const auto& [d2, j] : order) {
    if (a >= window) break;
    force += area[j] * p[j];
    a += area[j];
  }
  return {force, a};
}

}  // namespace

PressureMetrics pressure_metrics(const Eigen::MatrixX3d& V, const Eigen::VectorXd& area,
                                 const Eigen::VectorXd& pressure, const PressureMetricsOptions& options) {
  Eigen::VectorXd in_contact = Eigen::VectorXd::Zero(area.size());
  for (Eigen::Index i = 0; i < std::min(area.size(), pressure.size()); ++i) {
    if (pressure[i] > options.threshold) in_contact[i] = area[i];
  }
  return pressure_metrics(V, area, pressure, in_contact, options);
}

PressureMetrics pressure_metrics(const Eigen::MatrixX3d& V, const Eigen::VectorXd& area,
                                 const Eigen::VectorXd& pressure, const Eigen::VectorXd& contact_area,
                                 const PressureMetricsOptions& options) {
  if (area.size() != V.rows() || pressure.size() != V.rows() || contact_area.size() != V.rows()) {
    throw Error(ErrorKind::Input, fmt::format("a pressure map of {} vertices with {} areas and {} pressures", V.rows(),
                                              area.size(), pressure.size()));
  }
  if (!(options.window_area > 0.0) || !std::isfinite(options.window_area)) {
    throw Error(ErrorKind::Input, fmt::format("the peak pressure index's window must be > 0 m², got {}", options.window_area));
  }
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    if (!std::isfinite(pressure[i]) || pressure[i] < 0.0 || !std::isfinite(area[i]) || area[i] < 0.0) {
      throw Error(ErrorKind::Input, fmt::format("vertex {} of a pressure map has pressure {} Pa and area {} m²", i,
                                                pressure[i], area[i]));
    }
    if (!(contact_area[i] >= 0.0 && contact_area[i] <= area[i] * (1.0 + 1e-9))) {
      throw Error(ErrorKind::Input, fmt::format("vertex {} of a pressure map has {} m² in contact of its {} m²", i,
                                                contact_area[i], area[i]));
    }
  }
  PressureMetrics m;
  std::vector<Eigen::Index> contact, candidates;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    if (area[i] > 0.0) candidates.push_back(i);
    m.force += area[i] * pressure[i];
    if (pressure[i] > options.threshold && area[i] > 0.0) {
      contact.push_back(i);
      m.contact_area += contact_area[i];
      m.centre += area[i] * pressure[i] * V.row(i).transpose();
    }
  }
  m.contact_vertices = static_cast<int>(contact.size());
  if (contact.empty() || !(m.force > 0.0) || !(m.contact_area > 0.0)) return PressureMetrics{};
  m.centre /= m.force;
  m.mean = m.force / m.contact_area;
  m.peak = pressure.maxCoeff();

  // The 95th percentile by area.
  std::vector<Eigen::Index> by_pressure = contact;
  std::sort(by_pressure.begin(), by_pressure.end(), [&](Eigen::Index a, Eigen::Index b) { return pressure[a] < pressure[b]; });
  double below = 0.0;
  for (Eigen::Index i : by_pressure) {
    below += contact_area[i];
    m.p95 = pressure[i];
    if (below >= 0.95 * m.contact_area) break;
  }

  // The peak pressure index: every contact vertex as a window's centre.
  double total_area = 0.0;
  for (Eigen::Index j : candidates) total_area += area[j];
  const VertexGrid grid(V, candidates, std::sqrt(options.window_area));
  std::vector<std::pair<double, double>> sums(contact.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, contact.size(), 16), [&](const tbb::blocked_range<std::size_t>& r) {
    std::vector<std::pair<double, Eigen::Index>> order;
    for (std::size_t k = r.begin(); k != r.end(); ++k) {
      sums[k] = window_sums(grid, V, area, pressure, total_area, contact[k], options.window_area, order);
    }
  });
  double best_force = 0.0;
  for (const auto& [f, a] : sums) {
    if (a > 0.0 && f / a > m.peak_pressure_index) {
      m.peak_pressure_index = f / a;
      best_force = f;
    }
  }
  m.dispersion_index = best_force / m.force;
  return m;
}

PressureMetrics pressure_metrics(const SurfaceMesh& mesh, const Eigen::VectorXd& pressure,
                                 const PressureMetricsOptions& options) {
  return pressure_metrics(mesh.V, geometry::vertex_areas(mesh), pressure, options);
}

Json to_json(const PressureMetrics& m) {
  return Json{{"force_N", m.force},
              {"contact_area_m2", m.contact_area},
              {"mean_Pa", m.mean},
              {"peak_Pa", m.peak},
              {"peak_pressure_index_Pa", m.peak_pressure_index},
              {"p95_Pa", m.p95},
              {"centre_m", {m.centre.x(), m.centre.y(), m.centre.z()}},
              {"dispersion_index", m.dispersion_index},
              {"contact_vertices", m.contact_vertices}};
}

}  // namespace palpa::report
