// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/mesh/surface_check.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <unordered_map>
#include <vector>

#include "palpa/core/error.hpp"
#include "palpa/core/units.hpp"
#include "palpa/geometry/format.hpp"
#include "palpa/mesh/detail/cgal_surface.hpp"

namespace palpa::mesh {
namespace {

using geometry::format_point;

constexpr double kRelativeMergeTolerance = 1e-9;



using Edge = std::pair<int, int>;

// Directed edges of all triangles, counted: (a, b) -> number of triangles with
// a→b as an edge.
std::map<Edge, int> directed_edges(const SurfaceMesh& mesh) {
  std::map<Edge, int> edges;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) ++edges[{mesh.F(f, k), mesh.F(f, (k + 1) % 3)}];
  }
  return edges;
}

bool is_closed_manifold(const SurfaceMesh& mesh) {
  const auto edges = directed_edges(mesh);
  for (const auto& [e, n] : edges) {
    if (n != 1 || !edges.contains({e.second, e.first})) return false;
  }
  return true;
}

[[noreturn]] void degenerate_triangle(Eigen::Index f, const Eigen::Vector3d& at, const ErrorContext& where) {
  throw_input_error(fmt::format("triangle {} near {} has no area (its corners are collinear or coincide)", f,
                                format_point(at)),
                    where, "a surface whose every triangle has an area");
}

}  // namespace

double enclosed_volume(const SurfaceMesh& mesh) {
  double six_v = 0.0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    six_v += Eigen::Vector3d(mesh.V.row(mesh.F(f, 0)))
                 .dot(Eigen::Vector3d(mesh.V.row(mesh.F(f, 1)))
                          .cross(Eigen::Vector3d(mesh.V.row(mesh.F(f, 2)))));
  }
  return six_v / 6.0;
}

double mean_edge_length(const SurfaceMesh& mesh) {
  double sum = 0.0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      sum += (mesh.V.row(mesh.F(f, k)) - mesh.V.row(mesh.F(f, (k + 1) % 3))).norm();
    }
  }
  return mesh.F.rows() > 0 ? sum / (3.0 * double(mesh.F.rows())) : 0.0;
}

SurfaceMesh repair_surface(const SurfaceMesh& mesh, RepairReport* report,
                           double merge_tolerance) {
  RepairReport r;
  const Eigen::Index nv = mesh.V.rows();
  if (merge_tolerance < 0.0) {
    merge_tolerance = nv > 0 ? kRelativeMergeTolerance *
                                   (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm()
                             : 0.0;
  }
  // Merge: snap to a grid of cell merge_tolerance and compare within the cell
  // and its neighbours, so points closer than the tolerance always meet.
  std::vector<int> representative(static_cast<std::size_t>(nv));
  {
    const double cell = merge_tolerance > 0.0 ? merge_tolerance : 1.0;
    struct KeyHash {
      std::size_t operator()(const std::array<long long, 3>& k) const noexcept {
        return std::hash<long long>()(k[0] * 73856093LL ^ k[1] * 19349663LL ^ k[2] * 83492791LL);
      }
    };
    std::unordered_map<std::array<long long, 3>, std::vector<int>, KeyHash> grid;
    for (Eigen::Index i = 0; i < nv; ++i) {
      std::array<long long, 3> key;
      for (int c = 0; c < 3; ++c) key[c] = std::llround(std::floor(mesh.V(i, c) / cell));
      int found = -1;
      for (int dx = -1; dx <= 1 && found < 0; ++dx) {
        for (int dy = -1; dy <= 1 && found < 0; ++dy) {
          for (int dz = -1; dz <= 1 && found < 0; ++dz) {
            const auto it = grid.find({key[0] + dx, key[1] + dy, key[2] + dz});
            if (it == grid.end()) continue;
            for (int j : it->second) {
              if ((mesh.V.row(j) - mesh.V.row(i)).norm() <= merge_tolerance) {
                found = j;
                break;
              }
            }
          }
        }
      }
      if (found >= 0) {
        representative[i] = found;
        ++r.merged_vertices;
      } else {
        representative[i] = static_cast<int>(i);
        grid[key].push_back(static_cast<int>(i));
      }
    }
  }
  // Faces: drop repeated corners, then repeated triangles.
  std::vector<std::array<int, 3>> faces;
  std::map<std::array<int, 3>, std::vector<std::size_t>> by_vertices;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    std::array<int, 3> t;
    for (int k = 0; k < 3; ++k) t[k] = representative[mesh.F(f, k)];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      ++r.degenerate_faces;
      continue;
    }
    std::array<int, 3> key = t;
    std::sort(key.begin(), key.end());
    by_vertices[key].push_back(faces.size());
    faces.push_back(t);
  }
  std::vector<bool> keep(faces.size(), true);
  for (const auto& [key, list] : by_vertices) {
    if (list.size() < 2) continue;
    // Same orientation: keep one. Opposite orientations cancel in pairs.
    const auto parity = [&faces](std::size_t i) {
      const auto& t = faces[i];
      const int first = static_cast<int>(std::min_element(t.begin(), t.end()) - t.begin());
      return t[(first + 1) % 3] < t[(first + 2) % 3];
    };
    int positive = 0, negative = 0;
    for (std::size_t i : list) (parity(i) ? positive : negative)++;
    const int net = positive - negative;
    int kept = 0;
    for (std::size_t i : list) {
      const bool want = net != 0 && kept == 0 && parity(i) == (net > 0);
      if (want) {
        ++kept;
      } else {
        keep[i] = false;
        ++r.duplicate_faces;
      }
    }
  }
  // Compact.
  std::vector<int> new_index(static_cast<std::size_t>(nv), -1);
  SurfaceMesh out;
  std::vector<std::array<int, 3>> kept_faces;
  int next = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (!keep[f]) continue;
    std::array<int, 3> t;
    for (int k = 0; k < 3; ++k) {
      int& ni = new_index[faces[f][k]];
      if (ni < 0) ni = next++;
      t[k] = ni;
    }
    kept_faces.push_back(t);
  }
  out.V.resize(next, 3);
  for (Eigen::Index i = 0; i < nv; ++i) {
    if (new_index[i] >= 0) out.V.row(new_index[i]) = mesh.V.row(i);
  }
  r.unused_vertices = nv - r.merged_vertices - next;
  out.F.resize(static_cast<Eigen::Index>(kept_faces.size()), 3);
  for (std::size_t f = 0; f < kept_faces.size(); ++f) {
    out.F.row(Eigen::Index(f)) << kept_faces[f][0], kept_faces[f][1], kept_faces[f][2];
  }
  if (out.F.rows() > 0 && is_closed_manifold(out) && enclosed_volume(out) < 0.0) {
    out.F.col(1).swap(out.F.col(2));
    r.flipped = true;
  }
  if (report) *report = r;
  return out;
}

void check_closed_surface(const SurfaceMesh& mesh, const std::string& source) {
  const ErrorContext where = in_file(source);
  if (mesh.F.rows() < 4) {
    throw_input_error(fmt::format("the surface has {} triangles", mesh.F.rows()), where,
                      "a closed surface (at least 4 triangles)");
  }
  const auto edges = directed_edges(mesh);
  Eigen::Index open = 0;
  std::optional<Edge> first_open;
  for (const auto& [e, n] : edges) {
    const Eigen::Vector3d mid = 0.5 * (mesh.V.row(e.first) + mesh.V.row(e.second)).transpose();
    if (n > 1) {
      throw_input_error(fmt::format("edge between vertices {} and {} at {} is used in the same "
                                    "direction by {} triangles (inconsistent winding or a "
                                    "non-manifold edge)",
                                    e.first, e.second, format_point(mid), n),
                        where, "a consistently oriented 2-manifold surface");
    }
    const auto back = edges.find({e.second, e.first});
    if (back == edges.end()) {
      ++open;
      if (!first_open) first_open = e;
    }
  }
  if (open > 0) {
    const Eigen::Vector3d mid =
        0.5 * (mesh.V.row(first_open->first) + mesh.V.row(first_open->second)).transpose();
    throw_input_error(
        fmt::format("the surface is open: {} edges belong to a single triangle, the first "
                    "between vertices {} and {} at {}",
                    open, first_open->first, first_open->second, format_point(mid)),
        where, "a closed (watertight) surface: fill the holes of the scan first");
  }
  // Non-manifold vertices (two fans meeting at a point): count the fans.
  {
    std::vector<std::vector<Eigen::Index>> incident(static_cast<std::size_t>(mesh.V.rows()));
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
      for (int k = 0; k < 3; ++k) incident[mesh.F(f, k)].push_back(f);
    }
    for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
      const auto& fan = incident[v];
      if (fan.empty()) continue;
      // Walk around v from the first triangle: next triangle shares edge (v, w).
      std::map<int, Eigen::Index> by_outgoing;  // w -> triangle holding v→w
      for (Eigen::Index f : fan) {
        for (int k = 0; k < 3; ++k) {
          if (mesh.F(f, k) == v) by_outgoing[mesh.F(f, (k + 1) % 3)] = f;
        }
      }
      std::size_t walked = 0;
      Eigen::Index f = fan.front();
      do {
        int k = 0;
        while (mesh.F(f, k) != v) ++k;
        const int prev = mesh.F(f, (k + 2) % 3);  // triangle holding v→prev is next
        f = by_outgoing.at(prev);
        ++walked;
      } while (f != fan.front() && walked <= fan.size());
      if (walked != fan.size()) {
        throw_input_error(fmt::format("vertex {} at {} joins separate sheets of the surface "
                                      "(a non-manifold vertex)",
                                      v, format_point(mesh.V.row(v).transpose())),
                          where, "a 2-manifold surface");
      }
    }
  }
  // Triangles without area (corners collinear or coincident): the geometry
  // below has no normal for them.
  {
    const double diagonal = (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm();
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
      const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)).transpose();
      const Eigen::Vector3d b = mesh.V.row(mesh.F(f, 1)).transpose();
      const Eigen::Vector3d c = mesh.V.row(mesh.F(f, 2)).transpose();
      if (!((b - a).cross(c - a).norm() > 1e-14 * diagonal * diagonal)) {
        degenerate_triangle(f, (a + b + c) / 3.0, where);
      }
    }
  }
  if (enclosed_volume(mesh) <= 0.0) {
    throw_input_error("the surface's normals point inward (it encloses a negative volume)",
                      where, "outward normals (repair_surface reverses the winding)");
  }
  if (const auto pair = detail::cgal_self_intersection(mesh)) {
    const Eigen::Vector3d at = mesh.V.row(mesh.F(pair->first, 0)).transpose();
    if (pair->first == pair->second) degenerate_triangle(pair->first, at, where);  // CGAL's report of one
    throw_input_error(fmt::format("the surface intersects itself: triangles {} and {} cross "
                                  "near {}",
                                  pair->first, pair->second, format_point(at)),
                      where, "a surface without self-intersections");
  }
}

bool self_intersects(const SurfaceMesh& mesh) { return detail::cgal_self_intersection(mesh).has_value(); }

double remeshed_triangles(double area, double edge_length) {
  return area / (std::sqrt(3.0) / 4.0 * edge_length * edge_length);
}

double surface_area(const SurfaceMesh& mesh) {
  double a = 0.0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d p = mesh.V.row(mesh.F(f, 0)).transpose();
    const Eigen::Vector3d q = mesh.V.row(mesh.F(f, 1)).transpose();
    const Eigen::Vector3d r = mesh.V.row(mesh.F(f, 2)).transpose();
    a += 0.5 * (q - p).cross(r - p).norm();
  }
  return a;
}

SurfaceMesh remesh_surface(const SurfaceMesh& mesh, double edge_length, int iterations) {
  if (!(edge_length > 0.0) || !std::isfinite(edge_length)) {
    throw_input_error("the target edge length is not positive", {}, "an edge length > 0");
  }
  const double area = surface_area(mesh);
  if (const double n = remeshed_triangles(area, edge_length); !(n <= kMaxRemeshTriangles)) {
    throw_input_error(fmt::format("remeshing a surface of {:.4g} m² to edges of {} would make about {:.3g} "
                                  "triangles, more than the {:.0f} palpa makes",
                                  area, format_quantity(edge_length, Dimension::Length), n, kMaxRemeshTriangles),
                      {}, "a longer edge length, or the surface's true unit");
  }
  return detail::cgal_remesh(mesh, edge_length, iterations);
}

}  // namespace palpa::mesh
