// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/axisym/element.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <functional>

#include "palpa/core/error.hpp"
#include "palpa/material/kinematics.hpp"

namespace palpa::axisym {

std::string_view to_string(ElementFormulation f) noexcept {
  return f == ElementFormulation::FBar ? "fbar" : "standard";
}

ElementFormulation parse_element_formulation(std::string_view name) {
  if (name == "fbar") return ElementFormulation::FBar;
  if (name == "standard") return ElementFormulation::Standard;
  throw_input_error(fmt::format("unknown element '{}'", name), ErrorContext{"", 0, 0, "option --element"},
                    "fbar or standard");
}

namespace {

using material::Mat2;
using Vec5 = Eigen::Matrix<double, 5, 1>;

constexpr double kGp = 0.77459666924148337704;  // sqrt(3/5)
constexpr std::array<double, 3> kPoints = {-kGp, 0.0, kGp};
constexpr std::array<double, 3> kWeights = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
constexpr double kTwoPi = 6.28318530717958647693;

Vec5 rest_x() {
  Vec5 x;
  x << 1.0, 0.0, 0.0, 1.0, 1.0;
  return x;
}

Mat2 in_plane(const Vec5& x) { return (Mat2() << x[0], x[2], x[1], x[3]).finished(); }

}  // namespace


QuadGeometry quad_geometry(const Eigen::Matrix<double, 2, 4>& rest) {
  QuadGeometry g;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      const int k = 3 * a + b;
      const double xi = kPoints[static_cast<std::size_t>(a)];
      const double eta = kPoints[static_cast<std::size_t>(b)];
      const Eigen::Vector4d n(0.25 * (1 - xi) * (1 - eta), 0.25 * (1 + xi) * (1 - eta),
                              0.25 * (1 + xi) * (1 + eta), 0.25 * (1 - xi) * (1 + eta));
      Eigen::Matrix<double, 4, 2> dn;
      dn << -0.25 * (1 - eta), -0.25 * (1 - xi), 0.25 * (1 - eta), -0.25 * (1 + xi),
          0.25 * (1 + eta), 0.25 * (1 + xi), -0.25 * (1 + eta), 0.25 * (1 - xi);
      const Mat2 jac = rest * dn;  // ∂(r, z)/∂(ξ, η)
      const double det = jac.determinant();
      const double r = rest.row(0).dot(n);
      if (!(det > 0.0) || !(r > 0.0)) {
        throw Error(ErrorKind::Internal, "degenerate or inverted axisymmetric cell in the mesh");
      }
      const Eigen::Matrix<double, 4, 2> dndx = dn * jac.inverse();  // ∂N/∂(r, z)
      BMatrix& bm = g.b[static_cast<std::size_t>(k)];
      bm.setZero();
      for (int node = 0; node < 4; ++node) {
        bm(0, 2 * node) = dndx(node, 0);      // F_rr ← u_r
        bm(1, 2 * node + 1) = dndx(node, 0);  // F_zr ← u_z
        bm(2, 2 * node) = dndx(node, 1);      // F_rz ← u_r
        bm(3, 2 * node + 1) = dndx(node, 1);  // F_zz ← u_z
        bm(4, 2 * node) = n[node] / r;        // F_θθ ← u_r / r
      }
      g.weight[static_cast<std::size_t>(k)] =
          kTwoPi * r * kWeights[static_cast<std::size_t>(a)] * kWeights[static_cast<std::size_t>(b)] * det;
      g.radius[static_cast<std::size_t>(k)] = r;
    }
  }
  return g;
}

Eigen::Matrix<double, 5, 1> gauss_point_gradient(const QuadGeometry& g, int k, const Vec8& u) {
  return rest_x() + g.b[static_cast<std::size_t>(k)] * u;
}

namespace {

using Mat5 = Eigen::Matrix<double, 5, 5>;

double jacobian_of(const Vec5& x) { return (x[0] * x[3] - x[2] * x[1]) * x[4]; }

// ∂J/∂x and ∂²J/∂x² for J = (F_rr F_zz − F_rz F_zr) F_θθ.
Vec5 djacobian(const Vec5& x) {
  Vec5 d;
  d << x[3] * x[4], -x[2] * x[4], -x[1] * x[4], x[0] * x[4], x[0] * x[3] - x[2] * x[1];
  return d;
}

Mat5 d2jacobian(const Vec5& x) {
  Mat5 h = Mat5::Zero();
  h(0, 3) = h(3, 0) = x[4];
  h(1, 2) = h(2, 1) = -x[4];
  h(0, 4) = h(4, 0) = x[3];
  h(3, 4) = h(4, 3) = x[0];
  h(1, 4) = h(4, 1) = -x[2];
  h(2, 4) = h(4, 2) = -x[1];
  return h;
}

// Per Gauss point: the F-bar scaling s = (J̄/J)^(1/3) of x and its first
// derivative in u, through q = ln s = (ln J̄ − ln J)/3, J̄ = Σ w_p J_p / W.
// The second derivative ∇²q_p = (A − B_p)/3, A = ∇²J̄/J̄ − ∇J̄∇J̄ᵀ/J̄²,
// B_p = ∇²J_p/J_p − ∇J_p∇J_pᵀ/J_p², enters the element Hessian only as
// Σ_p c_p ∇²q_p for scalars c_p known after the stresses, so it is never
// formed per point (add_weighted_d2q).
struct FBarKinematics {
  std::array<Vec5, kGaussPoints> x;
  std::array<double, kGaussPoints> jac;
  std::array<double, kGaussPoints> s;
  std::array<Vec8, kGaussPoints> dj;  // ∇J_p
  std::array<Vec8, kGaussPoints> dq;
  double total_weight = 0.0;
  double jbar = 0.0;
  Vec8 djbar;
};

// Returns false for an inverted or degenerate Gauss point.
bool fbar_kinematics(const QuadGeometry& g, const Vec8& u, bool first, FBarKinematics& k) {
  k.total_weight = 0.0;
  k.jbar = 0.0;
  k.djbar.setZero();
  for (int p = 0; p < kGaussPoints; ++p) {
    const auto pp = static_cast<std::size_t>(p);
    k.x[pp] = rest_x() + g.b[pp] * u;
    const Vec5& x = k.x[pp];
    if (!(x[0] * x[3] - x[2] * x[1] > 0.0) || !(x[4] > 0.0)) return false;
    k.jac[pp] = jacobian_of(x);
    k.total_weight += g.weight[pp];
    k.jbar += g.weight[pp] * k.jac[pp];
    if (first) {
      k.dj[pp].noalias() = g.b[pp].transpose() * djacobian(x);
      k.djbar += g.weight[pp] * k.dj[pp];
    }
  }
  k.jbar /= k.total_weight;
  k.djbar /= k.total_weight;
  for (int p = 0; p < kGaussPoints; ++p) {
    const auto pp = static_cast<std::size_t>(p);
    k.s[pp] = std::cbrt(k.jbar / k.jac[pp]);
    if (first) k.dq[pp] = (k.djbar / k.jbar - k.dj[pp] / k.jac[pp]) / 3.0;
  }
  return true;
}

// H += Σ_p c_p ∇²q_p (see FBarKinematics):
// 3 Σ c_p ∇²q_p = Σ_p α_p ∇²J_p − (C/J̄²) ∇J̄∇J̄ᵀ + Σ_p (c_p/J_p²) ∇J_p∇J_pᵀ,
// C = Σ c_p, α_p = C w_p/(W J̄) − c_p/J_p, ∇²J_p = B_pᵀ ∇²J(x_p) B_p.
void add_weighted_d2q(const QuadGeometry& g, const FBarKinematics& k,
                      const std::array<double, kGaussPoints>& c, Mat8& h) {
  double csum = 0.0;
  for (double v : c) csum += v;
  Mat8 acc = (-csum / (k.jbar * k.jbar)) * (k.djbar * k.djbar.transpose());
  for (int p = 0; p < kGaussPoints; ++p) {
    const auto pp = static_cast<std::size_t>(p);
    const double alpha = csum * g.weight[pp] / (k.total_weight * k.jbar) - c[pp] / k.jac[pp];
    const Eigen::Matrix<double, 5, 8> hb = d2jacobian(k.x[pp]) * g.b[pp];
    acc.noalias() += alpha * (g.b[pp].transpose() * hb);
    acc.noalias() += (c[pp] / (k.jac[pp] * k.jac[pp])) * (k.dj[pp] * k.dj[pp].transpose());
  }
  h += acc / 3.0;
}

bool evaluate_fbar(const material::Material& m, const QuadGeometry& g, const Vec8& u,
                   material::EvalOrder order, material::PsdProjection projection, double kstab,
                   ElementResult& out) {
  const bool first = order != material::EvalOrder::Energy;
  const bool second = order == material::EvalOrder::Hessian;
  FBarKinematics k;
  if (!fbar_kinematics(g, u, first, k)) return false;
  material::StressAxisym st;
  std::array<double, kGaussPoints> c{};  // the weights of ∇²q_p in the Hessian
  for (int p = 0; p < kGaussPoints; ++p) {
    const auto pp = static_cast<std::size_t>(p);
    if (kstab > 0.0) {
      // ln J_k − ln J̄ = −3 q_k
      const double q = std::log(k.s[pp]);
      const double w9 = 9.0 * kstab * g.weight[pp];
      out.energy += 0.5 * w9 * q * q;
      if (first) out.gradient += w9 * q * k.dq[pp];
      if (second) {
        out.hessian.noalias() += w9 * (k.dq[pp] * k.dq[pp].transpose());
        c[pp] += w9 * q;
      }
    }
    const Vec5 xbar = k.s[pp] * k.x[pp];
    material::stress_axisymmetric(m, in_plane(xbar), xbar[4], order, projection, st);
    const double w = g.weight[pp];
    out.energy += w * st.psi;
    if (!first) continue;
    // ∂x̄/∂u = s (B + x ∇qᵀ)
    const BMatrix d = k.s[pp] * (g.b[pp] + k.x[pp] * k.dq[pp].transpose());
    out.gradient.noalias() += w * d.transpose() * st.P;
    if (!second) continue;
    // Σ_c P_c ∂²x̄_c = (P·x) ∇²s + ∇s (BᵀP)ᵀ + (BᵀP) ∇sᵀ, ∇s = s∇q, ∇²s = s (∇q∇qᵀ + ∇²q)
    const Vec8 btp = g.b[pp].transpose() * st.P;
    const double px = st.P.dot(k.x[pp]);
    const Vec8& dq = k.dq[pp];
    const Eigen::Matrix<double, 5, 8> pd = st.dPdF * d;
    out.hessian.noalias() += w * (d.transpose() * pd);
    out.hessian.noalias() += (w * k.s[pp]) * (px * (dq * dq.transpose()) + dq * btp.transpose() + btp * dq.transpose());
    c[pp] += w * k.s[pp] * px;
  }
  if (second) add_weighted_d2q(g, k, c, out.hessian);
  return std::isfinite(out.energy);
}

}  // namespace

bool element_evaluate(const material::Material& m, const QuadGeometry& g, const Vec8& u,
                      material::EvalOrder order, material::PsdProjection projection,
                      ElementResult& out, const ElementOptions& options) {
  out.energy = 0.0;
  if (order != material::EvalOrder::Energy) out.gradient.setZero();
  if (order == material::EvalOrder::Hessian) out.hessian.setZero();
  if (options.formulation == ElementFormulation::FBar) {
    return evaluate_fbar(m, g, u, order, projection, options.stabilization, out);
  }
  material::StressAxisym s;
  for (int k = 0; k < kGaussPoints; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    const Vec5 x = rest_x() + g.b[kk] * u;
    const double det2 = x[0] * x[3] - x[2] * x[1];
    if (!(det2 > 0.0) || !(x[4] > 0.0)) return false;
    material::stress_axisymmetric(m, in_plane(x), x[4], order, projection, s);
    const double w = g.weight[kk];
    out.energy += w * s.psi;
    if (order == material::EvalOrder::Energy) continue;
    out.gradient.noalias() += w * g.b[kk].transpose() * s.P;
    if (order == material::EvalOrder::Hessian) {
      out.hessian.noalias() += w * g.b[kk].transpose() * s.dPdF * g.b[kk];
    }
  }
  return std::isfinite(out.energy);
}

void element_dgradient_dparam(const material::Material& m, const QuadGeometry& g, const Vec8& u,
                              Eigen::Ref<Eigen::MatrixXd> work3, Eigen::Ref<Eigen::MatrixXd> work5,
                              Eigen::Ref<Eigen::MatrixXd> out, const ElementOptions& options) {
  out.setZero();
  FBarKinematics k;
  const bool fbar = options.formulation == ElementFormulation::FBar;
  if (fbar && !fbar_kinematics(g, u, true, k)) {
    throw Error(ErrorKind::Internal, "parameter derivative requested at an inverted element");
  }
  for (int p = 0; p < kGaussPoints; ++p) {
    const auto pp = static_cast<std::size_t>(p);
    Vec5 x = rest_x() + g.b[pp] * u;
    BMatrix d = g.b[pp];
    if (fbar) {
      x *= k.s[pp];
      d = k.s[pp] * (g.b[pp] + k.x[pp] * k.dq[pp].transpose());
    }
    material::dP_dparam_axisymmetric(m, in_plane(x), x[4], work3, work5);
    // (coefficient-based: a blocked product is slower for an 8×5 by 5×p)
    out.noalias() += g.weight[pp] * d.transpose().lazyProduct(work5);
  }
}

ElementState element_state(const material::Material& m, const QuadGeometry& g, const Vec8& u,
                           const ElementOptions& options) {
  ElementState out;
  out.stretches.setZero();
  out.jacobian = 0.0;
  FBarKinematics k;
  const bool fbar = options.formulation == ElementFormulation::FBar && fbar_kinematics(g, u, false, k);
  double total = 0.0;
  material::StressAxisym st;
  for (int p = 0; p < kGaussPoints; ++p) {
    const auto pp = static_cast<std::size_t>(p);
    const Vec5 x0 = rest_x() + g.b[pp] * u;
    const Vec5 x = fbar ? Vec5(k.s[pp] * x0) : x0;
    const material::Svd2 svd = material::signed_svd(in_plane(x));
    Eigen::Vector3d l(svd.sigma[0], svd.sigma[1], x[4]);
    std::sort(l.data(), l.data() + 3, std::greater<>());
    material::stress_axisymmetric(m, in_plane(x), x[4], material::EvalOrder::Gradient,
                                  material::PsdProjection::None, st);
    // σ = P Fᵀ / J on the (r, z) block and the hoop entry.
    const Mat2 f2 = in_plane(x);
    const Mat2 p2 = in_plane(st.P);
    const double j = f2.determinant() * x[4];
    const Mat2 sigma = p2 * f2.transpose() / j;
    const double w = g.weight[pp];
    total += w;
    out.stretches += w * l;
    out.jacobian += w * jacobian_of(x0);
    out.cauchy += w * Eigen::Vector4d(sigma(0, 0), sigma(1, 1), sigma(0, 1), st.P[4] * x[4] / j);
  }
  out.stretches /= total;
  out.jacobian /= total;
  out.cauchy /= total;
  return out;
}

double element_min_jacobian(const QuadGeometry& g, const Vec8& u) {
  double lowest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < kGaussPoints; ++k) {
    const Vec5 x = rest_x() + g.b[static_cast<std::size_t>(k)] * u;
    lowest = std::min(lowest, (x[0] * x[3] - x[2] * x[1]) * x[4]);
  }
  return lowest;
}

}  // namespace palpa::axisym
