// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/tet/nodal_pressure.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "palpa/solve/so3.hpp"

namespace palpa::tet {

namespace {

constexpr std::size_t kNodalGrain = 128;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// H with its negative eigenvalues set to zero (Clamp) or flipped (Abs).
Mat12 projected(const Mat12& H, PsdProjection projection) {
  const Eigen::SelfAdjointEigenSolver<Mat12> eig(H);
  Vec12 d = eig.eigenvalues();
  for (int i = 0; i < 12; ++i) d[i] = projection == PsdProjection::Abs ? std::abs(d[i]) : std::max(d[i], 0.0);
  return eig.eigenvectors() * d.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace

Dilatation dilatation(const material::Material& m, double J) {
  const double s = std::cbrt(J);
  material::StretchEnergy w;
  m.evaluate(material::Vec3::Constant(s), material::EvalOrder::Hessian, w);
  const double sum_g = w.grad.sum();
  Dilatation d;
  d.u = w.psi;
  d.du = sum_g / (3.0 * s * s);
  d.d2u = (w.hess.sum() - 2.0 * sum_g / s) / (9.0 * s * s * s * s);
  return d;
}

double tet_volume(const Mat34& x, Vec12* gradient, Mat12* hessian) {
  const Eigen::Vector3d d1 = x.col(1) - x.col(0), d2 = x.col(2) - x.col(0), d3 = x.col(3) - x.col(0);
  const Eigen::Vector3d c1 = d2.cross(d3);
  const double v = d1.dot(c1) / 6.0;
  if (gradient != nullptr) {
    const Eigen::Vector3d g1 = c1 / 6.0, g2 = d3.cross(d1) / 6.0, g3 = d1.cross(d2) / 6.0;
    gradient->segment<3>(0) = -(g1 + g2 + g3);
    gradient->segment<3>(3) = g1;
    gradient->segment<3>(6) = g2;
    gradient->segment<3>(9) = g3;
  }
  if (hessian != nullptr) {
    // Blocks over (d1, d2, d3): ∂²v/∂d1∂d2 = −[d3]×/6, ∂²v/∂d1∂d3 = [d2]×/6,
    // ∂²v/∂d2∂d3 = −[d1]×/6, zero on the diagonal; then x0 = −Σ d.
    Eigen::Matrix<double, 9, 9> hd = Eigen::Matrix<double, 9, 9>::Zero();
    hd.block<3, 3>(0, 3) = -hat(d3) / 6.0;
    hd.block<3, 3>(0, 6) = hat(d2) / 6.0;
    hd.block<3, 3>(3, 6) = -hat(d1) / 6.0;
    hd.block<3, 3>(3, 0) = hd.block<3, 3>(0, 3).transpose();
    hd.block<3, 3>(6, 0) = hd.block<3, 3>(0, 6).transpose();
    hd.block<3, 3>(6, 3) = hd.block<3, 3>(3, 6).transpose();
    Eigen::Matrix<double, 12, 9> T = Eigen::Matrix<double, 12, 9>::Zero();
    for (int i = 0; i < 3; ++i) {
      T.block<3, 3>(0, 3 * i) = -Eigen::Matrix3d::Identity();
      T.block<3, 3>(3 * (i + 1), 3 * i) = Eigen::Matrix3d::Identity();
    }
    *hessian = T * hd * T.transpose();
  }
  return v;
}

// ---------------------------------------------------------------- deviatoric

bool DeviatoricTerm::element(const VertexState& s, Eigen::Index e, double& energy, Vec12* gradient) const {
  const Mat34 x = model_->element_positions(s.u, e);
  TetResult r;
  if (!tet_evaluate(model_->material_of(e), model_->geometry(e), x,
                    gradient != nullptr ? material::EvalOrder::Gradient : material::EvalOrder::Energy,
                    PsdProjection::None, r)) {
    return false;
  }
  const double V = model_->geometry(e).volume;
  Vec12 dv;
  const double J = tet_volume(x, gradient != nullptr ? &dv : nullptr) / V;
  const Dilatation d = dilatation(model_->material_of(e), J);
  energy = r.energy - nodal_share_ * V * d.u;
  if (gradient != nullptr) *gradient = r.gradient - (nodal_share_ * d.du) * dv;
  return std::isfinite(energy);
}

double DeviatoricTerm::energy(const VertexState& s) const {
  const auto n = static_cast<std::size_t>(model_->num_elements());
  std::vector<double> energies(n);
  std::atomic<bool> admissible{true};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kNodalGrain), [&](const auto& range) {
    for (std::size_t e = range.begin(); e != range.end(); ++e) {
      if (!element(s, static_cast<Eigen::Index>(e), energies[e], nullptr)) admissible = false;
    }
  });
  if (!admissible) return kInfinity;
  double total = 0.0;
  for (double v : energies) total += v;
  return total;
}

double DeviatoricTerm::add_gradient(const VertexState& s, Eigen::VectorXd& g) const {
  const auto n = static_cast<std::size_t>(model_->num_elements());
  std::vector<double> energies(n);
  std::vector<Vec12> local(n);
  std::atomic<bool> admissible{true};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kNodalGrain), [&](const auto& range) {
    for (std::size_t e = range.begin(); e != range.end(); ++e) {
      if (!element(s, static_cast<Eigen::Index>(e), energies[e], &local[e])) admissible = false;
    }
  });
  if (!admissible) return kInfinity;
  double total = 0.0;
  const TetMesh& mesh = model_->mesh();
  for (std::size_t e = 0; e < n; ++e) {
    total += energies[e];
    for (int a = 0; a < 4; ++a) g.segment<3>(3 * mesh.T(static_cast<Eigen::Index>(e), a)) += local[e].segment<3>(3 * a);
  }
  return total;
}

bool DeviatoricTerm::stencil_hessian(const VertexState& s, Eigen::Index e, PsdProjection projection,
                                     double* h) const {
  const Mat34 x = model_->element_positions(s.u, e);
  TetResult r;
  if (!tet_evaluate(model_->material_of(e), model_->geometry(e), x, material::EvalOrder::Hessian,
                    PsdProjection::None, r)) {
    return false;
  }
  const double V = model_->geometry(e).volume;
  Vec12 dv;
  Mat12 hv;
  const double J = tet_volume(x, &dv, &hv) / V;
  const Dilatation d = dilatation(model_->material_of(e), J);
  Mat12 H = r.hessian - (nodal_share_ * d.d2u / V) * (dv * dv.transpose()) - (nodal_share_ * d.du) * hv;
  if (projection != PsdProjection::None) H = projected(H, projection);
  Eigen::Map<Mat12> out(h);
  out = H;
  return true;
}

// ---------------------------------------------------------------- nodal

NodalVolumeTerm::NodalVolumeTerm(const ElasticModel& model) : model_(&model) {
  const TetMesh& mesh = model.mesh();
  const Eigen::Index nv = model.num_vertices(), nt = model.num_elements();
  std::vector<int> count(static_cast<std::size_t>(nv) + 1, 0);
  for (Eigen::Index e = 0; e < nt; ++e) {
    for (int a = 0; a < 4; ++a) ++count[static_cast<std::size_t>(mesh.T(e, a)) + 1];
  }
  tet_start_.assign(count.begin(), count.end());
  for (std::size_t v = 0; v < static_cast<std::size_t>(nv); ++v) tet_start_[v + 1] += tet_start_[v];
  tets_.resize(static_cast<std::size_t>(tet_start_.back()));
  std::vector<int> fill(tet_start_.begin(), tet_start_.end() - 1);
  for (Eigen::Index e = 0; e < nt; ++e) {
    for (int a = 0; a < 4; ++a) tets_[static_cast<std::size_t>(fill[static_cast<std::size_t>(mesh.T(e, a))]++)] = static_cast<int>(e);
  }
  rest_ = Eigen::VectorXd::Zero(nv);
  patch_start_.assign(1, 0);
  share_start_.assign(1, 0);
  for (Eigen::Index v = 0; v < nv; ++v) {
    const auto vs = static_cast<std::size_t>(v);
    std::vector<int> patch;
    std::vector<std::pair<int, double>> shares;
    for (int k = tet_start_[vs]; k < tet_start_[vs + 1]; ++k) {
      const int e = tets_[static_cast<std::size_t>(k)];
      for (int a = 0; a < 4; ++a) patch.push_back(mesh.T(e, a));
      const double quarter = model.geometry(e).volume / 4.0;
      rest_[v] += quarter;
      const double share = (1.0 - model.stabilization()) * quarter;
      const int mat = model.element_material()[e];
      auto it = std::find_if(shares.begin(), shares.end(), [&](const auto& p) { return p.first == mat; });
      if (it == shares.end()) {
        shares.emplace_back(mat, share);
      } else {
        it->second += share;
      }
    }
    std::sort(patch.begin(), patch.end());
    patch.erase(std::unique(patch.begin(), patch.end()), patch.end());
    for (int k = tet_start_[vs]; k < tet_start_[vs + 1]; ++k) {
      const int e = tets_[static_cast<std::size_t>(k)];
      for (int a = 0; a < 4; ++a) {
        corner_local_.push_back(static_cast<int>(std::lower_bound(patch.begin(), patch.end(), mesh.T(e, a)) - patch.begin()));
      }
    }
    patch_.insert(patch_.end(), patch.begin(), patch.end());
    patch_start_.push_back(static_cast<int>(patch_.size()));
    max_patch_ = std::max(max_patch_, static_cast<int>(patch.size()));
    for (const auto& [mat, w] : shares) {
      share_material_.push_back(mat);
      share_weight_.push_back(w);
    }
    share_start_.push_back(static_cast<int>(share_material_.size()));
  }
}

Dilatation NodalVolumeTerm::nodal(Eigen::Index a, double J) const {
  Dilatation w;
  const auto as = static_cast<std::size_t>(a);
  for (int k = share_start_[as]; k < share_start_[as + 1]; ++k) {
    const auto ks = static_cast<std::size_t>(k);
    const Dilatation d = dilatation(*model_->materials()[static_cast<std::size_t>(share_material_[ks])].material, J);
    w.u += share_weight_[ks] * d.u;
    w.du += share_weight_[ks] * d.du;
    w.d2u += share_weight_[ks] * d.d2u;
  }
  return w;
}

bool NodalVolumeTerm::volumes(const Eigen::VectorXd& u, std::vector<double>& v, std::vector<Vec12>* gradients) const {
  const auto n = static_cast<std::size_t>(model_->num_elements());
  v.resize(n);
  if (gradients != nullptr) gradients->resize(n);
  std::atomic<bool> admissible{true};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kNodalGrain), [&](const auto& range) {
    for (std::size_t e = range.begin(); e != range.end(); ++e) {
      v[e] = tet_volume(model_->element_positions(u, static_cast<Eigen::Index>(e)),
                        gradients != nullptr ? &(*gradients)[e] : nullptr);
      if (!(v[e] > 0.0) || !std::isfinite(v[e])) admissible = false;
    }
  });
  return admissible;
}

Eigen::VectorXd NodalVolumeTerm::nodal_jacobians(const Eigen::VectorXd& u) const {
  std::vector<double> v;
  volumes(u, v);
  return jacobians(v);
}

Eigen::VectorXd NodalVolumeTerm::jacobians(const std::vector<double>& v) const {
  Eigen::VectorXd J = Eigen::VectorXd::Ones(model_->num_vertices());
  for (Eigen::Index a = 0; a < J.size(); ++a) {
    if (!(rest_[a] > 0.0)) continue;
    double current = 0.0;
    for (int k = tet_start_[static_cast<std::size_t>(a)]; k < tet_start_[static_cast<std::size_t>(a) + 1]; ++k) {
      current += v[static_cast<std::size_t>(tets_[static_cast<std::size_t>(k)])] / 4.0;
    }
    J[a] = current / rest_[a];
  }
  return J;
}

double NodalVolumeTerm::energy(const VertexState& s) const {
  std::vector<double> v;
  if (!volumes(s.u, v)) return kInfinity;
  const Eigen::VectorXd J = jacobians(v);
  std::vector<double> energies(static_cast<std::size_t>(J.size()), 0.0);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, J.size(), kNodalGrain), [&](const auto& range) {
    for (Eigen::Index a = range.begin(); a != range.end(); ++a) {
      if (rest_[a] > 0.0) energies[static_cast<std::size_t>(a)] = nodal(a, J[a]).u;
    }
  });
  double total = 0.0;
  for (double e : energies) total += e;
  return total;
}

double NodalVolumeTerm::add_gradient(const VertexState& s, Eigen::VectorXd& g) const {
  std::vector<double> v;
  std::vector<Vec12> dv;
  if (!volumes(s.u, v, &dv)) return kInfinity;
  const Eigen::VectorXd J = jacobians(v);
  const Eigen::Index nv = J.size();
  std::vector<double> energies(static_cast<std::size_t>(nv), 0.0);
  std::vector<double> slope(static_cast<std::size_t>(nv), 0.0);  // W_a'/(4 V̂_a)
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, nv, kNodalGrain), [&](const auto& range) {
    for (Eigen::Index a = range.begin(); a != range.end(); ++a) {
      if (!(rest_[a] > 0.0)) continue;
      const Dilatation w = nodal(a, J[a]);
      energies[static_cast<std::size_t>(a)] = w.u;
      slope[static_cast<std::size_t>(a)] = w.du / (4.0 * rest_[a]);
    }
  });
  // ∂E/∂x = Σ_e (Σ_{a∈e} W_a'/(4V̂_a)) ∂v_e.
  const TetMesh& mesh = model_->mesh();
  double total = 0.0;
  for (double e : energies) total += e;
  for (std::size_t e = 0; e < dv.size(); ++e) {
    const auto ei = static_cast<Eigen::Index>(e);
    double c = 0.0;
    for (int a = 0; a < 4; ++a) c += slope[static_cast<std::size_t>(mesh.T(ei, a))];
    for (int a = 0; a < 4; ++a) g.segment<3>(3 * mesh.T(ei, a)) += c * dv[e].segment<3>(3 * a);
  }
  return total;
}

int NodalVolumeTerm::stencil(Eigen::Index a, int* vertices) const {
  const auto as = static_cast<std::size_t>(a);
  const int n = patch_start_[as + 1] - patch_start_[as];
  std::copy(patch_.begin() + patch_start_[as], patch_.begin() + patch_start_[as + 1], vertices);
  return n;
}

bool NodalVolumeTerm::stencil_hessian(const VertexState& s, Eigen::Index a, PsdProjection projection,
                                      double* h) const {
  const auto as = static_cast<std::size_t>(a);
  const int n = patch_start_[as + 1] - patch_start_[as];
  Eigen::Map<Eigen::MatrixXd> H(h, 3 * n, 3 * n);
  H.setZero();
  if (!(rest_[a] > 0.0)) return true;
  const double scale = 1.0 / (4.0 * rest_[a]);
  // J_a, and ∂J_a over the patch.
  Eigen::VectorXd dJ = Eigen::VectorXd::Zero(3 * n);
  double current = 0.0;
  for (int k = tet_start_[as]; k < tet_start_[as + 1]; ++k) {
    Vec12 dv;
    const double v = tet_volume(model_->element_positions(s.u, tets_[static_cast<std::size_t>(k)]), &dv);
    if (!(v > 0.0)) return false;
    current += v / 4.0;
    const int* local = corner_local_.data() + 4 * k;
    for (int c = 0; c < 4; ++c) dJ.segment<3>(3 * local[c]) += scale * dv.segment<3>(3 * c);
  }
  const Dilatation w = nodal(a, current / rest_[a]);
  if (projection == PsdProjection::None) {
    for (int k = tet_start_[as]; k < tet_start_[as + 1]; ++k) {
      Vec12 dv;
      Mat12 hv;
      tet_volume(model_->element_positions(s.u, tets_[static_cast<std::size_t>(k)]), &dv, &hv);
      const int* local = corner_local_.data() + 4 * k;
      for (int c = 0; c < 4; ++c) {
        for (int d = 0; d < 4; ++d) H.block<3, 3>(3 * local[c], 3 * local[d]) += (w.du * scale) * hv.block<3, 3>(3 * c, 3 * d);
      }
    }
    H.noalias() += w.d2u * dJ * dJ.transpose();
  } else {
    H.noalias() += std::max(w.d2u, 0.0) * dJ * dJ.transpose();
  }
  return true;
}

}  // namespace palpa::tet
