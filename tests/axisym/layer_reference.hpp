// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Analytic reference for the small-depth stiffness of a rigid flat-ended
// cylindrical punch on a linear-elastic layer bonded to a rigid base.
//
// The problem: a punch of radius a is pressed by a depth w (w ≪ a, h) into a
// layer of thickness h, shear modulus G = E / (2 (1 + ν)) and Poisson's ratio ν,
// whose lower face is bonded to a rigid base; contact under the punch is
// frictionless and the surface outside it is traction-free. The load is
//
//   P = 4 a G w κ(a/h, ν) / (1 − ν)                     (Hayes et al. 1972, eq. for
//                                                         the plane-ended indenter)
//
// with κ → 1 as a/h → 0, where P/w becomes the half-space (Boussinesq/Sneddon)
// stiffness 2 a E / (1 − ν²). κ is computed here from the Fredholm integral
// equation of the second kind that governs the problem (derivation in
// layer_reference.cpp), solved by a Nyström method; it is not interpolated from
// any table.
//
// Validity and accuracy: 0 ≤ a/h ≤ 50 and −1 < ν ≤ 0.5 (ν = 0.5, the
// incompressible layer, is included: the kernel stays regular there). With the
// default quadrature the relative error of κ is below 1e-9 for a/h ≤ 20 and
// below 1e-7 up to a/h = 50 (measured against refined quadratures; see the
// convergence tests). Cost per value (Release): about 0.2 ms for a/h ≤ 4,
// 1.5 ms at a/h = 8, 8 ms at 20, 70 ms at 50 (it grows like (a/h)³).
//
// Thin-layer limits (a/h → ∞): κ ≈ (π/2) (a/h) (1 − ν)² / (1 − 2ν) for ν < 0.5
// (the layer under the punch is in confined compression), κ ≈ 3π (a/h)³ / 64 for
// ν = 0.5 (squeeze flow of an incompressible layer under a frictionless punch).
// Both are leading orders only; at a/h = 10 the second is off by a factor ~1.7.
//
// Published values (tests/axisym/hayes_table.md): κ agrees with Hayes et al.'s
// Table 1 for ν = 0.3 and 0.45 to 0.04% at a/h ≤ 0.4 and 0.4–0.64% at a/h = 2.
// Their column labelled ν = 0.5 (as transcribed) is 1–20% below κ(a/h, 0.5) and
// matches κ(a/h, 0.48) instead: do not use it for incompressible layers.

namespace palpa::test {

// Largest a/h the functions below accept.
inline constexpr double kLayerMaxAOverH = 50.0;

// Quadrature of the Nyström solution (see layer_reference.cpp).
struct LayerQuadrature {
  // n: the unknowns are the values at the n positive nodes of the 2n-point
  // Gauss–Legendre rule on [−1, 1] (the solution is even).
  int collocation_nodes = 0;
  // Gauss–Legendre points per panel of the transform integral over u = ξ h.
  int points_per_panel = 0;
  // Width of those panels in u (dimensionless).
  double panel_width = 0.0;
  // Upper limit of the transform integral in u; the integrand decays like
  // u² e^(−2u), so 25 leaves a truncation error below 1e-17.
  double u_max = 0.0;
};

// The quadrature layer_kappa(a_over_h, nu) uses: it grows with a/h so that the
// collocation resolves the edge layer of width ~h/a and the panels resolve the
// oscillation cos(u (a/h) x) of the kernel.
LayerQuadrature default_layer_quadrature(double a_over_h);

// κ(a/h, ν) of P = 4 a G w κ / (1 − ν). a_over_h: a/h ≥ 0 (κ = 1 at 0); nu:
// Poisson's ratio in (−1, 0.5]. Throws std::invalid_argument outside
// 0 ≤ a/h ≤ kLayerMaxAOverH or −1 < ν ≤ 0.5.
double layer_kappa(double a_over_h, double nu);
// The same with an explicit quadrature (for convergence studies). Throws
// std::invalid_argument for a quadrature with fewer than 1 node or point, a
// non-positive panel width or u_max.
double layer_kappa(double a_over_h, double nu, const LayerQuadrature& quadrature);

// L(s): the surface compliance factor of the layer. A normal surface pressure
// whose Hankel transform is P̄(ξ) gives the surface displacement
// u_z(r) = ((1 − ν)/G) ∫ P̄(ξ) L(ξ h) J0(ξ r) dξ (into the layer); L → 1 for a
// half-space. s = ξ h ≥ 0 (dimensionless), nu in (−1, 0.5].
double layer_surface_compliance(double s, double nu);

// M(s) = 1 − L(s), the kernel weight: K(t) = ∫_0^∞ M(u) cos(u t) du. Evaluated
// in a form without overflow or cancellation for large s (where M ~ s² e^(−2s)).
double layer_kernel_weight(double s, double nu);

// Small-depth stiffness P/w of the bonded layer [N/m]: 4 a G κ(a/h, ν) / (1 − ν).
// a: punch radius [m] > 0; h: layer thickness [m] > 0; young: E [Pa] > 0.
double layer_stiffness(double a, double h, double young, double nu);

// Small-depth stiffness P/w of the half-space [N/m]: 2 a E / (1 − ν²).
// a: punch radius [m]; young: E [Pa]; nu in (−1, 0.5].
double half_space_stiffness(double a, double young, double nu);

}  // namespace palpa::test
