// SPDX-License-Identifier: AGPL-3.0-or-later
#include "solve/spring_network.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace palpa::test {

namespace {

// Per-spring kernel: energy, force on end a (= −∂E/∂p_a) and the 2×2 block B
// of the Hessian (the 4×4 block is [B −B; −B B]).
struct SpringState {
  double energy;
  Eigen::Vector2d dE_dpa;  // ∂E/∂p_a [N]
  double length;
  Eigen::Vector2d direction;  // (p_a − p_b)/l
};

SpringState evaluate(const Spring& s, const Eigen::Vector2d& pa, const Eigen::Vector2d& pb) {
  const Eigen::Vector2d d = pa - pb;
  const double l = d.norm();
  const Eigen::Vector2d u = d / l;
  const double stretch = l - s.rest_length;
  return SpringState{0.5 * s.stiffness * stretch * stretch, s.stiffness * stretch * u, l, u};
}

Eigen::Matrix2d hessian_block(const Spring& s, const SpringState& st) {
  const Eigen::Matrix2d uu = st.direction * st.direction.transpose();
  return s.stiffness *
         (uu + (1.0 - s.rest_length / st.length) * (Eigen::Matrix2d::Identity() - uu));
}

int value_index(const Eigen::SparseMatrix<double>& H, int row, int col) {
  const int* begin = H.innerIndexPtr() + H.outerIndexPtr()[col];
  const int* end = H.innerIndexPtr() + H.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(begin, end, row);
  return (it != end && *it == row) ? static_cast<int>(it - H.innerIndexPtr()) : -1;
}

bool same_structure(const Eigen::SparseMatrix<double>& A, const Eigen::SparseMatrix<double>& B) {
  return A.rows() == B.rows() && A.cols() == B.cols() && A.isCompressed() &&
         A.nonZeros() == B.nonZeros() &&
         std::equal(A.outerIndexPtr(), A.outerIndexPtr() + A.cols() + 1, B.outerIndexPtr()) &&
         std::equal(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros(), B.innerIndexPtr());
}

}  // namespace

SpringNetwork::SpringNetwork(Eigen::MatrixX2d nodes, std::vector<Spring> springs,
                             const std::vector<int>& pinned)
    : nodes_(std::move(nodes)), springs_(std::move(springs)) {
  const auto count = static_cast<std::size_t>(nodes_.rows());
  std::vector<bool> is_pinned(count, false);
  for (int p : pinned) is_pinned[static_cast<std::size_t>(p)] = true;
  dof_.assign(count, -1);
  int next = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (!is_pinned[i]) {
      dof_[i] = next;
      next += 2;
    }
  }
  num_dofs_ = next;
  force_ = Eigen::VectorXd::Zero(num_dofs_);

  std::vector<Eigen::Triplet<double>> t;
  for (const Spring& s : springs_) {
    const std::array<int, 4> dofs = spring_dofs(s);
    for (int r : dofs) {
      for (int c : dofs) {
        if (r >= 0 && c >= 0 && r >= c) t.emplace_back(r, c, 0.0);
      }
    }
  }
  pattern_.resize(num_dofs_, num_dofs_);
  pattern_.setFromTriplets(t.begin(), t.end());
  pattern_.makeCompressed();
  slots_.reserve(springs_.size());
  for (const Spring& s : springs_) {
    const std::array<int, 4> dofs = spring_dofs(s);
    std::array<int, 16> slot{};
    for (std::size_t r = 0; r < 4; ++r) {
      for (std::size_t c = 0; c < 4; ++c) {
        const int gr = dofs[r];
        const int gc = dofs[c];
        slot[4 * r + c] = (gr >= 0 && gc >= 0 && gr >= gc) ? value_index(pattern_, gr, gc) : -1;
      }
    }
    slots_.push_back(slot);
  }
}

SpringNetwork SpringNetwork::grid(int nx, int ny, double h, double k) {
  Eigen::MatrixX2d nodes(nx * ny, 2);
  auto id = [nx](int i, int j) { return i + nx * j; };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) nodes.row(id(i, j)) = Eigen::RowVector2d(i * h, j * h);
  }
  std::vector<Spring> springs;
  const double diagonal = h * std::sqrt(2.0);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (i + 1 < nx) springs.push_back(Spring{id(i, j), id(i + 1, j), h, k});
      if (j + 1 < ny) springs.push_back(Spring{id(i, j), id(i, j + 1), h, k});
      if (i + 1 < nx && j + 1 < ny) {
        springs.push_back(Spring{id(i, j), id(i + 1, j + 1), diagonal, k});
        springs.push_back(Spring{id(i + 1, j), id(i, j + 1), diagonal, k});
      }
    }
  }
  std::vector<int> pinned;
  for (int j = 0; j < ny; ++j) pinned.push_back(id(0, j));
  return SpringNetwork(std::move(nodes), std::move(springs), pinned);
}

SpringNetwork SpringNetwork::chain(const std::vector<double>& rest_lengths,
                                   const std::vector<double>& stiffnesses) {
  const int count = static_cast<int>(rest_lengths.size());
  Eigen::MatrixX2d nodes = Eigen::MatrixX2d::Zero(count + 1, 2);
  std::vector<Spring> springs;
  for (int i = 0; i < count; ++i) {
    const auto si = static_cast<std::size_t>(i);
    nodes(i + 1, 0) = nodes(i, 0) + rest_lengths[si];
    springs.push_back(Spring{i, i + 1, rest_lengths[si], stiffnesses[si]});
  }
  return SpringNetwork(std::move(nodes), std::move(springs), {0});
}

void SpringNetwork::set_force(int node, const Eigen::Vector2d& f) {
  const int d = dof_of(node);
  force_.segment<2>(d) = f;
}

void SpringNetwork::set_stiffness(int spring, double k) {
  springs_[static_cast<std::size_t>(spring)].stiffness = k;
}

Eigen::VectorXd SpringNetwork::reference_dofs() const {
  Eigen::VectorXd x(num_dofs_);
  for (int i = 0; i < num_nodes(); ++i) {
    const int d = dof_of(i);
    if (d >= 0) x.segment<2>(d) = nodes_.row(i).transpose();
  }
  return x;
}

Eigen::Vector2d SpringNetwork::node_position(const Eigen::VectorXd& x, int node) const {
  const int d = dof_of(node);
  return d >= 0 ? Eigen::Vector2d(x.segment<2>(d)) : Eigen::Vector2d(nodes_.row(node).transpose());
}

Eigen::MatrixX2d SpringNetwork::positions(const Eigen::VectorXd& x) const {
  Eigen::MatrixX2d p(nodes_.rows(), 2);
  for (int i = 0; i < num_nodes(); ++i) p.row(i) = node_position(x, i).transpose();
  return p;
}

std::array<int, 4> SpringNetwork::spring_dofs(const Spring& s) const {
  const int da = dof_of(s.a);
  const int db = dof_of(s.b);
  return {da, da < 0 ? -1 : da + 1, db, db < 0 ? -1 : db + 1};
}

double SpringNetwork::energy(const Eigen::VectorXd& x) const {
  double e = 0.0;
  for (const Spring& s : springs_)
    e += evaluate(s, node_position(x, s.a), node_position(x, s.b)).energy;
  return e - force_.dot(x);
}

double SpringNetwork::energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  g = -force_;
  double e = 0.0;
  for (const Spring& s : springs_) {
    const SpringState st = evaluate(s, node_position(x, s.a), node_position(x, s.b));
    e += st.energy;
    const int da = dof_of(s.a);
    const int db = dof_of(s.b);
    if (da >= 0) g.segment<2>(da) += st.dE_dpa;
    if (db >= 0) g.segment<2>(db) -= st.dE_dpa;
  }
  return e - force_.dot(x);
}

void SpringNetwork::gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  energy_gradient(x, g);
}

void SpringNetwork::hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const {
  if (!same_structure(H, pattern_)) H = pattern_;
  double* values = H.valuePtr();
  std::fill(values, values + H.nonZeros(), 0.0);
  for (std::size_t si = 0; si < springs_.size(); ++si) {
    const Spring& s = springs_[si];
    const SpringState st = evaluate(s, node_position(x, s.a), node_position(x, s.b));
    const Eigen::Matrix2d B = hessian_block(s, st);
    const std::array<int, 16>& slot = slots_[si];
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) {
        const int target = slot[static_cast<std::size_t>(4 * r + c)];
        if (target < 0) continue;
        const double sign = ((r < 2) == (c < 2)) ? 1.0 : -1.0;
        values[target] += sign * B(r % 2, c % 2);
      }
    }
  }
}

Eigen::Vector2d SpringNetwork::support_reaction(const Eigen::VectorXd& x) const {
  // The pin holding node a against the spring exerts ∂E_s/∂p_a on it.
  Eigen::Vector2d reaction = Eigen::Vector2d::Zero();
  for (const Spring& s : springs_) {
    const SpringState st = evaluate(s, node_position(x, s.a), node_position(x, s.b));
    if (dof_of(s.a) < 0) reaction += st.dE_dpa;
    if (dof_of(s.b) < 0) reaction -= st.dE_dpa;
  }
  return reaction;
}

void SpringNetwork::gradient_param_jacobian(const Eigen::VectorXd& x,
                                            Eigen::SparseMatrix<double>& J) const {
  std::vector<Eigen::Triplet<double>> t;
  for (std::size_t si = 0; si < springs_.size(); ++si) {
    const Spring& s = springs_[si];
    const SpringState st = evaluate(s, node_position(x, s.a), node_position(x, s.b));
    // ∂/∂k of k (l − L) u.
    const Eigen::Vector2d d = (st.length - s.rest_length) * st.direction;
    const int col = static_cast<int>(si);
    const int da = dof_of(s.a);
    const int db = dof_of(s.b);
    for (int c = 0; c < 2; ++c) {
      if (da >= 0) t.emplace_back(da + c, col, d[c]);
      if (db >= 0) t.emplace_back(db + c, col, -d[c]);
    }
  }
  J.resize(num_dofs_, static_cast<Eigen::Index>(springs_.size()));
  J.setFromTriplets(t.begin(), t.end());
}

}  // namespace palpa::test
