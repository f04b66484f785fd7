// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/contact/spring_areas.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "palpa/core/error.hpp"
#include "palpa/geometry/surface_operators.hpp"

namespace palpa::contact {

SpringAreas::SpringAreas(const Eigen::MatrixX3d& rest, Eigen::MatrixX3i faces, std::string name)
    : name_(std::move(name)), faces_(std::move(faces)) {
  skin_area_ = geometry::vertex_areas(rest, faces_);
  face_area_ = geometry::face_areas(rest, faces_);
  std::vector<char> on(static_cast<std::size_t>(rest.rows()), 0);
  for (Eigen::Index f = 0; f < faces_.rows(); ++f) {
    for (int c = 0; c < 3; ++c) on[static_cast<std::size_t>(faces_(f, c))] = 1;
  }
  for (std::size_t v = 0; v < on.size(); ++v) {
    if (on[v]) {
      surface_.push_back(static_cast<int>(v));
      mean_area_ += skin_area_[static_cast<Eigen::Index>(v)];
    }
  }
  if (surface_.empty()) throw Error(ErrorKind::Input, fmt::format("{}: the body has no skin to touch it", name_));
  mean_area_ /= static_cast<double>(surface_.size());
  area_.assign(skin_area_.data(), skin_area_.data() + skin_area_.size());
  rescale();
}

void SpringAreas::rescale() {
  scale_.resize(area_.size());
  for (std::size_t v = 0; v < area_.size(); ++v) scale_[v] = area_[v] / mean_area_;
}

double SpringAreas::update(std::span<const int> touching_vertices, double min_change) {
  // The full skin share off contact; in contact, the share of the triangles
  // wholly in contact (the full share if there is none).
  std::vector<char> touching(area_.size(), 0);
  for (int v : touching_vertices) touching[static_cast<std::size_t>(v)] = 1;
  std::vector<double> contact_area(area_.size(), 0.0);
  for (Eigen::Index f = 0; f < faces_.rows(); ++f) {
    const int a = faces_(f, 0), b = faces_(f, 1), c = faces_(f, 2);
    if (!touching[static_cast<std::size_t>(a)] || !touching[static_cast<std::size_t>(b)] ||
        !touching[static_cast<std::size_t>(c)]) {
      continue;
    }
    const double third = face_area_[f] / 3.0;
    contact_area[static_cast<std::size_t>(a)] += third;
    contact_area[static_cast<std::size_t>(b)] += third;
    contact_area[static_cast<std::size_t>(c)] += third;
  }
  std::vector<double> next(area_.size());
  double changed = 0.0, total = 0.0;
  for (std::size_t v = 0; v < area_.size(); ++v) {
    next[v] = touching[v] && contact_area[v] > 0.0 ? contact_area[v] : skin_area_[static_cast<Eigen::Index>(v)];
    const double d = std::abs(next[v] - area_[v]);
    if (d > 1e-9 * mean_area_) changed += d;
    if (touching[v]) total += next[v];
  }
  // Relative to the area in contact (to the mean share when nothing touches).
  const double change = changed / std::max(total, mean_area_);
  if (!(change > min_change)) return 0.0;
  area_ = next;
  rescale();
  return change;
}

void SpringAreas::set(const std::vector<double>& areas) {
  if (areas.size() != area_.size()) {
    throw Error(ErrorKind::Input,
                fmt::format("{}: {} saved spring areas for {} vertices", name_, areas.size(), area_.size()));
  }
  for (int v : surface_) {
    const double a = areas[static_cast<std::size_t>(v)];
    if (!std::isfinite(a) || !(a > 0.0)) {
      throw Error(ErrorKind::Input, fmt::format("{}: saved spring area of vertex {} is {}", name_, v, a));
    }
  }
  area_ = areas;
  rescale();
}

}  // namespace palpa::contact
