// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/geometry/boundary.hpp"

#include <algorithm>
#include <array>
#include <unordered_map>
#include <utility>

namespace palpa::geometry {

Boundary boundary_of(const TetMesh& mesh) {
  // Faces opposite each corner, wound outward for a positively oriented tet.
  static constexpr std::array<std::array<int, 3>, 4> kFaces{
      {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};
  struct Seen {
    Eigen::Index tet;
    int face;
    int count;
  };
  const auto key = [](std::array<int, 3> f) {
    std::sort(f.begin(), f.end());
    return f;
  };
  struct Hash {
    std::size_t operator()(const std::array<int, 3>& f) const noexcept {
      std::size_t h = static_cast<std::size_t>(f[0]);
      h = h * 0x9E3779B97F4A7C15ULL + static_cast<std::size_t>(f[1]);
      h = h * 0x9E3779B97F4A7C15ULL + static_cast<std::size_t>(f[2]);
      return h;
    }
  };
  std::unordered_map<std::array<int, 3>, Seen, Hash> faces;
  faces.reserve(static_cast<std::size_t>(mesh.T.rows()) * 4);
  for (Eigen::Index t = 0; t < mesh.T.rows(); ++t) {
    for (int f = 0; f < 4; ++f) {
      const std::array<int, 3> tri{mesh.T(t, kFaces[f][0]), mesh.T(t, kFaces[f][1]),
                                   mesh.T(t, kFaces[f][2])};
      auto [it, inserted] = faces.try_emplace(key(tri), Seen{t, f, 0});
      ++it->second.count;
    }
  }
  std::vector<std::pair<Eigen::Index, int>> outer;
  for (const auto& [k, s] : faces) {
    if (s.count == 1) outer.emplace_back(s.tet, s.face);
  }
  std::sort(outer.begin(), outer.end());
  Boundary b;
  b.faces.resize(static_cast<Eigen::Index>(outer.size()), 3);
  b.face_tet.resize(static_cast<Eigen::Index>(outer.size()));
  std::vector<char> on(static_cast<std::size_t>(mesh.V.rows()), 0);
  for (std::size_t i = 0; i < outer.size(); ++i) {
    const auto [t, f] = outer[i];
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.T(t, kFaces[f][c]);
      b.faces(static_cast<Eigen::Index>(i), c) = v;
      on[static_cast<std::size_t>(v)] = 1;
    }
    b.face_tet[static_cast<Eigen::Index>(i)] = static_cast<int>(t);
  }
  for (std::size_t v = 0; v < on.size(); ++v) {
    if (on[v]) b.vertices.push_back(static_cast<int>(v));
  }
  return b;
}

}  // namespace palpa::geometry
