// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/tet/model.hpp"

#include <atomic>
#include <cassert>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "palpa/core/error.hpp"
#include "palpa/tet/nodal_pressure.hpp"

namespace palpa::tet {

namespace {
constexpr std::size_t kGrain = 256;
}

ElasticModel::ElasticModel(TetMesh mesh, std::vector<BodyMaterial> materials,
                           Eigen::VectorXi element_material)
    : mesh_(std::move(mesh)), materials_(std::move(materials)), element_material_(std::move(element_material)) {
  if (materials_.empty()) throw Error(ErrorKind::Input, "a body needs at least one material");
  for (std::size_t k = 0; k < materials_.size(); ++k) {
    if (!materials_[k].material) throw Error(ErrorKind::Input, fmt::format("material {} is missing", k));
    const double rho = materials_[k].density;
    if (!std::isfinite(rho) || rho < 0.0) {
      throw Error(ErrorKind::Input,
                  fmt::format("material {}: density must be finite and ≥ 0 kg/m³, got {}", k, rho));
    }
  }
  if (element_material_.size() == 0) element_material_ = Eigen::VectorXi::Zero(mesh_.T.rows());
  if (element_material_.size() != mesh_.T.rows()) {
    throw Error(ErrorKind::Input, fmt::format("{} element materials for {} tetrahedra",
                                              element_material_.size(), mesh_.T.rows()));
  }
  const int nm = static_cast<int>(materials_.size());
  for (Eigen::Index e = 0; e < element_material_.size(); ++e) {
    if (element_material_[e] < 0 || element_material_[e] >= nm) {
      throw Error(ErrorKind::Input, fmt::format("tetrahedron {} uses material {}, but there are {} materials", e,
                                                element_material_[e], nm));
    }
  }
  const Eigen::Index bad = compute_rest_data(mesh_.V, geometry_, lumped_mass_);
  if (bad >= 0) {
    throw Error(ErrorKind::Input, fmt::format("tetrahedron {} is inverted or flat (volume {:.3g} m³)", bad,
                                              geometry_[static_cast<std::size_t>(bad)].volume));
  }
}

void ElasticModel::set_element(TetElement element, double stabilization) {
  if (!(stabilization >= 0.0 && stabilization < 1.0)) {
    throw Error(ErrorKind::Input, fmt::format("a stabilization of {} is outside [0, 1)", stabilization));
  }
  if (element == TetElement::Linear && stabilization != 0.0) {
    throw Error(ErrorKind::Input, "a stabilization needs the nodal-pressure element");
  }
  element_ = element;
  stabilization_ = stabilization;
}

Eigen::Index ElasticModel::compute_rest_data(const Eigen::MatrixX3d& V, std::vector<TetGeometry>& geometry,
                                             Eigen::VectorXd& lumped_mass) const {
  geometry.resize(static_cast<std::size_t>(mesh_.T.rows()));
  lumped_mass = Eigen::VectorXd::Zero(V.rows());
  for (Eigen::Index e = 0; e < mesh_.T.rows(); ++e) {
    Mat34 X;
    for (int a = 0; a < 4; ++a) X.col(a) = V.row(mesh_.T(e, a)).transpose();
    auto& g = geometry[static_cast<std::size_t>(e)];
    g = tet_geometry(X);
    if (!(g.volume > 0.0) || !std::isfinite(g.volume)) return e;
    const double m = materials_[static_cast<std::size_t>(element_material_[e])].density * g.volume / 4.0;
    for (int a = 0; a < 4; ++a) lumped_mass[mesh_.T(e, a)] += m;
  }
  return -1;
}

void ElasticModel::set_rest_positions(const Eigen::MatrixX3d& V) {
  if (V.rows() != mesh_.V.rows()) {
    throw Error(ErrorKind::Input,
                fmt::format("{} rest positions for a mesh of {} vertices", V.rows(), mesh_.V.rows()));
  }
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    if (!V.row(v).allFinite()) {
      throw Error(ErrorKind::Solver, fmt::format("rest position of vertex {} is not finite ({}, {}, {})", v,
                                                 V(v, 0), V(v, 1), V(v, 2)));
    }
  }
  // Into temporaries first, so that a refused update leaves the model as it was.
  std::vector<TetGeometry> geometry;
  Eigen::VectorXd lumped_mass;
  const Eigen::Index bad = compute_rest_data(V, geometry, lumped_mass);
  if (bad >= 0) {
    throw Error(ErrorKind::Solver,
                fmt::format("new rest positions make tetrahedron {} inverted or flat (volume {:.3g} m³)", bad,
                            geometry[static_cast<std::size_t>(bad)].volume));
  }
  mesh_.V = V;
  geometry_ = std::move(geometry);
  lumped_mass_ = std::move(lumped_mass);
}

Eigen::MatrixX3d ElasticModel::rest_gradient_product(const Eigen::VectorXd& u, const Eigen::VectorXd& z) const {
  assert(u.size() == num_dofs() && z.size() == num_dofs());
  const auto n_el = static_cast<std::size_t>(mesh_.T.rows());
  // Per element, then a serial scatter (deterministic sums).
  std::vector<Mat34> local(n_el);
  std::atomic<bool> admissible{true};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_el, kGrain), [&](const auto& range) {
    for (std::size_t e = range.begin(); e != range.end(); ++e) {
      const auto ei = static_cast<Eigen::Index>(e);
      const Mat34 x = element_positions(u, ei);
      const double J = deformation_gradient(geometry_[e], x).determinant();
      if (!(J > 0.0) || !std::isfinite(J)) {
        admissible = false;
        return;
      }
      Mat34 ze;
      for (int a = 0; a < 4; ++a) ze.col(a) = z.segment<3>(3 * mesh_.T(ei, a));
      tet_rest_gradient_product(material_of(ei), geometry_[e], x, ze, local[e]);
    }
  });
  if (!admissible) throw Error(ErrorKind::Internal, "rest-position derivative requested at an inverted configuration");
  Eigen::MatrixX3d out = Eigen::MatrixX3d::Zero(mesh_.V.rows(), 3);
  for (std::size_t e = 0; e < n_el; ++e) {
    for (int a = 0; a < 4; ++a) out.row(mesh_.T(static_cast<Eigen::Index>(e), a)) += local[e].col(a).transpose();
  }
  return out;
}

Eigen::SparseMatrix<double> ElasticModel::consistent_mass() const {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<std::size_t>(mesh_.T.rows()) * 30);
  for (Eigen::Index e = 0; e < mesh_.T.rows(); ++e) {
    const double m = materials_[static_cast<std::size_t>(element_material_[e])].density *
                     geometry_[static_cast<std::size_t>(e)].volume / 20.0;
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) {
        const int va = mesh_.T(e, a);
        const int vb = mesh_.T(e, b);
        if (va < vb) continue;
        for (int c = 0; c < 3; ++c) trip.emplace_back(3 * va + c, 3 * vb + c, a == b ? 2.0 * m : m);
      }
    }
  }
  Eigen::SparseMatrix<double> M(num_dofs(), num_dofs());
  M.setFromTriplets(trip.begin(), trip.end());
  return M;
}

Mat34 ElasticModel::element_positions(const Eigen::VectorXd& u, Eigen::Index e) const {
  Mat34 x;
  for (int a = 0; a < 4; ++a) {
    const int v = mesh_.T(e, a);
    x.col(a) = mesh_.V.row(v).transpose() + u.segment<3>(3 * v);
  }
  return x;
}

double ElasticModel::elastic_energy(const Eigen::VectorXd& u, Eigen::VectorXd* g) const {
  const auto n_el = static_cast<std::size_t>(mesh_.T.rows());
  const auto order = g != nullptr ? material::EvalOrder::Gradient : material::EvalOrder::Energy;
  std::atomic<bool> admissible{true};
  if (g == nullptr) {
    // Deterministic reduction: the same u gives the same bits on every run, so
    // line searches and resumed runs compare energies reproducibly.
    const double total = tbb::parallel_deterministic_reduce(
        tbb::blocked_range<std::size_t>(0, n_el, kGrain), 0.0,
        [&](const auto& range, double sum) {
          TetResult r;
          for (std::size_t e = range.begin(); e != range.end(); ++e) {
            const auto ei = static_cast<Eigen::Index>(e);
            if (!tet_evaluate(material_of(ei), geometry_[e], element_positions(u, ei), order,
                              material::PsdProjection::None, r)) {
              admissible = false;
              return sum;
            }
            sum += r.energy;
          }
          return sum;
        },
        std::plus<>(), tbb::simple_partitioner());
    return admissible ? total : std::numeric_limits<double>::infinity();
  }
  // Gradients per element, then a serial scatter (deterministic sums).
  std::vector<Vec12> local(n_el);
  std::vector<double> energies(n_el, 0.0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_el, kGrain), [&](const auto& range) {
    TetResult r;
    for (std::size_t e = range.begin(); e != range.end(); ++e) {
      const auto ei = static_cast<Eigen::Index>(e);
      if (!tet_evaluate(material_of(ei), geometry_[e], element_positions(u, ei), order,
                        material::PsdProjection::None, r)) {
        admissible = false;
        return;
      }
      energies[e] = r.energy;
      local[e] = r.gradient;
    }
  });
  if (!admissible) return std::numeric_limits<double>::infinity();
  g->setZero(num_dofs());
  double total = 0.0;
  for (std::size_t e = 0; e < n_el; ++e) {
    total += energies[e];
    for (int a = 0; a < 4; ++a) {
      g->segment<3>(3 * mesh_.T(static_cast<Eigen::Index>(e), a)) += local[e].segment<3>(3 * a);
    }
  }
  return total;
}

Eigen::MatrixXd ElasticModel::gradient_param_jacobian(const Eigen::VectorXd& u, std::size_t k) const {
  const auto& m = *materials_.at(k).material;
  const Eigen::Index p = m.num_params();
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(num_dofs(), p);
  Eigen::MatrixXd work3(3, p);
  Eigen::MatrixXd work9(9, p);
  Eigen::MatrixXd block(12, p);
  for (Eigen::Index e = 0; e < mesh_.T.rows(); ++e) {
    if (static_cast<std::size_t>(element_material_[e]) != k) continue;
    tet_dgradient_dparam(m, geometry_[static_cast<std::size_t>(e)], element_positions(u, e), work3, work9, block);
    for (int a = 0; a < 4; ++a) J.middleRows(3 * mesh_.T(e, a), 3) += block.middleRows(3 * a, 3);
  }
  return J;
}

Eigen::VectorXd ElasticModel::gravity_gradient(const Eigen::Vector3d& gravity) const {
  Eigen::VectorXd g(num_dofs());
  for (Eigen::Index v = 0; v < mesh_.V.rows(); ++v) g.segment<3>(3 * v) = -lumped_mass_[v] * gravity;
  return g;
}

Eigen::MatrixXd ElasticModel::cauchy_stress(const Eigen::VectorXd& u) const {
  Eigen::MatrixXd s(mesh_.T.rows(), 6);
  // With nodal pressure, the share (1−β) of each tet's pressure U'(J_e) is
  // replaced by the pressure its corners' patches exert on it: the nodal
  // term's force on the tet is c_e ∂v_e, c_e = Σ_{a∈e} W_a'(J_a)/(4 V̂_a).
  const double nodal_share = element_ == TetElement::NodalPressure ? 1.0 - stabilization_ : 0.0;
  Eigen::VectorXd nodal_pressure;
  if (nodal_share > 0.0) {
    const Eigen::Index nv = mesh_.V.rows(), nt = mesh_.T.rows();
    Eigen::VectorXd rest = Eigen::VectorXd::Zero(nv), current = Eigen::VectorXd::Zero(nv);
    for (Eigen::Index e = 0; e < nt; ++e) {
      const double v = tet_volume(element_positions(u, e));
      for (int a = 0; a < 4; ++a) {
        rest[mesh_.T(e, a)] += geometry_[static_cast<std::size_t>(e)].volume / 4.0;
        current[mesh_.T(e, a)] += v / 4.0;
      }
    }
    Eigen::VectorXd slope = Eigen::VectorXd::Zero(nv);
    for (Eigen::Index e = 0; e < nt; ++e) {
      for (int a = 0; a < 4; ++a) {
        const int va = mesh_.T(e, a);
        const double J = current[va] / rest[va];
        if (!(J > 0.0)) continue;
        slope[va] += nodal_share * geometry_[static_cast<std::size_t>(e)].volume / 4.0 *
                     dilatation(material_of(e), J).du / (4.0 * rest[va]);
      }
    }
    nodal_pressure.resize(nt);
    for (Eigen::Index e = 0; e < nt; ++e) {
      nodal_pressure[e] = slope[mesh_.T(e, 0)] + slope[mesh_.T(e, 1)] + slope[mesh_.T(e, 2)] + slope[mesh_.T(e, 3)];
    }
  }
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, mesh_.T.rows(), kGrain), [&](const auto& range) {
    for (Eigen::Index e = range.begin(); e != range.end(); ++e) {
      const Mat34 x = element_positions(u, e);
      const double J = deformation_gradient(geometry_[static_cast<std::size_t>(e)], x).determinant();
      if (!(J > 0.0)) {
        s.row(e).setZero();  // undefined; the caller reports det F (no NaN in any output)
        continue;
      }
      material::Mat3 c = tet::cauchy_stress(material_of(e), geometry_[static_cast<std::size_t>(e)], x);
      if (nodal_share > 0.0) {
        c.diagonal().array() += nodal_pressure[e] - nodal_share * dilatation(material_of(e), J).du;
      }
      s.row(e) << c(0, 0), c(1, 1), c(2, 2), c(1, 2), c(0, 2), c(0, 1);
    }
  });
  return s;
}

Eigen::VectorXd ElasticModel::von_mises(const Eigen::MatrixXd& s) {
  Eigen::VectorXd vm(s.rows());
  for (Eigen::Index e = 0; e < s.rows(); ++e) {
    const double a = s(e, 0) - s(e, 1);
    const double b = s(e, 1) - s(e, 2);
    const double c = s(e, 2) - s(e, 0);
    vm[e] = std::sqrt(0.5 * (a * a + b * b + c * c) + 3.0 * (s(e, 3) * s(e, 3) + s(e, 4) * s(e, 4) + s(e, 5) * s(e, 5)));
  }
  return vm;
}

double ElasticModel::min_jacobian(const Eigen::VectorXd& u) const {
  double j = std::numeric_limits<double>::infinity();
  for (Eigen::Index e = 0; e < mesh_.T.rows(); ++e) {
    j = std::min(j, deformation_gradient(geometry_[static_cast<std::size_t>(e)], element_positions(u, e)).determinant());
  }
  return j;
}

}  // namespace palpa::tet
