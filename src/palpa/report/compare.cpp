// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/report/compare.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "palpa/core/error.hpp"
#include "palpa/geometry/closest_point.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/io/ply.hpp"
#include "palpa/io/vtu.hpp"

namespace palpa::report {

namespace {

[[noreturn]] void fail(const std::string& file, const std::string& what, const std::string& expected) {
  ErrorContext c;
  c.file = file;
  throw_input_error(what, c, expected);
}

}  // namespace

PressureMap read_pressure_map(const std::filesystem::path& path, const std::string& field) {
  PressureMap m;
  m.source = path.string();
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".ply") {
    const PlyContents c = read_ply_with_scalars(path);
    m.mesh = c.mesh;
    for (const auto& s : c.vertex_scalars) {
      if (s.name == field) m.pressure = s.values;
    }
  } else if (ext == ".vtu") {
    const UnstructuredGrid g = read_vtu(path);
    m.mesh.V = g.points;
    for (const CellBlock& b : g.cells) {
      if (b.type != VtkCellType::Triangle) fail(m.source, "the grid has cells other than triangles", "a triangle surface");
      const Eigen::Index r0 = m.mesh.F.rows();
      m.mesh.F.conservativeResize(r0 + b.nodes.rows(), 3);
      m.mesh.F.bottomRows(b.nodes.rows()) = b.nodes;
    }
    if (const DataArray* d = g.find_point_data(field)) {
      if (d->values.cols() != 1) fail(m.source, fmt::format("'{}' has {} components", field, d->values.cols()), "a scalar");
      m.pressure = d->values.col(0);
    }
  } else {
    fail(m.source, fmt::format("unknown pressure-map format '{}'", ext), ".ply or .vtu with a per-vertex pressure");
  }
  if (m.pressure.size() != m.mesh.V.rows()) {
    fail(m.source, fmt::format("no per-vertex field '{}'", field), fmt::format("a vertex scalar '{}' [Pa]", field));
  }
  if (m.mesh.F.rows() == 0) fail(m.source, "the map has no triangles", "a triangle surface");
  for (Eigen::Index i = 0; i < m.pressure.size(); ++i) {
    if (!std::isfinite(m.pressure[i]) || m.pressure[i] < 0.0 || m.pressure[i] > kMaxMapPressure) {
      fail(m.source, fmt::format("vertex {} has pressure {} Pa", i, m.pressure[i]),
           fmt::format("pressures from 0 to {:g} Pa", kMaxMapPressure));
    }
  }
  return m;
}

MapComparison compare_pressure_maps(const PressureMap& a, const PressureMap& b) {
  if (a.mesh.V.rows() != b.mesh.V.rows()) {
    fail(a.source, fmt::format("{} vertices against {} in {}", a.mesh.V.rows(), b.mesh.V.rows(), b.source),
         "two maps on the same support mesh, or a transfer of one onto the other's (palpa compare --transfer)");
  }
  const double size = (a.mesh.V.colwise().maxCoeff() - a.mesh.V.colwise().minCoeff()).norm();
  const double moved = (a.mesh.V - b.mesh.V).rowwise().norm().maxCoeff();
  if (moved > 1e-6 * size) {
    fail(a.source, fmt::format("its vertices lie up to {:.3g} m from those of {}", moved, b.source),
         "two maps on the same support mesh, or a transfer of one onto the other's (palpa compare --transfer)");
  }
  const Eigen::VectorXd A = geometry::vertex_areas(a.mesh);
  MapComparison c;
  c.a = pressure_metrics(a.mesh.V, A, a.pressure);
  c.b = pressure_metrics(a.mesh.V, A, b.pressure);
  double w = 0.0, ma = 0.0, mb = 0.0;
  for (Eigen::Index i = 0; i < A.size(); ++i) {
    if (a.pressure[i] <= 0.0 && b.pressure[i] <= 0.0) continue;
    ++c.vertices;
    w += A[i];
    ma += A[i] * a.pressure[i];
    mb += A[i] * b.pressure[i];
    c.max_difference = std::max(c.max_difference, std::abs(a.pressure[i] - b.pressure[i]));
  }
  if (c.vertices == 0 || !(w > 0.0)) fail(a.source, fmt::format("neither map has contact (nor {})", b.source), "a pressure > 0 somewhere");
  ma /= w;
  mb /= w;
  double sd = 0.0, caa = 0.0, cbb = 0.0, cab = 0.0;
  for (Eigen::Index i = 0; i < A.size(); ++i) {
    if (a.pressure[i] <= 0.0 && b.pressure[i] <= 0.0) continue;
    const double da = a.pressure[i] - ma, db = b.pressure[i] - mb;
    sd += A[i] * (a.pressure[i] - b.pressure[i]) * (a.pressure[i] - b.pressure[i]);
    caa += A[i] * da * da;
    cbb += A[i] * db * db;
    cab += A[i] * da * db;
  }
  c.rms_difference = std::sqrt(sd / w);
  c.relative_rms = mb > 0.0 ? c.rms_difference / mb : 0.0;
  c.correlation = caa > 0.0 && cbb > 0.0 ? cab / std::sqrt(caa * cbb) : std::numeric_limits<double>::quiet_NaN();
  return c;
}

PressureMap transfer_pressure_map(const PressureMap& from, const SurfaceMesh& onto, MapTransfer* t) {
  PressureMap out;
  out.mesh = onto;
  out.source = from.source + " (moved by closest point)";
  out.pressure.resize(onto.V.rows());
  const geometry::TriangleTree tree(from.mesh.V, from.mesh.F);
  MapTransfer figures;
  for (Eigen::Index v = 0; v < onto.V.rows(); ++v) {
    const geometry::SurfacePoint q = geometry::closest_point(from.mesh, tree, onto.V.row(v).transpose());
    double p = 0.0;
    for (int k = 0; k < 3; ++k) p += q.barycentric[k] * from.pressure[from.mesh.F(q.face, k)];
    out.pressure[v] = std::max(0.0, p);
    figures.max_distance = std::max(figures.max_distance, q.distance);
    figures.mean_distance += q.distance;
  }
  if (onto.V.rows() > 0) figures.mean_distance /= static_cast<double>(onto.V.rows());
  if (t != nullptr) *t = figures;
  return out;
}

MapComparison compare_across_meshes(const PressureMap& a, const PressureMap& b, MapTransfer* t) {
  MapComparison c = compare_pressure_maps(a, transfer_pressure_map(b, a.mesh, t));
  c.b = pressure_metrics(b.mesh, b.pressure);
  return c;
}

}  // namespace palpa::report
