#include "palpa/axisym/element.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <functional>

#include "palpa/core/error.hpp"
#include "palpa/material/kinematics.hpp"

namespace palpa::axisym {

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

// Per Gauss point: the F-bar scaling s = (J̄/J)^(1/3) of x and its first and
// second derivatives in u, through q = ln s = (ln J̄ − ln J)/3.
struct FBarKinematics {
  std::array<Vec5, kGaussPoints> x;
  std::array<double, kGaussPoints> s;
  std::array<Vec8, kGaussPoints> dq;
  std::array<Mat8, kGaussPoints> d2q;
};

// Returns false for an inverted or degenerate Gauss point.
bool fbar_kinematics(const QuadGeometry& g, const Vec8& u, bool first, bool second,
                     FBarKinematics& k) {
  std::array<double, kGaussPoints> jac{};
  std::array<Vec8, kGaussPoints> dj{};
  std::array<Mat8, kGaussPoints> d2j{};
  double total_weight = 0.0;
  double jbar = 0.0;
  Vec8 djbar = Vec8::Zero();
  Mat8 d2jbar = Mat8::Zero();
  for (int p = 0; p < kGaussPoints; ++p) {
    const auto pp = static_cast<std::size_t>(p);
    k.x[pp] = rest_x() + g.b[pp] * u;
    const Vec5& x = k.x[pp];
    if (!(x[0] * x[3] - x[2] * x[1] > 0.0) || !(x[4] > 0.0)) return false;
    jac[pp] = jacobian_of(x);
    total_weight += g.weight[pp];
    jbar += g.weight[pp] * jac[pp];
    if (first) {
      dj[pp] = g.b[pp].transpose() * djacobian(x);
      djbar += g.weight[pp] * dj[pp];
    }
    if (second) {
      d2j[pp] = g.b[pp].transpose() * d2jacobian(x) * g.b[pp];
      d2jbar += g.weight[pp] * d2j[pp];
    }
  }
  jbar /= total_weight;
  djbar /= total_weight;
  d2jbar /= total_weight;
  for (int p = 0; p < kGaussPoints; ++p) {
    const auto pp = static_cast<std::size_t>(p);
    k.s[pp] = std::cbrt(jbar / jac[pp]);
    if (first) k.dq[pp] = (djbar / jbar - dj[pp] / jac[pp]) / 3.0;
    if (second) {
      k.d2q[pp] = ((d2jbar / jbar - djbar * djbar.transpose() / (jbar * jbar)) -
                   (d2j[pp] / jac[pp] - dj[pp] * dj[pp].transpose() / (jac[pp] * jac[pp]))) /
                  3.0;
    }
  }
  return true;
}

bool evaluate_fbar(const material::Material& m, const QuadGeometry& g, const Vec8& u,
                   material::EvalOrder order, material::PsdProjection projection, double kstab,
                   ElementResult& out) {
  const bool first = order != material::EvalOrder::Energy;
  const bool second = order == material::EvalOrder::Hessian;
  FBarKinematics k;
  if (!fbar_kinematics(g, u, first, second, k)) return false;
  material::StressAxisym st;
  for (int p = 0; p < kGaussPoints; ++p) {
    const auto pp = static_cast<std::size_t>(p);
    if (kstab > 0.0) {
      // ln J_k − ln J̄ = −3 q_k
      const double q = std::log(k.s[pp]);
      const double w9 = 9.0 * kstab * g.weight[pp];
      out.energy += 0.5 * w9 * q * q;
      if (first) out.gradient += w9 * q * k.dq[pp];
      if (second) out.hessian += w9 * (k.dq[pp] * k.dq[pp].transpose() + q * k.d2q[pp]);
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
    out.hessian.noalias() += w * (d.transpose() * st.dPdF * d);
    out.hessian.noalias() +=
        (w * k.s[pp]) * (px * (dq * dq.transpose() + k.d2q[pp]) + dq * btp.transpose() + btp * dq.transpose());
  }
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
  if (fbar && !fbar_kinematics(g, u, true, false, k)) {
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
    out.noalias() += g.weight[pp] * d.transpose() * work5;
  }
}

ElementState element_state(const material::Material& m, const QuadGeometry& g, const Vec8& u,
                           const ElementOptions& options) {
  ElementState out;
  out.stretches.setZero();
  out.jacobian = 0.0;
  FBarKinematics k;
  const bool fbar = options.formulation == ElementFormulation::FBar && fbar_kinematics(g, u, false, false, k);
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
