// SPDX-License-Identifier: AGPL-3.0-or-later
// Tests of the bonded-layer flat-punch reference κ(a/h, ν): published values,
// the half-space and thin-layer limits, the small-a/h expansion, the layer
// compliance function and the convergence of both quadratures.
#include "axisym/layer_reference.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace palpa::test {
namespace {

constexpr double kPi = std::numbers::pi;

struct Published {
  double a_over_h;
  double kappa;
};

// Hayes, W.C., Keer, L.M., Herrmann, G., Mockros, L.F. (1972) "A mathematical
// analysis for indentation tests of articular cartilage", J. Biomechanics 5,
// 541–551, Table 1 (plane-ended indenter), as reproduced (cited "Hayes et al,
// 1972") in M. Ebrahimi's cartilage analysis scripts, 2018
// (github.com/MohammadHosseinEbrahimi/Equilibrium-and-instantaneous-moduli,
// equilibrium_instantaneous.m, function kappa_value; the same table is in his
// Dynamic-modulus scripts). The original table was not accessible to us; these
// are the transcribed values (three decimals).
constexpr std::array<Published, 10> kHayesNu03{{{0.2, 1.207},
                                                {0.4, 1.472},
                                                {0.6, 1.784},
                                                {0.8, 2.124},
                                                {1.0, 2.480},
                                                {1.2, 2.845},
                                                {1.4, 3.214},
                                                {1.6, 3.586},
                                                {1.8, 3.960},
                                                {2.0, 4.336}}};
// Same source, column labelled ν = 0.5 (see HayesNuHalfColumn below).
constexpr std::array<Published, 10> kHayesNu05{{{0.2, 1.268},
                                                {0.4, 1.645},
                                                {0.6, 2.129},
                                                {0.8, 2.704},
                                                {1.0, 3.359},
                                                {1.2, 4.085},
                                                {1.4, 4.878},
                                                {1.6, 5.737},
                                                {1.8, 6.659},
                                                {2.0, 7.644}}};
// ν = 0.45, labelled "Hayes et al. (1972)" (with Zheng & Mak 1999) in a public
// Python port of a legacy MATLAB analysis script for ultrasound indentation of
// soft tissue (s3_e_20170718_polyfit_index_kUS.m, table index_k_serial). The
// entries up to a/h = 2 lie in the range of Hayes' Table 1; those beyond are an
// extension whose original source is not named there.
constexpr std::array<Published, 7> kHayesNu045{{{0.2, 1.252},
                                                {0.4, 1.599},
                                                {0.6, 2.031},
                                                {0.8, 2.532},
                                                {1.0, 3.085},
                                                {1.5, 4.638},
                                                {2.0, 6.380}}};
constexpr std::array<Published, 8> kExtendedNu045{{{2.5, 8.265},
                                                   {3.0, 10.26},
                                                   {3.5, 12.32},
                                                   {4.0, 14.45},
                                                   {5.0, 18.80},
                                                   {6.0, 23.23},
                                                   {7.0, 27.69},
                                                   {8.0, 32.15}}};

// Agreement with Hayes' Table 1 (a/h ≤ 2). Observed: our κ is higher by at most
// 0.04% for a/h ≤ 0.4 (the table's rounding), growing smoothly with a/h to 0.40%
// (ν = 0.3) and 0.64% (ν = 0.45) at a/h = 2 — a systematic, smooth deviation of
// the 1972 numerical solution; ours is converged to 1e-9 (QuadratureConverges).
constexpr double kTableTolerance = 0.01;          // relative, a/h ≤ 2
constexpr double kSmallAOverHTolerance = 0.0015;  // relative, a/h ≤ 0.6

void expect_matches(const Published& p, double nu) {
  const double kappa = layer_kappa(p.a_over_h, nu);
  EXPECT_NEAR(kappa / p.kappa, 1.0, kTableTolerance) << "a/h " << p.a_over_h << " nu " << nu;
  if (p.a_over_h <= 0.6) {
    EXPECT_NEAR(kappa / p.kappa, 1.0, kSmallAOverHTolerance)
        << "a/h " << p.a_over_h << " nu " << nu;
  }
}

TEST(LayerReference, MatchesHayesTableNu03) {
  for (const Published& p : kHayesNu03) expect_matches(p, 0.3);
}

TEST(LayerReference, MatchesHayesTableNu045) {
  for (const Published& p : kHayesNu045) expect_matches(p, 0.45);
}

TEST(LayerReference, ExtendedNu045TableAgreesWithinItsOwnAccuracy) {
  // Beyond Hayes' range the published values fall increasingly below ours:
  // 0.85% at a/h = 2.5 to 2.9% at a/h = 8. Their increments (4.46 per unit a/h
  // between 6 and 8) stay well below the exact thin-layer slope
  // π(1−ν)²/(2(1−2ν)) = 4.752, which ours approach (ThinLayerLimitCompressible), so the
  // extension is the less accurate of the two. Tolerance: 3.5%.
  for (const Published& p : kExtendedNu045) {
    const double kappa = layer_kappa(p.a_over_h, 0.45);
    EXPECT_NEAR(kappa / p.kappa, 1.0, 0.035) << "a/h " << p.a_over_h;
    EXPECT_GT(kappa, p.kappa) << "a/h " << p.a_over_h;
  }
}

// The transcribed ν = 0.5 column does NOT match κ(a/h, 0.5): ours is higher by
// 1.0% at a/h = 0.2 rising to 19.7% at a/h = 2. The disagreement is already in
// the exact first-order term: κ = 1 + c λ + c² λ² + O(λ³) with
// c = (2/π)∫M du = 1.1270 for ν = 0.5 (SmallAOverHExpansion), while fitting
// 1 + cλ + c²λ² + dλ³ to the column at a/h = 0.2, 0.4 gives c = 1.091, as the
// same fit does for our ν = 0.48 values (c(0.48) = 1.0866); it gives 1.131 for
// our ν = 0.5 values. The column coincides instead with our κ at ν = 0.48 to
// within the same small, smooth deviation seen for ν = 0.3 and 0.45 (≤ 0.74% up
// to a/h = 2). So either the 1972 "ν = 0.5" computation was in effect made at a
// Poisson's ratio near 0.48 (a formulation singular at ν = 1/2 would force a
// value below it), or the column was mis-transcribed; it must not be used as a
// reference for incompressible layers. This test pins both observations.
TEST(LayerReference, HayesNuHalfColumnCorrespondsToNuNear048) {
  for (const Published& p : kHayesNu05) {
    EXPECT_NEAR(layer_kappa(p.a_over_h, 0.48) / p.kappa, 1.0, kTableTolerance)
        << "a/h " << p.a_over_h;
    const double excess = layer_kappa(p.a_over_h, 0.5) / p.kappa - 1.0;
    EXPECT_GT(excess, 0.009) << "a/h " << p.a_over_h;
    EXPECT_LT(excess, 0.21) << "a/h " << p.a_over_h;
  }
}

// ∫_0^∞ M(u) du by composite Simpson (M is smooth and below 1e-30 past u = 40).
double kernel_integral(double nu) {
  const int intervals = 40000;
  const double upper = 40.0;
  const double step = upper / intervals;
  double sum = layer_kernel_weight(0.0, nu) + layer_kernel_weight(upper, nu);
  for (int i = 1; i < intervals; ++i) {
    sum += (i % 2 == 1 ? 4.0 : 2.0) * layer_kernel_weight(i * step, nu);
  }
  return sum * step / 3.0;
}

TEST(LayerReference, HalfSpaceLimit) {
  // κ → 1 as a/h → 0 (Sneddon's half-space result), exactly 1 at 0.
  for (double nu : {0.0, 0.3, 0.5}) {
    EXPECT_EQ(layer_kappa(0.0, nu), 1.0);
    EXPECT_NEAR(layer_kappa(1e-6, nu), 1.0, 2e-6) << nu;
  }
  // The stiffness helpers agree: a layer 1e5 times thicker than the punch radius
  // is a half-space to O(a/h) = 1e-5.
  const double a = 2e-3;
  const double young = 12e3;
  for (double nu : {0.2, 0.45}) {
    const double half = half_space_stiffness(a, young, nu);
    EXPECT_NEAR(half, 2.0 * a * young / (1.0 - nu * nu), 1e-12 * half);
    EXPECT_NEAR(layer_stiffness(a, 1e5 * a, young, nu) / half, 1.0, 2e-5) << nu;
  }
}

TEST(LayerReference, SmallAOverHExpansion) {
  // κ = 1 + c λ + c² λ² + O(λ³), c = (2/π) ∫_0^∞ M(u) du (derivation in
  // layer_reference.cpp). Observed |remainder| / λ³ between 0.1 and 0.62.
  for (double nu : {0.0, 0.3, 0.45, 0.5}) {
    const double c = 2.0 / kPi * kernel_integral(nu);
    for (double lambda : {1e-3, 1e-2, 5e-2, 0.1}) {
      const double series = 1.0 + c * lambda + c * c * lambda * lambda;
      EXPECT_NEAR(layer_kappa(lambda, nu), series, lambda * lambda * lambda)
          << "nu " << nu << " a/h " << lambda;
    }
  }
  // The coefficient itself, for the record: c(0.3) = 0.87653, c(0.5) = 1.12695.
  EXPECT_NEAR(2.0 / kPi * kernel_integral(0.3), 0.876533, 1e-6);
  EXPECT_NEAR(2.0 / kPi * kernel_integral(0.5), 1.126955, 1e-6);
}

TEST(LayerReference, GrowsWithAOverHAndWithPoissonsRatio) {
  const std::vector<double> nus{0.0, 0.2, 0.3, 0.4, 0.45, 0.49, 0.5};
  for (double nu : nus) {
    double previous = 1.0;
    for (int i = 1; i <= 40; ++i) {
      const double lambda = 0.25 * i;
      const double kappa = layer_kappa(lambda, nu);
      EXPECT_GT(kappa, previous) << "nu " << nu << " a/h " << lambda;
      previous = kappa;
    }
  }
  for (double lambda : {0.2, 1.0, 4.0, 10.0}) {
    for (std::size_t j = 1; j < nus.size(); ++j) {
      EXPECT_GT(layer_kappa(lambda, nus[j]), layer_kappa(lambda, nus[j - 1]))
          << "a/h " << lambda << " nu " << nus[j];
    }
  }
}

TEST(LayerReference, ThinLayerLimitCompressible) {
  // a/h → ∞, ν < 1/2: the layer under the punch is in confined compression,
  // σ_zz = −2G(1−ν)/(1−2ν) · w/h, so P → π a² 2G(1−ν) w / ((1−2ν) h) and
  // κ = P(1−ν)/(4aGw) → s λ with s = (π/2)(1−ν)²/(1−2ν); the edge adds an O(1)
  // constant κ − s λ → c0 (c0 ≈ 0.4705 for ν = 0.3, ≈ −5.18 for ν = 0.45).
  // Observed secant slope over [20, 30]: within 3e-5 (ν = 0.3) and 7e-4
  // (ν = 0.45) of s.
  for (double nu : {0.0, 0.3, 0.45}) {
    const double slope = 0.5 * kPi * (1.0 - nu) * (1.0 - nu) / (1.0 - 2.0 * nu);
    const double k10 = layer_kappa(10.0, nu);
    const double k20 = layer_kappa(20.0, nu);
    const double k30 = layer_kappa(30.0, nu);
    EXPECT_NEAR((k30 - k20) / 10.0 / slope, 1.0, 1e-3) << nu;
    // The secant slope converges: closer over [20, 30] than over [10, 20].
    EXPECT_LT(std::abs((k30 - k20) / 10.0 - slope), std::abs((k20 - k10) / 10.0 - slope)) << nu;
    // κ / (s λ) → 1 like 1 + c0 / (s λ) (−0.036 for ν = 0.45 at λ = 30).
    EXPECT_NEAR(k30 / (slope * 30.0), 1.0, 0.04) << nu;
  }
  EXPECT_NEAR(layer_kappa(30.0, 0.3) - 0.5 * kPi * 0.49 / 0.4 * 30.0, 0.4708, 1e-3);
}

TEST(LayerReference, ThinLayerLimitIncompressible) {
  // ν = 1/2, a/h → ∞: squeeze flow between the bonded base and the frictionless
  // punch, flux −(h³/3G) dp/dr, p = 3Gw(a² − r²)/(4h³), P = 3π G w a⁴ / (8h³), so
  // κ → 3π λ³/64. The edge acts like a larger radius: κ ≈ 3π (λ + d)³ / 64 with
  // d → 1.95 (observed 1.975 at λ = 10, 1.959 at λ = 30, 1.956 at λ = 40).
  const double coefficient = 3.0 * kPi / 64.0;
  double previous_offset = 0.0;
  for (double lambda : {10.0, 20.0, 30.0}) {
    const double kappa = layer_kappa(lambda, 0.5);
    EXPECT_GT(kappa, coefficient * lambda * lambda * lambda) << lambda;
    const double offset = std::cbrt(kappa / coefficient) - lambda;
    EXPECT_NEAR(offset, 1.96, 0.03) << lambda;
    if (previous_offset > 0.0) {
      EXPECT_LT(offset, previous_offset) << lambda;
    }
    previous_offset = offset;
  }
}

TEST(LayerReference, QuadratureConverges) {
  // Default quadrature against one with twice the collocation nodes, half the
  // panel width, 20-point panels and a longer transform interval: the default
  // is accurate to 1e-9 relative (observed ≤ 2e-10 up to a/h = 20; the hardest
  // case is the incompressible layer at the largest a/h).
  auto default_against_fine = [](double lambda, double nu) {
    const LayerQuadrature base = default_layer_quadrature(lambda);
    LayerQuadrature fine = base;
    fine.collocation_nodes = 2 * base.collocation_nodes + 8;
    fine.panel_width = 0.5 * base.panel_width;
    fine.points_per_panel = 20;
    fine.u_max = 30.0;
    return layer_kappa(lambda, nu, base) / layer_kappa(lambda, nu, fine);
  };
  for (double nu : {0.0, 0.3, 0.45, 0.5}) {
    for (double lambda : {0.2, 1.0, 2.0, 5.0, 12.0}) {
      EXPECT_NEAR(default_against_fine(lambda, nu), 1.0, 1e-9) << "nu " << nu << " a/h " << lambda;
    }
  }
  EXPECT_NEAR(default_against_fine(20.0, 0.5), 1.0, 1e-9);
  // Each quadrature converges exponentially when refined alone (a/h = 8,
  // ν = 0.3; errors relative to the default).
  const double lambda = 8.0;
  const double reference = layer_kappa(lambda, 0.3);
  auto error_with = [&](auto change) {
    LayerQuadrature q = default_layer_quadrature(lambda);
    change(q);
    return std::abs(layer_kappa(lambda, 0.3, q) / reference - 1.0);
  };
  // Collocation: 16 nodes ~2e-4, 32 nodes ~7e-11.
  const double n16 = error_with([](LayerQuadrature& q) { q.collocation_nodes = 16; });
  const double n32 = error_with([](LayerQuadrature& q) { q.collocation_nodes = 32; });
  EXPECT_GT(n16, 1e-5);
  EXPECT_LT(n32, 1e-9);
  // Transform panels (8-point): width 2 ~5e-2, width 1 ~7e-6.
  const double w2 = error_with([](LayerQuadrature& q) {
    q.points_per_panel = 8;
    q.panel_width = 2.0;
  });
  const double w1 = error_with([](LayerQuadrature& q) {
    q.points_per_panel = 8;
    q.panel_width = 1.0;
  });
  EXPECT_GT(w2, 1e-3);
  EXPECT_LT(w1, 1e-4);
  EXPECT_LT(w1, 1e-2 * w2);
  // Truncation of the transform integral: u_max 6 ~7e-7, 10 ~2e-10, 15 ~1e-14.
  const double u6 = error_with([](LayerQuadrature& q) { q.u_max = 6.0; });
  const double u10 = error_with([](LayerQuadrature& q) { q.u_max = 10.0; });
  const double u15 = error_with([](LayerQuadrature& q) { q.u_max = 15.0; });
  EXPECT_GT(u6, 1e-8);
  EXPECT_LT(u10, 1e-8);
  EXPECT_LT(u15, 1e-12);
}

// Transformed layer equations integrated directly (an independent check of L):
// with u_r = U(z) J1(ξr), u_z = W(z) J0(ξr) and λ_L the Lamé modulus, the
// Navier equations become
//   G U'' = ξ [(λ_L + 2G) ξ U + λ_L W'] + G ξ W',
//   (λ_L + 2G) W'' = −ξ [G (U' − ξ W) + λ_L U'],
// σ_zz = (λ_L + 2G) W' + λ_L ξ U, σ_rz = G (U' − ξ W). Two solutions from the
// bonded face (U = W = 0, unit U' or W') are integrated up to the top face by
// RK4 and combined so that σ_rz = 0 and σ_zz = −1 there; L = G ξ W(0)/(1−ν).
double compliance_by_integration(double s, double nu) {
  const double shear = 1.0;
  const double lame = 2.0 * shear * nu / (1.0 - 2.0 * nu);
  const double xi = 1.0;
  using State = std::array<double, 4>;  // U, U', W, W'
  auto rate = [&](const State& y) {
    const double upp =
        (xi * ((lame + 2.0 * shear) * xi * y[0] + lame * y[3]) + shear * xi * y[3]) / shear;
    const double wpp = -(xi * shear * (y[1] - xi * y[2]) + lame * xi * y[1]) / (lame + 2.0 * shear);
    return State{y[1], upp, y[3], wpp};
  };
  auto integrate = [&](State y) {
    const int steps = 4000;
    const double dz = -s / steps;  // from the base z = s down to the top z = 0
    for (int i = 0; i < steps; ++i) {
      const State k1 = rate(y);
      State t{};
      for (std::size_t j = 0; j < 4; ++j) t[j] = y[j] + 0.5 * dz * k1[j];
      const State k2 = rate(t);
      for (std::size_t j = 0; j < 4; ++j) t[j] = y[j] + 0.5 * dz * k2[j];
      const State k3 = rate(t);
      for (std::size_t j = 0; j < 4; ++j) t[j] = y[j] + dz * k3[j];
      const State k4 = rate(t);
      for (std::size_t j = 0; j < 4; ++j)
        y[j] += dz / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
    }
    return y;
  };
  const State a = integrate({0.0, 1.0, 0.0, 0.0});
  const State b = integrate({0.0, 0.0, 0.0, 1.0});
  auto sigma_zz = [&](const State& y) { return (lame + 2.0 * shear) * y[3] + lame * xi * y[0]; };
  auto sigma_rz = [&](const State& y) { return shear * (y[1] - xi * y[2]); };
  const double a11 = sigma_rz(a), a12 = sigma_rz(b), a21 = sigma_zz(a), a22 = sigma_zz(b);
  const double det = a11 * a22 - a12 * a21;
  const double alpha = a12 / det;  // solves [a11 a12; a21 a22] (α, β) = (0, −1)
  const double beta = -a11 / det;
  const double w_top = alpha * a[2] + beta * b[2];
  return shear * xi * w_top / (1.0 - nu);
}

TEST(LayerReference, SurfaceComplianceMatchesTheLayerEquations) {
  for (double nu : {0.0, 0.3, 0.45, 0.49}) {
    for (double s : {0.3, 1.0, 2.5}) {
      EXPECT_NEAR(layer_surface_compliance(s, nu), compliance_by_integration(s, nu), 1e-9)
          << "nu " << nu << " s " << s;
    }
  }
}

TEST(LayerReference, SurfaceComplianceLimits) {
  for (double nu : {0.0, 0.3, 0.45, 0.5}) {
    // Half-space: L → 1, M = 1 − L ~ (k² + (1+2s)²) e^(−2s) / k, computed
    // without cancellation.
    const double k = 3.0 - 4.0 * nu;
    const double s = 30.0;
    const double tail = (k * k + (1.0 + 2.0 * s) * (1.0 + 2.0 * s)) * std::exp(-2.0 * s) / k;
    EXPECT_NEAR(layer_kernel_weight(s, nu) / tail, 1.0, 1e-12) << nu;
    EXPECT_NEAR(layer_surface_compliance(s, nu), 1.0, 1e-20) << nu;
    EXPECT_GT(layer_kernel_weight(s, nu), 0.0) << nu;
    EXPECT_EQ(layer_kernel_weight(0.0, nu), 1.0) << nu;
    for (double t : {0.05, 0.7, 3.0}) {
      EXPECT_NEAR(layer_kernel_weight(t, nu) + layer_surface_compliance(t, nu), 1.0, 1e-14);
      EXPECT_GT(layer_surface_compliance(t, nu), 0.0);
    }
  }
  // Thin compressible layer: confined compression, L ≈ (1−2ν) s / (2(1−ν)²).
  for (double nu : {0.0, 0.3, 0.45}) {
    const double s = 1e-4;
    EXPECT_NEAR(layer_surface_compliance(s, nu) / s,
                (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu) * (1.0 - nu)), 1e-6)
        << nu;
  }
  // Thin incompressible layer: squeeze flow, L ≈ 2 s³ / 3.
  const double s = 1e-3;
  EXPECT_NEAR(layer_surface_compliance(s, 0.5) / (s * s * s), 2.0 / 3.0, 1e-5);
}

TEST(LayerReference, StiffnessIsHayesFormula) {
  // P/w = 4 a G κ / (1 − ν), G = E / (2(1 + ν)).
  const double a = 1.5e-3;
  const double h = 2e-3;
  const double young = 8e3;
  const double nu = 0.4;
  const double shear = young / (2.0 * (1.0 + nu));
  EXPECT_NEAR(layer_stiffness(a, h, young, nu),
              4.0 * a * shear * layer_kappa(0.75, nu) / (1.0 - nu),
              1e-12 * layer_stiffness(a, h, young, nu));
  EXPECT_GT(layer_stiffness(a, h, young, nu), half_space_stiffness(a, young, nu));
}

TEST(LayerReference, RejectsInputsOutsideItsRange) {
  EXPECT_THROW(layer_kappa(-0.1, 0.3), std::invalid_argument);
  EXPECT_THROW(layer_kappa(kLayerMaxAOverH + 1.0, 0.3), std::invalid_argument);
  EXPECT_THROW(layer_kappa(1.0, 0.51), std::invalid_argument);
  EXPECT_THROW(layer_kappa(1.0, -1.0), std::invalid_argument);
  EXPECT_THROW(layer_kappa(1.0, std::nan("")), std::invalid_argument);
  LayerQuadrature q = default_layer_quadrature(1.0);
  q.collocation_nodes = 0;
  EXPECT_THROW(layer_kappa(1.0, 0.3, q), std::invalid_argument);
  EXPECT_THROW(layer_stiffness(1e-3, 0.0, 1e4, 0.3), std::invalid_argument);
}

}  // namespace
}  // namespace palpa::test
