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

}  // namespace palpa::tet
