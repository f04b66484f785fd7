// SPDX-License-Identifier: AGPL-3.0-or-later
#include "axisym/layer_reference.hpp"

// Derivation
// ==========
// Layer equations. Cylindrical coordinates (r, z), z pointing into the layer from
// the top face z = 0 to the bonded face z = h; displacements u_r, u_z; shear
// modulus G, Poisson's ratio ν. Axisymmetric linear elasticity is solved with
// Love's strain function φ(r, z), ∇⁴φ = 0:
//   2G u_r = −∂²φ/∂r∂z,          2G u_z = 2(1−ν) ∇²φ − ∂²φ/∂z²,
//   σ_zz = ∂/∂z [(2−ν) ∇²φ − ∂²φ/∂z²],   σ_rz = ∂/∂r [(1−ν) ∇²φ − ∂²φ/∂z²].
// A Hankel transform in r (J0 for u_z, σ_zz; J1 for u_r, σ_rz) turns ∇² into
// d²/dz² − ξ², so for each ξ the transform of φ is
//   (A + B z) e^(ξz) + (C + D z) e^(−ξz).
//
// Boundary conditions:
//   z = h: u_r = u_z = 0                 (bonded to the rigid base)
//   z = 0: σ_rz = 0 for all r            (frictionless punch, free surface)
//   z = 0: u_z = w for r < a, σ_zz = 0 for r > a.
// With the contact pressure p(r) = −σ_zz(r, 0) and P̄(ξ) = ∫_0^∞ r p(r) J0(ξr) dr,
// the four conditions on A..D (three homogeneous, σ̄_zz(0) = −P̄) give the
// surface displacement
//   u_z(r, 0) = ((1−ν)/G) ∫_0^∞ P̄(ξ) L(ξh) J0(ξr) dξ,
//   L(s) = (2k sinh 2s − 4s) / (2k cosh 2s + k² + 1 + 4s²),   k = 3 − 4ν.
// Checks of L: L → 1 as s → ∞ is Boussinesq's half-space (a point load P gives
// u_z = (1−ν) P / (2π G r)); L ≈ (1−2ν) s / (2(1−ν)²) as s → 0 is confined
// compression, u_z = p h (1−2ν) / (2G(1−ν)); for ν = 1/2, L ≈ 2s³/3 is the
// squeeze flow of a thin incompressible layer, u_z = −(h³/3G) ∇²p. (L was also
// checked against a direct integration of the transformed Navier equations.)
//
// Kernel. M(s) = 1 − L(s) = (k² + (1+2s)² + 2k e^(−2s)) / (k² + 1 + 4s² + 2k cosh 2s):
// M(0) = 1, 0 < M ≤ 1 for ν ≤ 1/2, and M ~ (k² + (1+2s)²) e^(−2s) / k for large
// s. It is evaluated with numerator and denominator multiplied by e^(−2s): no
// overflow of cosh and no cancellation (computing 1 − L would lose every digit
// once L ≈ 1). The kernel of the integral equation is
//   K(t) = ∫_0^∞ M(u) cos(u t) du,
// smooth and even in t, K(0) = ∫_0^∞ M du finite; for large t it decays like
// −M'(0)/t² = (1−2ν) / (2(1−ν)² t²) (like −4/t⁴ for ν = 1/2, where M'(0) = 0).
//
// Reduction to a Fredholm equation (Copson/Sneddon). Write
//   P̄(ξ) = ∫_0^a g(t) cos(ξt) dt.
// Then p(r) = g(a)/√(a²−r²) − ∫_r^a g'(t)/√(t²−r²) dt for r < a and p = 0 for
// r > a, so the traction-free condition outside the punch holds identically, and
// the load is P = 2π P̄(0) = 2π ∫_0^a g dt. Since
//   ∫_0^∞ cos(ξt) J0(ξr) dξ = H(r−t)/√(r²−t²),  J0(ξr) = (2/π) ∫_0^r cos(ξs)/√(r²−s²) ds,
// the condition u_z = w for r < a reads
//   ∫_0^r [g(s) − (2/π) ∫_0^a g(t) ∫_0^∞ M(ξh) cos(ξs) cos(ξt) dξ dt] / √(r²−s²) ds
//     = G w / (1−ν),
// an Abel equation whose unique solution gives, with s = a x, t = a y, u = ξ h,
// λ = a/h and g(a x) = (2 G w / (π (1−ν))) Φ(x):
//   Φ(x) − (2λ/π) ∫_0^1 k(x, y) Φ(y) dy = 1,  0 ≤ x ≤ 1,
//   k(x, y) = ∫_0^∞ M(u) cos(λux) cos(λuy) du = [K(λ(x−y)) + K(λ(x+y))] / 2,
// i.e. Φ(x) − (λ/π) ∫_{−1}^{1} K(λ(x−y)) Φ(y) dy = 1 for the even extension of
// Φ (the form used by Hayes et al. 1972). The load becomes
//   P = 4 a G w / (1−ν) ∫_0^1 Φ dx,   so   κ = ∫_0^1 Φ(x) dx.
// Normalization: as h → ∞ (λ → 0) the integral term vanishes, Φ = 1 and κ = 1,
// Sneddon's P = 2 a E w / (1−ν²). Expanding in λ (K(λt) = K(0) + O(λ²)) gives
// κ = 1 + c λ + c² λ² + O(λ³) with c = (2/π) K(0) = (2/π) ∫_0^∞ M du.
//
// Numerical method. Nyström on the even extension: the 2n-point Gauss–Legendre
// rule on [−1, 1], folded onto its n positive nodes x_i with weights w_i:
//   Φ_i − (2λ/π) Σ_j w_j k(x_i, x_j) Φ_j = 1,   κ ≈ Σ_i w_i Φ_i.
// The transform integral k(x_i, x_j) is separable: with Q quadrature points u_q,
// weights ω_q in u, k ≈ Σ_q ω_q M(u_q) cos(λ u_q x_i) cos(λ u_q x_j), so the
// matrix is a product C diag(ω M) Cᵀ (C_iq = cos(λ u_q x_i)), built with n·Q
// cosines and one matrix product instead of n² separate kernel integrals. The u
// integral runs over [0, u_max] with composite Gauss–Legendre panels narrow
// enough to resolve both the oscillation (frequency up to 2λ) and M (its complex
// poles lie at least 0.74 from the real axis for ν ≤ 1/2); the tail
// beyond u_max = 25 is below 1e-17 and dropped. Symmetrized with D = diag(√w_i)
// the system matrix I − (2λ/π) D C diag(ωM) Cᵀ D is symmetric positive definite
// (its symbol is L ≥ 0), solved by LDLᵀ; κ = √wᵀ (that matrix)⁻¹ √w.
// Both quadratures converge exponentially; default_layer_quadrature() keeps the
// error below 1e-9 (see layer_reference_test.cpp).

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace palpa::test {
namespace {

struct GaussRule {
  std::vector<double> nodes;
  std::vector<double> weights;
};

// n-point Gauss–Legendre rule on [−1, 1] (Newton iteration on the three-term
// recurrence), nodes ascending.
GaussRule gauss_legendre(int n) {
  GaussRule rule;
  const auto count = static_cast<std::size_t>(n);
  rule.nodes.resize(count);
  rule.weights.resize(count);
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
    double derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p_current = 1.0;
      double p_previous = 0.0;
      for (int j = 1; j <= n; ++j) {
        const double p_older = p_previous;
        p_previous = p_current;
        p_current = ((2.0 * j - 1.0) * z * p_previous - (j - 1.0) * p_older) / j;
      }
      derivative = n * (z * p_current - p_previous) / (z * z - 1.0);
      const double step = p_current / derivative;
      z -= step;
      if (std::abs(step) < 1e-16) break;
    }
    const double weight = 2.0 / ((1.0 - z * z) * derivative * derivative);
    const auto low = static_cast<std::size_t>(i);
    const auto high = count - 1 - low;
    rule.nodes[low] = -z;
    rule.nodes[high] = z;
    rule.weights[low] = weight;
    rule.weights[high] = weight;
  }
  return rule;
}

void check_nu(double nu) {
  if (!(nu > -1.0 && nu <= 0.5)) {
    throw std::invalid_argument("layer reference: Poisson's ratio " + std::to_string(nu) +
                                " outside (-1, 0.5]");
  }
}

void check_a_over_h(double a_over_h) {
  if (!(a_over_h >= 0.0 && a_over_h <= kLayerMaxAOverH)) {
    throw std::invalid_argument("layer reference: a/h = " + std::to_string(a_over_h) +
                                " outside [0, " + std::to_string(kLayerMaxAOverH) + "]");
  }
}

}  // namespace

double layer_kernel_weight(double s, double nu) {
  check_nu(nu);
  const double k = 3.0 - 4.0 * nu;
  const double e = std::exp(-2.0 * s);
  const double numerator = (k * k + (1.0 + 2.0 * s) * (1.0 + 2.0 * s)) * e + 2.0 * k * e * e;
  const double denominator = (k * k + 1.0 + 4.0 * s * s) * e + k * (1.0 + e * e);
  return numerator / denominator;
}

double layer_surface_compliance(double s, double nu) {
  check_nu(nu);
  const double k = 3.0 - 4.0 * nu;
  if (s > 20.0) return 1.0 - layer_kernel_weight(s, nu);
  return (2.0 * k * std::sinh(2.0 * s) - 4.0 * s) /
         (2.0 * k * std::cosh(2.0 * s) + k * k + 1.0 + 4.0 * s * s);
}

LayerQuadrature default_layer_quadrature(double a_over_h) {
  LayerQuadrature q;
  q.collocation_nodes = 12 + static_cast<int>(std::ceil(4.0 * a_over_h));
  q.points_per_panel = 16;
  q.panel_width = a_over_h > 4.0 ? 2.0 / a_over_h : 0.5;
  q.u_max = 25.0;
  return q;
}

double layer_kappa(double a_over_h, double nu) {
  return layer_kappa(a_over_h, nu, default_layer_quadrature(a_over_h));
}

double layer_kappa(double a_over_h, double nu, const LayerQuadrature& quadrature) {
  check_a_over_h(a_over_h);
  check_nu(nu);
  if (quadrature.collocation_nodes < 1 || quadrature.points_per_panel < 1 ||
      !(quadrature.panel_width > 0.0) || !(quadrature.u_max > 0.0)) {
    throw std::invalid_argument("layer reference: invalid quadrature");
  }
  if (a_over_h == 0.0) return 1.0;
  const double lambda = a_over_h;

  // Collocation: positive half of the 2n-point rule.
  const int n = quadrature.collocation_nodes;
  const GaussRule full = gauss_legendre(2 * n);
  Eigen::VectorXd x(n);
  Eigen::VectorXd sqrt_w(n);
  for (int i = 0; i < n; ++i) {
    const auto source = static_cast<std::size_t>(n + i);
    x(i) = full.nodes[source];
    sqrt_w(i) = std::sqrt(full.weights[source]);
  }

  // Transform integral: composite Gauss–Legendre panels on [0, u_max].
  const int panels = static_cast<int>(std::ceil(quadrature.u_max / quadrature.panel_width));
  const double width = quadrature.u_max / panels;
  const GaussRule panel_rule = gauss_legendre(quadrature.points_per_panel);
  const int per_panel = quadrature.points_per_panel;
  const int q_count = panels * per_panel;
  // B = D C diag(ωM): columns are scaled so that B Bᵀ = D C diag(ωM) Cᵀ D.
  Eigen::MatrixXd scaled(n, q_count);
  for (int p = 0; p < panels; ++p) {
    for (int j = 0; j < per_panel; ++j) {
      const auto jj = static_cast<std::size_t>(j);
      const double u = width * (p + 0.5 * (panel_rule.nodes[jj] + 1.0));
      const double omega_m = 0.5 * width * panel_rule.weights[jj] * layer_kernel_weight(u, nu);
      const double column_scale = std::sqrt(omega_m);
      const int column = p * per_panel + j;
      for (int i = 0; i < n; ++i) {
        scaled(i, column) = column_scale * sqrt_w(i) * std::cos(lambda * u * x(i));
      }
    }
  }
  Eigen::MatrixXd system = Eigen::MatrixXd::Identity(n, n);
  system.noalias() -= (2.0 * lambda / std::numbers::pi) * (scaled * scaled.transpose());
  const Eigen::LDLT<Eigen::MatrixXd> factor(system);
  if (factor.info() == Eigen::Success && factor.isPositive()) {
    return sqrt_w.dot(factor.solve(sqrt_w));
  }
  // A quadrature far too coarse for this a/h can lose definiteness; it still
  // gives an (inaccurate) answer, which convergence studies need to see.
  return sqrt_w.dot(system.partialPivLu().solve(sqrt_w));
}

double layer_stiffness(double a, double h, double young, double nu) {
  if (!(a > 0.0) || !(h > 0.0) || !(young > 0.0)) {
    throw std::invalid_argument("layer reference: a, h and E must be positive");
  }
  const double shear = young / (2.0 * (1.0 + nu));
  return 4.0 * a * shear * layer_kappa(a / h, nu) / (1.0 - nu);
}

double half_space_stiffness(double a, double young, double nu) {
  check_nu(nu);
  return 2.0 * a * young / (1.0 - nu * nu);
}

}  // namespace palpa::test
