// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/contact/contact.hpp"

namespace palpa::contact {

FeatureGeometry feature_geometry(const Obstacle& obstacle, const ClosestPoint& closest) {
  FeatureGeometry g;
  g.m = feature_size(closest.feature);
  for (int i = 0; i < g.m; ++i) {
    g.q[static_cast<std::size_t>(i)] =
        obstacle.world_vertex(closest.vertices[static_cast<std::size_t>(i)]);
  }
  return g;
}

}  // namespace palpa::contact
