// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/body/core_system.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "palpa/core/error.hpp"

namespace palpa::body {

namespace {

Eigen::Matrix3d hat(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0;
  return m;
}

}  // namespace

Eigen::Matrix3d exp_so3(const Eigen::Vector3d& w) {
  const double t2 = w.squaredNorm();
  const Eigen::Matrix3d K = hat(w);
  double a, b;
  if (t2 < 1e-12) {
    a = 1.0 - t2 / 6.0;
    b = 0.5 - t2 / 24.0;
  } else {
    const double t = std::sqrt(t2);
    a = std::sin(t) / t;
    b = (1.0 - std::cos(t)) / t2;
  }
  return Eigen::Matrix3d::Identity() + a * K + b * K * K;
}

Eigen::Matrix3d left_jacobian_so3(const Eigen::Vector3d& w) {
  const double t2 = w.squaredNorm();
  const Eigen::Matrix3d K = hat(w);
  double a, b;
  if (t2 < 1e-12) {
    a = 0.5 - t2 / 24.0;
    b = 1.0 / 6.0 - t2 / 120.0;
  } else {
    const double t = std::sqrt(t2);
    a = (1.0 - std::cos(t)) / t2;
    b = (t - std::sin(t)) / (t2 * t);
  }
  return Eigen::Matrix3d::Identity() + a * K + b * K * K;
}

CoreSystem::CoreSystem(const tet::ElasticModel& model, CoreSpec core) : model_(&model), core_(std::move(core)) {
  const Eigen::Index nv = model.num_vertices();
  if (core_.attached.empty()) {
    throw Error(ErrorKind::Input, "the rigid core has no attached vertices: nothing holds the layer to it");
  }
  if (!std::isfinite(core_.mass) || core_.mass < 0.0) {
    throw Error(ErrorKind::Input, fmt::format("core mass must be finite and ≥ 0 kg, got {}", core_.mass));
  }
  if (!core_.centre.allFinite() || !core_.force.allFinite() || !core_.torque.allFinite()) {
    throw Error(ErrorKind::Input, "core centre, force and torque must be finite");
  }
  is_attached_.assign(static_cast<std::size_t>(nv), 0);
  for (int v : core_.attached) {
    if (v < 0 || v >= nv) {
      throw Error(ErrorKind::Input, fmt::format("attached vertex {} is not a vertex of the layer ({} vertices)", v, nv));
    }
    is_attached_[static_cast<std::size_t>(v)] = 1;
  }
  full_ = std::make_unique<tet::StaticSystem>(model, std::vector<char>(static_cast<std::size_t>(3 * nv), 0));
  // The full system's own free DOFs exclude vertices no tet uses; so do ours.
  std::vector<char> in_full(static_cast<std::size_t>(3 * nv), 0);
  for (int d : full_->free_dofs()) in_full[static_cast<std::size_t>(d)] = 1;
  for (Eigen::Index d = 0; d < 3 * nv; ++d) {
    if (in_full[static_cast<std::size_t>(d)] && !is_attached_[static_cast<std::size_t>(d / 3)]) {
      free_.push_back(static_cast<int>(d));
    }
  }
  for (int k = 0; k < 6; ++k) {
    if (!core_.locked[static_cast<std::size_t>(k)]) core_dofs_.push_back(k);
  }
  if (core_dofs_.empty() && free_.empty()) {
    throw Error(ErrorKind::Input, "every core DOF is locked and every vertex is attached: nothing can move");
  }
}

CoreSystem::~CoreSystem() = default;

void CoreSystem::set_gravity(const Eigen::Vector3d& g) {
  gravity_ = g;
  full_->set_gravity(g);
}

bool CoreSystem::regularizing() const { return full_->regularizing(); }

Eigen::Vector3d CoreSystem::omega_total(const Eigen::VectorXd& x) const {
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < core_dofs_.size(); ++k) {
    const int c = core_dofs_[k];
    if (c >= 3) w[c - 3] = x[num_vertex_dofs() + static_cast<Eigen::Index>(k)];
  }
  return w;
}

Eigen::Vector3d CoreSystem::omega_local(const Eigen::VectorXd& x) const { return omega_total(x) - omega_committed_; }

Eigen::Vector3d CoreSystem::core_translation(const Eigen::VectorXd& x) const {
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < core_dofs_.size(); ++k) {
    const int c = core_dofs_[k];
    if (c < 3) t[c] = x[num_vertex_dofs() + static_cast<Eigen::Index>(k)];
  }
  return t;
}

Eigen::Matrix3d CoreSystem::core_rotation(const Eigen::VectorXd& x) const { return exp_so3(omega_local(x)) * rotation_; }

Eigen::VectorXd CoreSystem::full_displacement(const Eigen::VectorXd& x) const {
  const TetMesh& mesh = model_->mesh();
  Eigen::VectorXd u = Eigen::VectorXd::Zero(3 * mesh.V.rows());
  for (std::size_t k = 0; k < free_.size(); ++k) u[free_[k]] = x[static_cast<Eigen::Index>(k)];
  const Eigen::Vector3d t = core_translation(x);
  const Eigen::Matrix3d R = core_rotation(x);
  for (int v : core_.attached) {
    const Eigen::Vector3d X = mesh.V.row(v).transpose();
    u.segment<3>(3 * v) = core_.centre + t + R * (X - core_.centre) - X;
  }
  return u;
}

Eigen::VectorXd CoreSystem::positions(const Eigen::VectorXd& x) const {
  return full_->positions(full_displacement(x));
}

double CoreSystem::evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* g) const {
  const Eigen::VectorXd u = full_displacement(x);
  const Eigen::Vector3d t = core_translation(x);
  const Eigen::Vector3d w = omega_total(x);
  const double core_energy = -core_.mass * gravity_.dot(t) - core_.force.dot(t) - core_.torque.dot(w);
  if (g == nullptr) {
    const double e = full_->energy(full_->free_part(u));
    return std::isfinite(e) ? e + core_energy : std::numeric_limits<double>::infinity();
  }
  Eigen::VectorXd gf;
  const double e = full_->energy_gradient(full_->free_part(u), gf);
  if (!std::isfinite(e)) return std::numeric_limits<double>::infinity();
  Eigen::VectorXd G = Eigen::VectorXd::Zero(u.size());
  const std::vector<int>& fd = full_->free_dofs();
  for (std::size_t k = 0; k < fd.size(); ++k) G[fd[k]] = gf[static_cast<Eigen::Index>(k)];
  g->resize(num_dofs());
  for (std::size_t k = 0; k < free_.size(); ++k) (*g)[static_cast<Eigen::Index>(k)] = G[free_[k]];
  Eigen::Vector3d gt = -core_.mass * gravity_ - core_.force;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  const Eigen::Matrix3d Rl = exp_so3(omega_local(x));
  const Eigen::Matrix3d& Rc = rotation_;
  const TetMesh& mesh = model_->mesh();
  for (int v : core_.attached) {
    const Eigen::Vector3d gi = G.segment<3>(3 * v);
    const Eigen::Vector3d b = Rl * (Rc * (mesh.V.row(v).transpose() - core_.centre));
    gt += gi;
    moment += b.cross(gi);
  }
  const Eigen::Vector3d gw = left_jacobian_so3(omega_local(x)).transpose() * moment - core_.torque;
  for (std::size_t k = 0; k < core_dofs_.size(); ++k) {
    const int c = core_dofs_[k];
    (*g)[num_vertex_dofs() + static_cast<Eigen::Index>(k)] = c < 3 ? gt[c] : gw[c - 3];
  }
  return e + core_energy;
}

double CoreSystem::energy(const Eigen::VectorXd& x) const { return evaluate(x, nullptr); }
void CoreSystem::gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const { evaluate(x, &g); }
double CoreSystem::energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const { return evaluate(x, &g); }

Eigen::SparseMatrix<double> CoreSystem::coupling(const Eigen::VectorXd& x) const {
  // Rows: the full system's free DOFs; columns: ours.
  const std::vector<int>& fd = full_->free_dofs();
  std::vector<int> row_of(static_cast<std::size_t>(3 * model_->num_vertices()), -1);
  for (std::size_t k = 0; k < fd.size(); ++k) row_of[static_cast<std::size_t>(fd[k])] = static_cast<int>(k);
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(free_.size() + core_.attached.size() * 3 * core_dofs_.size());
  for (std::size_t k = 0; k < free_.size(); ++k) trip.emplace_back(row_of[static_cast<std::size_t>(free_[k])], static_cast<int>(k), 1.0);
  const Eigen::Matrix3d Rl = exp_so3(omega_local(x));
  const Eigen::Matrix3d Jl = left_jacobian_so3(omega_local(x));
  const TetMesh& mesh = model_->mesh();
  const int base = static_cast<int>(num_vertex_dofs());
  for (int v : core_.attached) {
    const Eigen::Vector3d b = Rl * (rotation_ * (mesh.V.row(v).transpose() - core_.centre));
    const Eigen::Matrix3d dw = -hat(b) * Jl;  // ∂x_i/∂ω
    for (int c = 0; c < 3; ++c) {
      const int r = row_of[static_cast<std::size_t>(3 * v + c)];
      if (r < 0) continue;
      for (std::size_t k = 0; k < core_dofs_.size(); ++k) {
        const int p = core_dofs_[k];
        const double value = p < 3 ? (p == c ? 1.0 : 0.0) : dw(c, p - 3);
        trip.emplace_back(r, base + static_cast<int>(k), value);
      }
    }
  }
  Eigen::SparseMatrix<double> P(static_cast<Eigen::Index>(fd.size()), num_dofs());
  P.setFromTriplets(trip.begin(), trip.end());
  return P;
}

void CoreSystem::hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const {
  const Eigen::VectorXd u = full_displacement(x);
  const Eigen::VectorXd xf = full_->free_part(u);
  thread_local Eigen::SparseMatrix<double> Hf;
  full_->hessian(xf, Hf);  // includes αM while nothing touches
  const Eigen::SparseMatrix<double> sym = Hf.selfadjointView<Eigen::Lower>();
  const Eigen::SparseMatrix<double> P = coupling(x);
  Eigen::SparseMatrix<double> reduced = P.transpose() * (sym * P);
  // Rotational curvature: Σ_i ½(g_i b_iᵀ + b_i g_iᵀ) − (g_i·b_i) I.
  Eigen::VectorXd gf;
  full_->gradient(xf, gf);
  Eigen::VectorXd G = Eigen::VectorXd::Zero(u.size());
  const std::vector<int>& fd = full_->free_dofs();
  for (std::size_t k = 0; k < fd.size(); ++k) G[fd[k]] = gf[static_cast<Eigen::Index>(k)];
  Eigen::Matrix3d curvature = Eigen::Matrix3d::Zero();
  const Eigen::Matrix3d Rl = exp_so3(omega_local(x));
  const TetMesh& mesh = model_->mesh();
  for (int v : core_.attached) {
    const Eigen::Vector3d gi = G.segment<3>(3 * v);
    const Eigen::Vector3d b = Rl * (rotation_ * (mesh.V.row(v).transpose() - core_.centre));
    curvature += 0.5 * (gi * b.transpose() + b * gi.transpose()) - gi.dot(b) * Eigen::Matrix3d::Identity();
  }
  const Eigen::Index base = num_vertex_dofs();
  for (std::size_t i = 0; i < core_dofs_.size(); ++i) {
    for (std::size_t j = 0; j < core_dofs_.size(); ++j) {
      const int a = core_dofs_[i], b = core_dofs_[j];
      double add = 0.0;
      if (a >= 3 && b >= 3) add += curvature(a - 3, b - 3);
      if (a < 3 && a == b && full_->regularizing()) add += alpha_ * core_.mass;
      if (add != 0.0) reduced.coeffRef(base + static_cast<Eigen::Index>(i), base + static_cast<Eigen::Index>(j)) += add;
    }
  }
  H = reduced.triangularView<Eigen::Lower>();
  H.makeCompressed();
}

void CoreSystem::set_committed(const Committed& c) {
  if (!c.rotation.allFinite() || !c.omega.allFinite() ||
      (c.rotation.transpose() * c.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9) {
    throw Error(ErrorKind::Input, "a committed core pose must be a finite rotation and rotation vector");
  }
  rotation_ = c.rotation;
  omega_committed_ = c.omega;
}

Eigen::VectorXd CoreSystem::pull_back(const Eigen::VectorXd& x, const Eigen::VectorXd& G) const {
  const std::vector<int>& fd = full_->free_dofs();
  Eigen::VectorXd gf(static_cast<Eigen::Index>(fd.size()));
  for (std::size_t k = 0; k < fd.size(); ++k) gf[static_cast<Eigen::Index>(k)] = G[fd[k]];
  return coupling(x).transpose() * gf;
}

Eigen::VectorXd CoreSystem::push_forward(const Eigen::VectorXd& x, const Eigen::VectorXd& z) const {
  const std::vector<int>& fd = full_->free_dofs();
  const Eigen::VectorXd zf = coupling(x) * z;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(3 * model_->num_vertices());
  for (std::size_t k = 0; k < fd.size(); ++k) u[fd[k]] = zf[static_cast<Eigen::Index>(k)];
  return u;
}

void CoreSystem::prepare(const Eigen::VectorXd& x) {
  rotation_ = core_rotation(x);
  omega_committed_ = omega_total(x);
  full_->prepare(full_->free_part(full_displacement(x)));
}

}  // namespace palpa::body
