// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/geometry/surface_interpolation.hpp"

#include <fmt/format.h>

#include <Eigen/QR>
#include <algorithm>
#include <numeric>

#include "palpa/core/error.hpp"
#include "palpa/core/units.hpp"
#include "palpa/geometry/format.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/geometry/triangle_tree.hpp"
#include "palpa/solve/sparse_cholesky.hpp"

namespace palpa::geometry {
namespace {

// Relative rank threshold of the linear (affine) fit of the biharmonic method.
constexpr double kAffineRankThreshold = 1e-8;

// Connected components of the triangle graph: component id per vertex, -1 for
// vertices used by no triangle.
Eigen::VectorXi vertex_components(const SurfaceMesh& mesh) {
  std::vector<int> parent(static_cast<std::size_t>(mesh.V.rows()));
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&parent](int i) {
    while (parent[i] != i) {
      parent[i] = parent[parent[i]];
      i = parent[i];
    }
    return i;
  };
  std::vector<bool> used(parent.size(), false);
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      used[mesh.F(f, k)] = true;
      parent[find(mesh.F(f, k))] = find(mesh.F(f, (k + 1) % 3));
    }
  }
  Eigen::VectorXi component(mesh.V.rows());
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) component(i) = used[i] ? find(int(i)) : -1;
  return component;
}

}  // namespace

struct SurfaceInterpolator::Impl {
  InterpolationOptions options;
  Eigen::MatrixX3d V;
  std::vector<SurfacePoint> points;
  std::vector<Eigen::Index> sample_vertex;  // #S
  std::vector<Eigen::Index> free_of;        // #V: index among free vertices, or -1
  std::vector<Eigen::Index> free_vertices;  // free index -> vertex
  Eigen::SparseMatrix<double> Q_fk;         // #free×#S coupling to the sample vertices
  SparseCholesky cholesky{SparseCholesky::Method::Auto};  // of Q_ff
  // Biharmonic only: affine basis [1, (x − centre)/scale] at sample vertices.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double scale = 1.0;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> affine_fit;
  Eigen::MatrixXd sample_basis;

  std::string label(Eigen::Index s) const {
    const auto i = static_cast<std::size_t>(s);
    return i < options.sample_labels.size() ? options.sample_labels[i]
                                            : fmt::format("sample {}", s);
  }
  ErrorContext context() const {
    ErrorContext c;
    c.file = options.source;
    return c;
  }

  Eigen::MatrixXd affine_basis(const Eigen::MatrixX3d& X) const {
    Eigen::MatrixXd B(X.rows(), 4);
    B.col(0).setOnes();
    B.rightCols(3) = (X.rowwise() - centre.transpose()) / scale;
    return B;
  }

  void locate(const SurfaceMesh& mesh, const Eigen::MatrixX3d& positions);
  void check_coverage(const SurfaceMesh& mesh) const;
  void factor(const Eigen::SparseMatrix<double>& Q);
};

void SurfaceInterpolator::Impl::locate(const SurfaceMesh& mesh,
                                       const Eigen::MatrixX3d& positions) {
  points.reserve(static_cast<std::size_t>(positions.rows()));
  free_of.assign(static_cast<std::size_t>(mesh.V.rows()), -1);
  std::vector<Eigen::Index> owner(static_cast<std::size_t>(mesh.V.rows()), -1);
  const TriangleTree tree(mesh.V, mesh.F);
  for (Eigen::Index s = 0; s < positions.rows(); ++s) {
    const Eigen::Vector3d p = positions.row(s).transpose();
    if (!p.allFinite()) {
      throw_input_error(fmt::format("{} has a non-finite position", label(s)), context(),
                        "finite coordinates");
    }
    SurfacePoint q = closest_point(mesh, tree, p);
    if (q.distance > options.max_distance) {
      throw_input_error(
          fmt::format("{} at {} is {} from the surface", label(s), format_point(p),
                      format_quantity(q.distance, Dimension::Length)),
          context(),
          fmt::format("a point within {} of the surface (the same length unit and placement "
                      "as the surface)",
                      format_quantity(options.max_distance, Dimension::Length)));
    }
    int corner = 0;
    q.barycentric.maxCoeff(&corner);
    const Eigen::Index v = mesh.F(q.face, corner);
    if (owner[v] >= 0) {
      throw_input_error(
          fmt::format("{} and {} are both nearest to surface vertex {} at {}", label(owner[v]),
                      label(s), v, format_point(mesh.V.row(v).transpose())),
          context(),
          "samples farther apart than the surface's edge length (refine the surface or merge "
          "the samples)");
    }
    owner[v] = s;
    points.push_back(q);
    sample_vertex.push_back(v);
  }
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
    if (owner[v] < 0) {
      free_of[v] = static_cast<Eigen::Index>(free_vertices.size());
      free_vertices.push_back(v);
    }
  }
}

void SurfaceInterpolator::Impl::check_coverage(const SurfaceMesh& mesh) const {
  const Eigen::VectorXi component = vertex_components(mesh);
  for (Eigen::Index i = 0; i < component.size(); ++i) {
    if (component(i) < 0) {
      throw_input_error(fmt::format("surface vertex {} belongs to no triangle", i), context(),
                        "a surface whose every vertex is used by a triangle");
    }
  }
  std::vector<bool> sampled(static_cast<std::size_t>(mesh.V.rows()), false);
  for (const Eigen::Index v : sample_vertex) sampled[component(v)] = true;
  for (Eigen::Index i = 0; i < component.size(); ++i) {
    if (!sampled[component(i)]) {
      throw_input_error(
          fmt::format("the connected part of the surface holding vertex {} has no sample", i),
          context(), "at least one sample on every connected part of the surface");
    }
  }
}

void SurfaceInterpolator::Impl::factor(const Eigen::SparseMatrix<double>& Q) {
  // Split Q into the free block Q_ff (factored) and the coupling Q_fk.
  std::vector<Eigen::Index> sample_of(free_of.size(), -1);
  for (std::size_t s = 0; s < sample_vertex.size(); ++s) {
    sample_of[sample_vertex[s]] = static_cast<Eigen::Index>(s);
  }
  std::vector<Eigen::Triplet<double>> ff, fk;
  for (Eigen::Index col = 0; col < Q.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(Q, col); it; ++it) {
      const Eigen::Index r = free_of[it.row()];
      if (r < 0) continue;
      if (free_of[col] >= 0) {
        ff.emplace_back(r, free_of[col], it.value());
      } else {
        fk.emplace_back(r, sample_of[col], it.value());
      }
    }
  }
  const auto n_free = static_cast<Eigen::Index>(free_vertices.size());
  Q_fk.resize(n_free, static_cast<Eigen::Index>(sample_vertex.size()));
  Q_fk.setFromTriplets(fk.begin(), fk.end());
  if (n_free == 0) return;
  Eigen::SparseMatrix<double> Q_ff(n_free, n_free);
  Q_ff.setFromTriplets(ff.begin(), ff.end());
  const FactorStatus status = cholesky.factorize(Q_ff);
  if (status != FactorStatus::Ok) {
    throw_solver_error(fmt::format("surface interpolation: the sparse factorization failed ({})",
                                   to_string(status)),
                       context());
  }
}

SurfaceInterpolator::SurfaceInterpolator(const SurfaceMesh& mesh,
                                         const Eigen::MatrixX3d& sample_positions,
                                         const InterpolationOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.options = options;
  m.V = mesh.V;
  if (!(options.max_distance > 0.0)) {
    throw_input_error("the largest sample distance from the surface is not positive",
                      m.context(), "max_distance > 0");
  }
  if (mesh.F.rows() == 0) {
    throw_input_error("the surface has no triangles", m.context(), "a triangle surface");
  }
  if (sample_positions.rows() == 0) {
    throw_input_error("no samples to interpolate", m.context(), "at least one sample");
  }
  m.locate(mesh, sample_positions);
  m.check_coverage(mesh);

  const Eigen::SparseMatrix<double> L = cotangent_laplacian(mesh);
  if (options.method == SurfaceInterpolation::Harmonic) {
    m.factor(L);
    return;
  }
  // Biharmonic: Q = L M⁻¹ L, with a floor on vertex areas so that a vertex
  // whose triangles are all degenerate does not divide by zero.
  Eigen::VectorXd areas = vertex_areas(mesh);
  areas = areas.cwiseMax(1e-12 * areas.mean());
  m.factor(L * areas.cwiseInverse().asDiagonal() * L);

  const Eigen::Index S = sample_positions.rows();
  Eigen::MatrixX3d at_samples(S, 3);
  for (Eigen::Index s = 0; s < S; ++s) at_samples.row(s) = mesh.V.row(m.sample_vertex[s]);
  m.centre = at_samples.colwise().mean().transpose();
  m.scale = std::max((mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm(), 1e-300);
  m.sample_basis = m.affine_basis(at_samples);
  m.affine_fit.setThreshold(kAffineRankThreshold);
  m.affine_fit.compute(m.sample_basis);
}

SurfaceInterpolator::~SurfaceInterpolator() = default;
SurfaceInterpolator::SurfaceInterpolator(SurfaceInterpolator&&) noexcept = default;
SurfaceInterpolator& SurfaceInterpolator::operator=(SurfaceInterpolator&&) noexcept = default;

Eigen::MatrixXd SurfaceInterpolator::interpolate_columns(const Eigen::MatrixXd& values) const {
  const Impl& m = *impl_;
  const auto S = static_cast<Eigen::Index>(m.sample_vertex.size());
  if (values.rows() != S) {
    throw_input_error(fmt::format("{} sample values for {} samples", values.rows(), S),
                      m.context(), "one value row per sample");
  }
  for (Eigen::Index s = 0; s < S; ++s) {
    if (!values.row(s).allFinite()) {
      throw_input_error(fmt::format("{} has a non-finite value", m.label(s)), m.context(),
                        "finite values");
    }
  }
  const bool biharmonic = m.options.method == SurfaceInterpolation::Biharmonic;
  Eigen::MatrixXd coefficients;
  Eigen::MatrixXd residual = values;
  if (biharmonic) {
    coefficients = m.affine_fit.solve(values);
    residual -= m.sample_basis * coefficients;
  }
  Eigen::MatrixXd u(m.V.rows(), values.cols());
  if (!m.free_vertices.empty()) {
    const Eigen::MatrixXd u_free = m.cholesky.solve(-(m.Q_fk * residual));
    for (std::size_t i = 0; i < m.free_vertices.size(); ++i) {
      u.row(m.free_vertices[i]) = u_free.row(static_cast<Eigen::Index>(i));
    }
  }
  for (std::size_t s = 0; s < m.sample_vertex.size(); ++s) {
    u.row(m.sample_vertex[s]) = residual.row(static_cast<Eigen::Index>(s));
  }
  if (biharmonic) {
    u += m.affine_basis(m.V) * coefficients;
    // Bit-exact at the samples (the sum above rounds).
    for (std::size_t s = 0; s < m.sample_vertex.size(); ++s) {
      u.row(m.sample_vertex[s]) = values.row(static_cast<Eigen::Index>(s));
    }
  }
  if (m.options.clamp_to_sample_range) {
    for (Eigen::Index j = 0; j < u.cols(); ++j) {
      u.col(j) = u.col(j).cwiseMax(values.col(j).minCoeff()).cwiseMin(values.col(j).maxCoeff());
    }
  }
  return u;
}

Eigen::VectorXd SurfaceInterpolator::interpolate(const Eigen::VectorXd& values) const {
  return interpolate_columns(values).col(0);
}

const std::vector<SurfacePoint>& SurfaceInterpolator::sample_points() const noexcept {
  return impl_->points;
}
const std::vector<Eigen::Index>& SurfaceInterpolator::sample_vertices() const noexcept {
  return impl_->sample_vertex;
}
Eigen::Index SurfaceInterpolator::vertex_count() const noexcept { return impl_->V.rows(); }
Eigen::Index SurfaceInterpolator::sample_count() const noexcept {
  return static_cast<Eigen::Index>(impl_->sample_vertex.size());
}

Eigen::VectorXd interpolate_over_surface(const SurfaceMesh& mesh,
                                         const Eigen::MatrixX3d& sample_positions,
                                         const Eigen::VectorXd& values,
                                         const InterpolationOptions& options) {
  return SurfaceInterpolator(mesh, sample_positions, options).interpolate(values);
}

}  // namespace palpa::geometry
