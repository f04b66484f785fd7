// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/solve/dof_map.hpp"

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "palpa/core/error.hpp"
#include "palpa/solve/so3.hpp"

namespace palpa {

DofMap::DofMap(const Eigen::MatrixX3d& rest, std::vector<char> fixed, std::optional<RigidCore> core)
    : rest_(&rest), fixed_(std::move(fixed)), core_(std::move(core)) {
  const Eigen::Index nv = rest.rows();
  if (static_cast<Eigen::Index>(fixed_.size()) != 3 * nv) {
    throw Error(ErrorKind::Internal, fmt::format("{} fixed-DOF flags for {} vertices", fixed_.size(), nv));
  }
  is_attached_.assign(static_cast<std::size_t>(nv), 0);
  if (core_) {
    for (int v : core_->attached) {
      if (v < 0 || v >= nv) {
        throw Error(ErrorKind::Internal, fmt::format("attached vertex {} of {} vertices", v, nv));
      }
      is_attached_[static_cast<std::size_t>(v)] = 1;
    }
    for (int k = 0; k < 6; ++k) {
      if (!core_->locked[static_cast<std::size_t>(k)]) core_dofs_.push_back(k);
    }
  }
  full_to_free_.assign(static_cast<std::size_t>(3 * nv), -1);
  for (Eigen::Index d = 0; d < 3 * nv; ++d) {
    if (!fixed_[static_cast<std::size_t>(d)] && !is_attached_[static_cast<std::size_t>(d / 3)]) {
      full_to_free_[static_cast<std::size_t>(d)] = static_cast<int>(free_.size());
      free_.push_back(static_cast<int>(d));
    }
  }
  prescribed_ = Eigen::VectorXd::Zero(3 * nv);
}

void DofMap::set_prescribed(const Eigen::VectorXd& u_fixed) {
  if (u_fixed.size() != prescribed_.size()) {
    throw Error(ErrorKind::Internal, "prescribed displacement of the wrong size");
  }
  for (Eigen::Index d = 0; d < u_fixed.size(); ++d) {
    prescribed_[d] = fixed_[static_cast<std::size_t>(d)] ? u_fixed[d] : 0.0;
  }
}

Eigen::Vector3d DofMap::core_translation(const Eigen::VectorXd& x) const {
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < core_dofs_.size(); ++k) {
    const int c = core_dofs_[k];
    if (c < 3) t[c] = x[num_vertex_dofs() + static_cast<Eigen::Index>(k)];
  }
  return t;
}

Eigen::Vector3d DofMap::core_omega(const Eigen::VectorXd& x) const {
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < core_dofs_.size(); ++k) {
    const int c = core_dofs_[k];
    if (c >= 3) w[c - 3] = x[num_vertex_dofs() + static_cast<Eigen::Index>(k)];
  }
  return w;
}

Eigen::Matrix3d DofMap::core_rotation(const Eigen::VectorXd& x) const {
  return exp_so3(omega_local(x)) * committed_.rotation;
}

DofMap::Frame DofMap::frame(const Eigen::VectorXd& x) const {
  if (!core_) return {};
  const Eigen::Vector3d w = omega_local(x);
  return {exp_so3(w) * committed_.rotation, left_jacobian_so3(w)};
}

Eigen::Vector3d DofMap::lever(const Frame& f, Eigen::Index v) const {
  return f.turn * (rest_->row(v).transpose() - core_->centre);
}

void DofMap::core_jacobian(const Frame& f, Eigen::Index v, Eigen::Ref<Eigen::MatrixXd> B) const {
  const Eigen::Matrix3d dw = -hat(lever(f, v)) * f.jacobian;  // ∂p/∂ω
  for (std::size_t k = 0; k < core_dofs_.size(); ++k) {
    const int p = core_dofs_[k];
    const auto col = static_cast<Eigen::Index>(k);
    if (p < 3) {
      B.col(col).setZero();
      B(p, col) = 1.0;
    } else {
      B.col(col) = dw.col(p - 3);
    }
  }
}

Eigen::VectorXd DofMap::displacement(const Eigen::VectorXd& x) const {
  Eigen::VectorXd u = prescribed_;
  for (std::size_t k = 0; k < free_.size(); ++k) u[free_[k]] = x[static_cast<Eigen::Index>(k)];
  if (core_) {
    const Eigen::Vector3d t = core_translation(x);
    const Eigen::Matrix3d R = core_rotation(x);
    for (int v : core_->attached) {
      const Eigen::Vector3d X = rest_->row(v).transpose();
      u.segment<3>(3 * v) = core_->centre + t + R * (X - core_->centre) - X;
    }
  }
  return u;
}

Eigen::VectorXd DofMap::positions(const Eigen::VectorXd& u) const {
  Eigen::VectorXd p(u.size());
  for (Eigen::Index v = 0; v < rest_->rows(); ++v) p.segment<3>(3 * v) = rest_->row(v).transpose() + u.segment<3>(3 * v);
  return p;
}

Eigen::VectorXd DofMap::free_part(const Eigen::VectorXd& u) const {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(num_dofs());
  for (std::size_t k = 0; k < free_.size(); ++k) x[static_cast<Eigen::Index>(k)] = u[free_[k]];
  return x;
}

Eigen::VectorXd DofMap::pull_back(const Eigen::VectorXd& x, const Eigen::VectorXd& G) const {
  Eigen::VectorXd g(num_dofs());
  for (std::size_t k = 0; k < free_.size(); ++k) g[static_cast<Eigen::Index>(k)] = G[free_[k]];
  if (core_dofs_.empty()) return g;
  const Frame f = frame(x);
  Eigen::Vector3d gt = Eigen::Vector3d::Zero();
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (int v : core_->attached) {
    const Eigen::Vector3d gi = G.segment<3>(3 * v);
    gt += gi;
    moment += lever(f, v).cross(gi);
  }
  const Eigen::Vector3d gw = f.jacobian.transpose() * moment;
  for (std::size_t k = 0; k < core_dofs_.size(); ++k) {
    const int c = core_dofs_[k];
    g[num_vertex_dofs() + static_cast<Eigen::Index>(k)] = c < 3 ? gt[c] : gw[c - 3];
  }
  return g;
}

Eigen::VectorXd DofMap::push_forward(const Eigen::VectorXd& x, const Eigen::VectorXd& z) const {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(3 * num_vertices());
  for (std::size_t k = 0; k < free_.size(); ++k) u[free_[k]] = z[static_cast<Eigen::Index>(k)];
  if (core_dofs_.empty()) return u;
  const Frame f = frame(x);
  const Eigen::VectorXd zc = z.tail(num_core_dofs());
  Eigen::MatrixXd B(3, num_core_dofs());
  for (int v : core_->attached) {
    core_jacobian(f, v, B);
    u.segment<3>(3 * v) = B * zc;
  }
  return u;
}

Eigen::Matrix3d DofMap::curvature(const Eigen::VectorXd& x, const Eigen::VectorXd& G) const {
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  if (!core_) return c;
  const Frame f = frame(x);
  for (int v : core_->attached) {
    const Eigen::Vector3d gi = G.segment<3>(3 * v);
    const Eigen::Vector3d b = lever(f, v);
    c += 0.5 * (gi * b.transpose() + b * gi.transpose()) - gi.dot(b) * Eigen::Matrix3d::Identity();
  }
  return c;
}

void DofMap::set_committed(const Committed& c) {
  if (!c.rotation.allFinite() || !c.omega.allFinite() ||
      (c.rotation.transpose() * c.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9) {
    throw Error(ErrorKind::Input, "a committed core pose must be a finite rotation and rotation vector");
  }
  committed_ = c;
}

void DofMap::commit(const Eigen::VectorXd& x) {
  if (!core_) return;
  committed_ = {core_rotation(x), core_omega(x)};
}

}  // namespace palpa
