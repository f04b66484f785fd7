// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/tet/mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fmt/format.h>

#include "palpa/core/error.hpp"
#include "palpa/tet/element.hpp"

namespace palpa::tet {

namespace {

Mat34 corners(const TetMesh& mesh, Eigen::Index t) {
  Mat34 X;
  for (int a = 0; a < 4; ++a) X.col(a) = mesh.V.row(mesh.T(t, a)).transpose();
  return X;
}

double longest_edge(const Mat34& X) {
  double h = 0.0;
  for (int a = 0; a < 4; ++a) {
    for (int b = a + 1; b < 4; ++b) h = std::max(h, (X.col(a) - X.col(b)).norm());
  }
  return h;
}

}  // namespace

TetMeshCheck prepare_tet_mesh(TetMesh& mesh, std::string_view name) {
  const auto fail = [&](const std::string& what) {
    throw Error(ErrorKind::Input, fmt::format("{}: {}", name, what));
  };
  if (mesh.V.rows() == 0) fail("the tet mesh has no vertices");
  if (mesh.T.rows() == 0) fail("the tet mesh has no tetrahedra");
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    if (!mesh.V.row(i).allFinite()) fail(fmt::format("vertex {} has a non-finite coordinate", i));
  }
  if (mesh.region.size() != 0 && mesh.region.size() != mesh.T.rows()) {
    fail(fmt::format("{} region ids for {} tetrahedra", mesh.region.size(), mesh.T.rows()));
  }
  const auto nv = mesh.V.rows();
  std::vector<char> used(static_cast<std::size_t>(nv), 0);
  Eigen::Index negative = 0;
  Eigen::Index first_negative = -1;
  Eigen::Index first_positive = -1;
  for (Eigen::Index t = 0; t < mesh.T.rows(); ++t) {
    for (int a = 0; a < 4; ++a) {
      const int v = mesh.T(t, a);
      if (v < 0 || v >= nv) {
        fail(fmt::format("tetrahedron {} uses vertex {}, but there are only {} vertices", t, v, nv));
      }
      for (int b = 0; b < a; ++b) {
        if (mesh.T(t, b) == v) fail(fmt::format("tetrahedron {} uses vertex {} twice", t, v));
      }
      used[static_cast<std::size_t>(v)] = 1;
    }
    const Mat34 X = corners(mesh, t);
    const double vol = signed_volume(X);
    const double h = longest_edge(X);
    if (!(std::abs(vol) > 1e-9 * h * h * h)) {
      fail(fmt::format("tetrahedron {} is degenerate (volume {:.3g} m³ for a longest edge of {:.3g} m)",
                       t, vol, h));
    }
    if (vol < 0.0) {
      ++negative;
      if (first_negative < 0) first_negative = t;
    } else if (first_positive < 0) {
      first_positive = t;
    }
  }
  TetMeshCheck check;
  if (negative == mesh.T.rows()) {
    for (Eigen::Index t = 0; t < mesh.T.rows(); ++t) std::swap(mesh.T(t, 2), mesh.T(t, 3));
    check.flipped = negative;
  } else if (negative > 0) {
    fail(fmt::format("{} of {} tetrahedra are inverted (the first is tetrahedron {}; tetrahedron {} "
                     "has the opposite orientation)",
                     negative, mesh.T.rows(), first_negative, first_positive));
  }
  check.min_volume = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < mesh.T.rows(); ++t) {
    const double vol = signed_volume(corners(mesh, t));
    check.min_volume = std::min(check.min_volume, vol);
    check.total_volume += vol;
  }
  check.unused_vertices = static_cast<Eigen::Index>(std::count(used.begin(), used.end(), 0));
  return check;
}

BoxMesh make_box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Eigen::Vector3i& cells) {
  if (!(cells.minCoeff() >= 1)) {
    throw Error(ErrorKind::Input, fmt::format("box mesh: cells must be at least 1 per axis, got {} {} {}",
                                              cells[0], cells[1], cells[2]));
  }
  if (!lo.allFinite() || !hi.allFinite() || !((hi - lo).minCoeff() > 0.0)) {
    throw Error(ErrorKind::Input, "box mesh: the upper corner must lie above the lower one on every axis");
  }
  const int nx = cells[0] + 1;
  const int ny = cells[1] + 1;
  const int nz = cells[2] + 1;
  const auto id = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  BoxMesh box;
  TetMesh& m = box.mesh;
  m.V.resize(static_cast<Eigen::Index>(nx) * ny * nz, 3);
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const Eigen::Vector3d t(double(i) / cells[0], double(j) / cells[1], double(k) / cells[2]);
        m.V.row(id(i, j, k)) = (lo.array() + t.array() * (hi - lo).array()).matrix().transpose();
      }
    }
  }
  // Kuhn subdivision: the 6 paths from corner 0 to corner 7 of the unit cube,
  // one coordinate step at a time; every tet shares the main diagonal.
  static constexpr std::array<std::array<int, 3>, 6> kPaths{
      {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  m.T.resize(6 * static_cast<Eigen::Index>(cells[0]) * cells[1] * cells[2], 4);
  Eigen::Index t = 0;
  for (int k = 0; k < cells[2]; ++k) {
    for (int j = 0; j < cells[1]; ++j) {
      for (int i = 0; i < cells[0]; ++i) {
        for (const auto& path : kPaths) {
          std::array<int, 3> c{i, j, k};
          std::array<int, 4> tet{};
          tet[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[static_cast<std::size_t>(path[static_cast<std::size_t>(s)])];
            tet[static_cast<std::size_t>(s + 1)] = id(c[0], c[1], c[2]);
          }
          for (int a = 0; a < 4; ++a) m.T(t, a) = tet[static_cast<std::size_t>(a)];
          Mat34 X;
          for (int a = 0; a < 4; ++a) X.col(a) = m.V.row(m.T(t, a)).transpose();
          if (signed_volume(X) < 0.0) std::swap(m.T(t, 2), m.T(t, 3));
          ++t;
        }
      }
    }
  }
  m.region = Eigen::VectorXi::Zero(m.T.rows());
  auto& sets = box.vertex_sets;
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const int v = id(i, j, k);
        if (i == 0) sets["xmin"].push_back(v);
        if (i == nx - 1) sets["xmax"].push_back(v);
        if (j == 0) sets["ymin"].push_back(v);
        if (j == ny - 1) sets["ymax"].push_back(v);
        if (k == 0) sets["zmin"].push_back(v);
        if (k == nz - 1) sets["zmax"].push_back(v);
      }
    }
  }
  sets["bottom"] = sets["zmin"];
  sets["top"] = sets["zmax"];
  return box;
}

namespace {

// A triangular prism (bottom a b c, top a' b' c' = corners 3 4 5) as 3 tets whose
// quad faces are split from their lowest vertex index (Dompierre et al.'s rule):
// relabel so that the lowest corner is a, then the face b c c' b' alone decides.
void split_prism(std::array<int, 6> v, std::vector<std::array<int, 4>>& out) {
  const auto lowest = static_cast<std::size_t>(std::min_element(v.begin(), v.end()) - v.begin());
  if (lowest >= 3) {
    for (std::size_t k = 0; k < 3; ++k) std::swap(v[k], v[k + 3]);
  }
  const std::size_t r = lowest % 3;
  const std::array<int, 6> p{v[r], v[(r + 1) % 3], v[(r + 2) % 3], v[3 + r], v[3 + (r + 1) % 3], v[3 + (r + 2) % 3]};
  const auto [a, b, c, a1, b1, c1] = p;
  if (std::min(b, c1) < std::min(c, b1)) {  // diagonal b–c'
    out.push_back({a, b, c, c1});
    out.push_back({a, b, c1, b1});
  } else {  // diagonal c–b'
    out.push_back({a, b, c, b1});
    out.push_back({a, c, c1, b1});
  }
  out.push_back({a, b1, c1, a1});
}

bool increasing_from_zero(std::span<const double> x) {
  if (x.size() < 2 || x[0] != 0.0) return false;
  for (std::size_t k = 1; k < x.size(); ++k) {
    if (!(std::isfinite(x[k]) && x[k] > x[k - 1])) return false;
  }
  return true;
}

}  // namespace

StructuredMesh make_cylinder_mesh(std::span<const double> radii, std::span<const double> depths, int segments,
                                  double angle) {
  if (!increasing_from_zero(radii) || !increasing_from_zero(depths)) {
    throw Error(ErrorKind::Input, "cylinder mesh: radii and depths must increase from 0 (at least two of each)");
  }
  const double turn = 2.0 * std::numbers::pi;
  const double sectors_real = segments * angle / turn;
  const int sectors = static_cast<int>(std::lround(sectors_real));
  if (segments < 3 || !(angle > 0.0 && angle <= turn * (1.0 + 1e-12)) || sectors < 1 ||
      std::abs(sectors_real - sectors) > 1e-9 * segments) {
    throw Error(ErrorKind::Input,
                fmt::format("cylinder mesh: a sector of {:g} deg is not a whole number of the {} segments around",
                            angle * 180.0 / std::numbers::pi, segments));
  }
  const bool closed = sectors == segments;
  const int rings = static_cast<int>(radii.size()) - 1;     // rings off the axis
  const int layers = static_cast<int>(depths.size());      // node layers
  const int around = closed ? segments : sectors + 1;      // nodes per ring
  const int per_layer = 1 + rings * around;
  // Node of ring i (0 = the axis) at angle index j, layer k (0 = top).
  const auto id = [&](int i, int j, int k) {
    return k * per_layer + (i == 0 ? 0 : 1 + (i - 1) * around + (closed ? j % segments : j));
  };
  StructuredMesh out;
  TetMesh& m = out.mesh;
  m.V.resize(static_cast<Eigen::Index>(per_layer) * layers, 3);
  for (int k = 0; k < layers; ++k) {
    const double z = -depths[static_cast<std::size_t>(k)];
    m.V.row(id(0, 0, k)) << 0.0, 0.0, z;
    for (int i = 1; i <= rings; ++i) {
      const double r = radii[static_cast<std::size_t>(i)];
      for (int j = 0; j < around; ++j) {
        const double t = turn * j / segments;
        m.V.row(id(i, j, k)) << r * std::cos(t), r * std::sin(t), z;
      }
    }
  }
  // The plane's triangles (the same in every layer, so the horizontal faces
  // agree): a fan on the axis, then each quad cut along the diagonal from its
  // lowest index.
  std::vector<std::array<std::array<int, 2>, 3>> triangles;  // (ring, angle) corners
  for (int j = 0; j < sectors; ++j) {
    triangles.push_back({{{0, 0}, {1, j}, {1, j + 1}}});
    for (int i = 1; i < rings; ++i) {
      const std::array<int, 2> q00{i, j}, q10{i + 1, j}, q11{i + 1, j + 1}, q01{i, j + 1};
      const int lo02 = std::min(id(i, j, 0), id(i + 1, j + 1, 0));
      const int lo13 = std::min(id(i + 1, j, 0), id(i, j + 1, 0));
      if (lo02 < lo13) {
        triangles.push_back({q00, q10, q11});
        triangles.push_back({q00, q11, q01});
      } else {
        triangles.push_back({q00, q10, q01});
        triangles.push_back({q10, q11, q01});
      }
    }
  }
  std::vector<std::array<int, 4>> tets;
  tets.reserve(3 * triangles.size() * static_cast<std::size_t>(layers - 1));
  for (int k = 0; k + 1 < layers; ++k) {
    for (const auto& tri : triangles) {
      std::array<int, 6> v{};
      for (std::size_t c = 0; c < 3; ++c) {
        v[c] = id(tri[c][0], tri[c][1], k + 1);
        v[c + 3] = id(tri[c][0], tri[c][1], k);
      }
      split_prism(v, tets);
    }
  }
  m.T.resize(static_cast<Eigen::Index>(tets.size()), 4);
  for (std::size_t t = 0; t < tets.size(); ++t) {
    auto tet = tets[t];
    Mat34 X;
    for (std::size_t a = 0; a < 4; ++a) X.col(static_cast<Eigen::Index>(a)) = m.V.row(tet[a]).transpose();
    if (signed_volume(X) < 0.0) std::swap(tet[2], tet[3]);
    for (std::size_t a = 0; a < 4; ++a) m.T(static_cast<Eigen::Index>(t), static_cast<Eigen::Index>(a)) = tet[a];
  }
  m.region = Eigen::VectorXi::Zero(m.T.rows());
  auto& sets = out.vertex_sets;
  for (int k = 0; k < layers; ++k) {
    if (k == 0) sets["zmax"].push_back(id(0, 0, k));
    if (k == layers - 1) sets["zmin"].push_back(id(0, 0, k));
    if (!closed) {
      sets["sector_start"].push_back(id(0, 0, k));
      sets["sector_end"].push_back(id(0, 0, k));
    }
    for (int i = 1; i <= rings; ++i) {
      for (int j = 0; j < around; ++j) {
        const int v = id(i, j, k);
        if (k == 0) sets["zmax"].push_back(v);
        if (k == layers - 1) sets["zmin"].push_back(v);
        if (i == rings) sets["side"].push_back(v);
        if (!closed && j == 0) sets["sector_start"].push_back(v);
        if (!closed && j == sectors) sets["sector_end"].push_back(v);
      }
    }
  }
  sets["top"] = sets["zmax"];
  sets["bottom"] = sets["zmin"];
  return out;
}

}  // namespace palpa::tet
