// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/contact/contact.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <numeric>


namespace palpa::contact {

namespace {

// Points per task of the parallel loops: a closest-point query costs ~1 µs.
constexpr std::size_t kGrain = 256;

Eigen::Vector3d point_of(Points points, int column) {
  return points.col(column);
}

}  // namespace

FeatureGeometry feature_geometry(const Obstacle& obstacle, const ClosestPoint& closest) {
  FeatureGeometry g;
  g.m = feature_size(closest.feature);
  for (int i = 0; i < g.m; ++i) {
    g.q[static_cast<std::size_t>(i)] =
        obstacle.world_vertex(closest.vertices[static_cast<std::size_t>(i)]);
  }
  return g;
}

void ContactSet::detect(const Obstacle& obstacle, Points points, std::span<const int> which) {
  assert(
      std::all_of(which.begin(), which.end(), [&](int i) { return i >= 0 && i < points.cols(); }));
  slot_.resize(which.size());
  hit_.resize(which.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, which.size(), kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) {
                        hit_[i] =
                            obstacle.penetration(point_of(points, which[i]), slot_[i]) ? 1 : 0;
                      }
                    });
  contacts_.clear();
  for (std::size_t i = 0; i < which.size(); ++i) {
    if (hit_[i] != 0) contacts_.push_back({which[i], slot_[i]});
  }
}

void ContactSet::detect(const Obstacle& obstacle, Points points) {
  if (all_.size() != static_cast<std::size_t>(points.cols())) {
    all_.resize(static_cast<std::size_t>(points.cols()));
    std::iota(all_.begin(), all_.end(), 0);
  }
  detect(obstacle, points, all_);
}

double ContactSet::max_depth() const {
  double m = 0.0;
  for (const Contact& c : contacts_) m = std::max(m, c.closest.distance);
  return m;
}

}  // namespace palpa::contact
