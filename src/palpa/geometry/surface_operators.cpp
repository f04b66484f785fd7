// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/geometry/surface_operators.hpp"

#include <Eigen/Geometry>
#include <cassert>
#include <cmath>
#include <vector>

namespace palpa::geometry {
namespace {

Eigen::Vector3d corner(const SurfaceMesh& mesh, Eigen::Index f, int k) {
  return mesh.V.row(mesh.F(f, k)).transpose();
}

// Angle at a between rays to b and c, robust for small angles (atan2).
double corner_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d u = b - a;
  const Eigen::Vector3d v = c - a;
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace

Eigen::VectorXd face_areas(const SurfaceMesh& mesh) {
  return face_areas(mesh.V, mesh.F);
}

Eigen::VectorXd face_areas(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  Eigen::VectorXd areas(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0));
    areas(f) = 0.5 * (V.row(F(f, 1)).transpose() - a).cross(V.row(F(f, 2)).transpose() - a).norm();
  }
  return areas;
}

Eigen::MatrixX3d face_normals(const SurfaceMesh& mesh) {
  Eigen::MatrixX3d normals(mesh.F.rows(), 3);
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = corner(mesh, f, 0);
    const Eigen::Vector3d n = (corner(mesh, f, 1) - a).cross(corner(mesh, f, 2) - a);
    const double length = n.norm();
    normals.row(f) = length > 0.0 ? Eigen::RowVector3d((n / length).transpose())
                                  : Eigen::RowVector3d::Zero();
  }
  return normals;
}

Eigen::Vector3d pressure_force(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::VectorXd& pressure) {
  assert(pressure.size() == V.rows());
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (Eigen::Index t = 0; t < F.rows(); ++t) {
    const Eigen::Vector3d a = V.row(F(t, 0));
    // ½ (V1−V0)×(V2−V0) is the area times the unit normal.
    const Eigen::Vector3d an = 0.5 * (V.row(F(t, 1)).transpose() - a).cross(V.row(F(t, 2)).transpose() - a);
    f += (pressure(F(t, 0)) + pressure(F(t, 1)) + pressure(F(t, 2))) / 3.0 * an;
  }
  return f;
}

Eigen::VectorXd vertex_areas(const SurfaceMesh& mesh) {
  return vertex_areas(mesh.V, mesh.F);
}

Eigen::VectorXd vertex_areas(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  const Eigen::VectorXd fa = face_areas(V, F);
  Eigen::VectorXd areas = Eigen::VectorXd::Zero(V.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) areas(F(f, k)) += fa(f) / 3.0;
  }
  return areas;
}

void add_vertex_area_gradient(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::VectorXd& w,
                              Eigen::MatrixX3d& grad) {
  assert(w.size() == V.rows() && grad.rows() == V.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int ia = F(f, 0), ib = F(f, 1), ic = F(f, 2);
    const double wf = (w[ia] + w[ib] + w[ic]) / 3.0;  // each corner gets a third of the area
    if (wf == 0.0) continue;
    const Eigen::Vector3d a = V.row(ia), b = V.row(ib), c = V.row(ic);
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double length = n.norm();
    if (!(length > 0.0)) continue;
    const Eigen::Vector3d u = n / length;
    grad.row(ia) += wf * 0.5 * u.cross(c - b).transpose();
    grad.row(ib) += wf * 0.5 * u.cross(a - c).transpose();
    grad.row(ic) += wf * 0.5 * u.cross(b - a).transpose();
  }
}

Eigen::MatrixX3d vertex_normals(const SurfaceMesh& mesh, NormalWeighting weighting) {
  Eigen::MatrixX3d normals = Eigen::MatrixX3d::Zero(mesh.V.rows(), 3);
  if (weighting == NormalWeighting::Area) {
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
      const Eigen::Vector3d a = corner(mesh, f, 0);
      const Eigen::RowVector3d n =
          (corner(mesh, f, 1) - a).cross(corner(mesh, f, 2) - a).transpose();
      for (int k = 0; k < 3; ++k) normals.row(mesh.F(f, k)) += n;
    }
  } else {
    const Eigen::MatrixX3d fn = face_normals(mesh);
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
      for (int k = 0; k < 3; ++k) {
        const double weight = weighting == NormalWeighting::Uniform
                                  ? 1.0
                                  : corner_angle(corner(mesh, f, k), corner(mesh, f, (k + 1) % 3),
                                                 corner(mesh, f, (k + 2) % 3));
        normals.row(mesh.F(f, k)) += weight * fn.row(f);
      }
    }
  }
  for (Eigen::Index i = 0; i < normals.rows(); ++i) {
    const double length = normals.row(i).norm();
    if (length > 0.0) normals.row(i) /= length;
  }
  return normals;
}

Eigen::SparseMatrix<double> cotangent_laplacian(const SurfaceMesh& mesh) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(mesh.F.rows()) * 12);
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      // Edge (i, j) opposite corner k.
      const int i = mesh.F(f, (k + 1) % 3);
      const int j = mesh.F(f, (k + 2) % 3);
      const Eigen::Vector3d u = mesh.V.row(i) - mesh.V.row(mesh.F(f, k));
      const Eigen::Vector3d v = mesh.V.row(j) - mesh.V.row(mesh.F(f, k));
      const double twice_area = u.cross(v).norm();
      if (!(twice_area > 0.0)) continue;
      const double w = 0.5 * u.dot(v) / twice_area;  // ½ cot of the corner angle
      entries.emplace_back(i, j, -w);
      entries.emplace_back(j, i, -w);
      entries.emplace_back(i, i, w);
      entries.emplace_back(j, j, w);
    }
  }
  Eigen::SparseMatrix<double> L(mesh.V.rows(), mesh.V.rows());
  L.setFromTriplets(entries.begin(), entries.end());
  return L;
}

Eigen::SparseMatrix<double> mass_matrix(const SurfaceMesh& mesh) {
  const Eigen::VectorXd areas = vertex_areas(mesh);
  Eigen::SparseMatrix<double> M(areas.size(), areas.size());
  M.reserve(Eigen::VectorXi::Ones(areas.size()));
  for (Eigen::Index i = 0; i < areas.size(); ++i) M.insert(i, i) = areas(i);
  M.makeCompressed();
  return M;
}

}  // namespace palpa::geometry
