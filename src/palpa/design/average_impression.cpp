// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/design/average_impression.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "palpa/core/error.hpp"
#include "palpa/mesh/csg.hpp"

namespace palpa::design {

namespace {

// Two directions across `down` (unit), so that (e1, e2, d̂) is right-handed.
std::pair<Eigen::Vector3d, Eigen::Vector3d> across(const Eigen::Vector3d& d) {
  const Eigen::Vector3d helper = std::abs(d.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = d.cross(helper).normalized();
  return {e1, d.cross(e1)};
}

}  // namespace

std::vector<double> lower_envelope(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                   const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& down) {
  const Eigen::Vector3d d = down.normalized();
  const auto [e1, e2] = across(d);
  const auto n = static_cast<Eigen::Index>(points.size());
  std::vector<double> out(points.size(), std::numeric_limits<double>::infinity());
  if (n == 0 || F.rows() == 0) return out;
  // The points in the plane across `down`, bucketed on a grid of about one
  // point per cell; each triangle visits the cells its shadow covers.
  Eigen::MatrixX2d P(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) P.row(i) << points[static_cast<std::size_t>(i)].dot(e1), points[static_cast<std::size_t>(i)].dot(e2);
  const Eigen::Vector2d lo = P.colwise().minCoeff().transpose(), hi = P.colwise().maxCoeff().transpose();
  const double span = std::max((hi - lo).maxCoeff(), 1e-12);
  const int cells = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(n))), 1, 1024);
  const double h = span / cells * (1.0 + 1e-9);
  std::vector<std::vector<Eigen::Index>> grid(static_cast<std::size_t>(cells) * static_cast<std::size_t>(cells));
  const auto cell = [&](double u, int axis) {
    return std::clamp(static_cast<int>(std::floor((u - lo[axis]) / h)), 0, cells - 1);
  };
  for (Eigen::Index i = 0; i < n; ++i) {
    grid[static_cast<std::size_t>(cell(P(i, 1), 1)) * static_cast<std::size_t>(cells) +
         static_cast<std::size_t>(cell(P(i, 0), 0))]
        .push_back(i);
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    Eigen::Matrix<double, 3, 2> q;
    Eigen::Vector3d height;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d x = V.row(F(f, k)).transpose();
      q.row(k) << x.dot(e1), x.dot(e2);
      height[k] = -x.dot(d);
    }
    const Eigen::Vector2d a = q.row(0).transpose(), b = q.row(1).transpose(), c = q.row(2).transpose();
    const double area2 = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (std::abs(area2) < 1e-18) continue;  // seen edge-on
    const Eigen::Vector2d qlo = q.colwise().minCoeff().transpose(), qhi = q.colwise().maxCoeff().transpose();
    if ((qhi.array() < lo.array()).any() || (qlo.array() > hi.array()).any()) continue;
    for (int cy = cell(qlo.y(), 1); cy <= cell(qhi.y(), 1); ++cy) {
      for (int cx = cell(qlo.x(), 0); cx <= cell(qhi.x(), 0); ++cx) {
        for (Eigen::Index i : grid[static_cast<std::size_t>(cy) * static_cast<std::size_t>(cells) + static_cast<std::size_t>(cx)]) {
          const Eigen::Vector2d p = P.row(i).transpose();
          // Barycentric weights of p in the shadow (inside: all ≥ 0).
          const double wb = ((p - a).x() * (c - a).y() - (p - a).y() * (c - a).x()) / area2;
          const double wc = ((b - a).x() * (p - a).y() - (b - a).y() * (p - a).x()) / area2;
          const double wa = 1.0 - wb - wc;
          constexpr double eps = -1e-12;
          if (wa < eps || wb < eps || wc < eps) continue;
          const double at = wa * height[0] + wb * height[1] + wc * height[2];
          double& o = out[static_cast<std::size_t>(i)];
          o = std::min(o, at);
        }
      }
    }
  }
  return out;
}

SurfaceMesh average_impression(const std::vector<const rest::RestBody*>& bodies, const SurfaceMesh& support,
                               const std::vector<int>& design_vertices, const Eigen::Vector3d& down,
                               const AverageImpressionOptions& options) {
  if (bodies.empty()) throw Error(ErrorKind::Input, "the average impression needs a body");
  if (!(options.press > 0.0) || !std::isfinite(options.press)) {
    throw Error(ErrorKind::Input, fmt::format("the impression's press must be a length > 0, got {} m", options.press));
  }
  if (!(down.norm() > 0.0)) throw Error(ErrorKind::Input, "the average impression needs gravity's direction");
  const Eigen::Vector3d d = down.normalized();
  std::vector<Eigen::Vector3d> points;
  double top = -std::numeric_limits<double>::infinity();
  for (int v : design_vertices) {
    points.push_back(support.V.row(v).transpose());
    top = std::max(top, -points.back().dot(d));
  }
  std::vector<double> dent(points.size(), 0.0);
  for (const rest::RestBody* b : bodies) {
    const Eigen::MatrixX3i skin = rest::skin_faces(b->mesh, b->attached);
    // Pressed in: its lowest skin point `press` below the support's top.
    double lowest = std::numeric_limits<double>::infinity();
    for (Eigen::Index f = 0; f < skin.rows(); ++f) {
      for (int k = 0; k < 3; ++k) lowest = std::min(lowest, -b->mesh.V.row(skin(f, k)).dot(d));
    }
    const double shift = lowest - (top - options.press);
    const std::vector<double> envelope = lower_envelope(b->mesh.V, skin, points, d);
    bool reaches = false;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (!std::isfinite(envelope[i])) continue;
      const double depth = -points[i].dot(d) - (envelope[i] - shift);
      if (depth > 0.0) {
        dent[i] += depth / static_cast<double>(bodies.size());
        reaches = true;
      }
    }
    if (!reaches) {
      throw Error(ErrorKind::Input, "a body pressed into the support reaches none of its design vertices", {},
                  "bodies above the design region");
    }
  }
  SurfaceMesh out = support;
  std::vector<bool> movable(static_cast<std::size_t>(support.V.rows()), false);
  for (std::size_t i = 0; i < design_vertices.size(); ++i) {
    const int v = design_vertices[i];
    out.V.row(v) += dent[i] * d.transpose();
    movable[static_cast<std::size_t>(v)] = true;
  }
  if (options.smoothing_rounds > 0) mesh::taubin_smooth(out, options.smoothing_rounds, &movable);
  return out;
}

}  // namespace palpa::design
