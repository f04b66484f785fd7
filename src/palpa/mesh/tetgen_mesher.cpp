// SPDX-License-Identifier: AGPL-3.0-or-later
// The one translation unit of palpa that includes TetGen.
#include <fmt/format.h>
#include <tetgen.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "palpa/core/error.hpp"
#include "palpa/mesh/tetrahedralize.hpp"

namespace palpa::mesh {
namespace {

constexpr double kMinRadiusEdgeBound = 1.0;  // TetGen does not terminate below ~1.1
constexpr double kMaxDihedralBound = 70.0 * std::numbers::pi / 180.0;

void check_quality(const TetQuality& q) {
  if (!(q.max_radius_edge > kMinRadiusEdgeBound) || !std::isfinite(q.max_radius_edge)) {
    throw_input_error(fmt::format("radius-edge bound {} is too small", q.max_radius_edge), {},
                      "a radius-edge ratio bound > 1 (TetGen's default is 2, 1.2–1.5 is fine)");
  }
  if (!(q.min_dihedral >= 0.0) || !(q.min_dihedral < kMaxDihedralBound)) {
    throw_input_error(fmt::format("minimum dihedral angle bound {} rad is out of range",
                                  q.min_dihedral),
                      {}, "an angle in [0°, 70°)");
  }
  if (!(q.max_volume >= 0.0) || !std::isfinite(q.max_volume)) {
    throw_input_error("the largest tet volume is negative or not finite", {},
                      "a volume ≥ 0 (0: no bound)");
  }
}

std::string tetgen_error(int code) {
  switch (code) {
    case 1: return "out of memory";
    case 3: return "the surface intersects itself";
    case 4: return "the surface has a feature too small for TetGen's tolerance";
    case 5: return "two surface triangles are too close together";
    case 10: return "TetGen rejected the input surface";
    default: return fmt::format("TetGen failed (code {})", code);
  }
}

}  // namespace

namespace detail {

TetMesh tetgen_shells(const std::vector<const SurfaceMesh*>& shells,
                      const std::vector<Eigen::Vector3d>& holes, const TetQuality& quality) {
  check_quality(quality);
  tetgenio in;
  tetgenio out;
  in.firstnumber = 0;
  Eigen::Index n_points = 0, n_faces = 0;
  for (const SurfaceMesh* s : shells) {
    n_points += s->V.rows();
    n_faces += s->F.rows();
  }
  in.numberofpoints = static_cast<int>(n_points);
  in.pointlist = new REAL[3 * n_points];
  in.numberoffacets = static_cast<int>(n_faces);
  in.facetlist = new tetgenio::facet[n_faces];
  in.facetmarkerlist = new int[n_faces];
  Eigen::Index point_offset = 0, face = 0;
  for (std::size_t k = 0; k < shells.size(); ++k) {
    const SurfaceMesh& s = *shells[k];
    for (Eigen::Index i = 0; i < s.V.rows(); ++i) {
      for (int c = 0; c < 3; ++c) in.pointlist[3 * (point_offset + i) + c] = s.V(i, c);
    }
    for (Eigen::Index f = 0; f < s.F.rows(); ++f, ++face) {
      tetgenio::facet& facet = in.facetlist[face];
      tetgenio::init(&facet);
      facet.numberofpolygons = 1;
      facet.polygonlist = new tetgenio::polygon[1];
      tetgenio::init(&facet.polygonlist[0]);
      facet.polygonlist[0].numberofvertices = 3;
      facet.polygonlist[0].vertexlist = new int[3];
      for (int c = 0; c < 3; ++c) {
        facet.polygonlist[0].vertexlist[c] = static_cast<int>(point_offset + s.F(f, c));
      }
      in.facetmarkerlist[face] = static_cast<int>(k) + 1;
    }
    point_offset += s.V.rows();
  }
  in.numberofholes = static_cast<int>(holes.size());
  if (!holes.empty()) {
    in.holelist = new REAL[3 * holes.size()];
    for (std::size_t h = 0; h < holes.size(); ++h) {
      for (int c = 0; c < 3; ++c) in.holelist[3 * h + c] = holes[h](c);
    }
  }

  // p: a piecewise linear complex; q: quality; a: volume; Y: keep the
  // boundary; Q: quiet; z: number from 0.
  std::string switches = fmt::format("pzQq{:.6g}/{:.6g}", quality.max_radius_edge,
                                     quality.min_dihedral * 180.0 / std::numbers::pi);
  if (quality.max_volume > 0.0) switches += fmt::format("a{:.9g}", quality.max_volume);
  if (quality.preserve_surface) switches += "Y";
  tetgenbehavior behavior;
  if (!behavior.parse_commandline(switches.data())) {
    throw Error(ErrorKind::Internal, "TetGen refused the switches " + switches);
  }
  try {
    tetrahedralize(&behavior, &in, &out);
  } catch (int code) {
    if (code == 3 || code == 4 || code == 5 || code == 10) throw_input_error(tetgen_error(code));
    throw_solver_error(tetgen_error(code));
  }

  TetMesh mesh;
  mesh.V.resize(out.numberofpoints, 3);
  for (int i = 0; i < out.numberofpoints; ++i) {
    mesh.V.row(i) << out.pointlist[3 * i], out.pointlist[3 * i + 1], out.pointlist[3 * i + 2];
  }
  mesh.T.resize(out.numberoftetrahedra, 4);
  for (int t = 0; t < out.numberoftetrahedra; ++t) {
    for (int c = 0; c < 4; ++c) mesh.T(t, c) = out.tetrahedronlist[t * out.numberofcorners + c];
  }
  // TetGen orients tets with det[b−a, c−a, d−a] < 0; palpa's convention is > 0.
  for (int t = 0; t < out.numberoftetrahedra; ++t) {
    const Eigen::Vector3d a = mesh.V.row(mesh.T(t, 0));
    const double det = (mesh.V.row(mesh.T(t, 1)).transpose() - a)
                           .cross(mesh.V.row(mesh.T(t, 2)).transpose() - a)
                           .dot(mesh.V.row(mesh.T(t, 3)).transpose() - a);
    if (det < 0.0) std::swap(mesh.T(t, 2), mesh.T(t, 3));
  }
  mesh.region = Eigen::VectorXi::Ones(out.numberoftetrahedra);
  mesh.boundary.resize(out.numberoftrifaces, 3);
  mesh.boundary_marker.resize(out.numberoftrifaces);
  for (int f = 0; f < out.numberoftrifaces; ++f) {
    for (int c = 0; c < 3; ++c) mesh.boundary(f, c) = out.trifacelist[3 * f + c];
    mesh.boundary_marker(f) = out.trifacemarkerlist ? out.trifacemarkerlist[f] : 0;
  }
  return mesh;
}

}  // namespace detail

TetMesh tetrahedralize(const SurfaceMesh& closed_surface, const TetQuality& quality) {
  return detail::tetgen_shells({&closed_surface}, {}, quality);
}

Eigen::VectorXd tet_volumes(const TetMesh& mesh) {
  Eigen::VectorXd v(mesh.T.rows());
  for (Eigen::Index t = 0; t < mesh.T.rows(); ++t) {
    const Eigen::Vector3d a = mesh.V.row(mesh.T(t, 0));
    v(t) = (mesh.V.row(mesh.T(t, 1)).transpose() - a)
               .cross(mesh.V.row(mesh.T(t, 2)).transpose() - a)
               .dot(mesh.V.row(mesh.T(t, 3)).transpose() - a) /
           6.0;
  }
  return v;
}

TetStatistics tet_statistics(const TetMesh& mesh, const TetQuality& bounds) {
  TetStatistics s;
  s.tets = mesh.T.rows();
  s.vertices = mesh.V.rows();
  if (s.tets == 0) return s;
  const Eigen::VectorXd volumes = tet_volumes(mesh);
  s.volume = volumes.sum();
  s.min_volume = volumes.minCoeff();
  s.inverted = (volumes.array() <= 0.0).count();
  s.min_dihedral = std::numbers::pi;
  double sum_ratio = 0.0;
  for (Eigen::Index t = 0; t < s.tets; ++t) {
    std::array<Eigen::Vector3d, 4> p;
    for (int c = 0; c < 4; ++c) p[c] = mesh.V.row(mesh.T(t, c)).transpose();
    // Face normals (outward for a positive tet) opposite each corner.
    std::array<Eigen::Vector3d, 4> n;
    for (int c = 0; c < 4; ++c) {
      const Eigen::Vector3d& a = p[(c + 1) % 4];
      const Eigen::Vector3d& b = p[(c + 2) % 4];
      const Eigen::Vector3d& d = p[(c + 3) % 4];
      Eigen::Vector3d normal = (b - a).cross(d - a);
      if (normal.dot(p[c] - a) > 0.0) normal = -normal;
      n[c] = normal.normalized();
    }
    double tet_min = std::numbers::pi;
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) {
        const double angle = std::numbers::pi - std::acos(std::clamp(n[i].dot(n[j]), -1.0, 1.0));
        tet_min = std::min(tet_min, angle);
        s.max_dihedral = std::max(s.max_dihedral, angle);
      }
    }
    s.min_dihedral = std::min(s.min_dihedral, tet_min);
    if (tet_min < bounds.min_dihedral) ++s.below_min_dihedral;
    // Circumcentre c = p_0 + x with 2 (p_i − p_0)·x = |p_i − p_0|².
    Eigen::Matrix3d A;
    Eigen::Vector3d rhs;
    for (int i = 1; i < 4; ++i) {
      A.row(i - 1) = 2.0 * (p[i] - p[0]).transpose();
      rhs(i - 1) = (p[i] - p[0]).squaredNorm();
    }
    const double radius = A.fullPivLu().solve(rhs).norm();
    double shortest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) shortest = std::min(shortest, (p[i] - p[j]).norm());
    }
    const double ratio = radius / shortest;
    sum_ratio += ratio;
    s.max_radius_edge = std::max(s.max_radius_edge, ratio);
    if (ratio > bounds.max_radius_edge) ++s.above_max_radius_edge;
  }
  s.mean_radius_edge = sum_ratio / double(s.tets);
  return s;
}

}  // namespace palpa::mesh
