// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Bilinear axisymmetric quadrilateral with 3×3 Gauss points (thesis §4.2–4.3).
// Element DOFs u = (u_r0, u_z0, u_r1, u_z1, u_r2, u_z2, u_r3, u_z3) [m]. At each
// Gauss point the five non-zero entries of F (thesis 4.5),
//   x = (F_rr, F_zr, F_rz, F_zz, F_θθ) = x0 + B u,  x0 = (1, 0, 0, 1, 1),
// with F_θθ = 1 + u_r/r, and the energy is E = Σ_k w_k Ψ(x_k),
// w_k = 2π r_k W_k |det J_k| (thesis 4.2 with the Jacobian made explicit), a
// full-circle energy [J].

#include <string_view>

#include <Eigen/Core>
#include <array>

#include "palpa/material/material.hpp"

namespace palpa::axisym {

using Vec8 = Eigen::Matrix<double, 8, 1>;
using Mat8 = Eigen::Matrix<double, 8, 8>;
using BMatrix = Eigen::Matrix<double, 5, 8>;

inline constexpr int kGaussPoints = 9;

// Standard: Ψ(F) at each Gauss point (locks as ν → 0.5).
// FBar: Ψ(F̄) with F̄ = (J̄/J)^(1/3) F, J̄ the element's volume-averaged det F
// (de Souza Neto, Perić, Dutko, Owen 1996): the volume change is constant over
// the element, which removes volumetric locking of the bilinear quad for
// nearly incompressible tissue; identical to Standard where J is uniform.
enum class ElementFormulation { Standard, FBar };

// "standard" / "fbar", as files and the command line name them; an unknown
// name is an Input error naming option --element.
std::string_view to_string(ElementFormulation f) noexcept;
ElementFormulation parse_element_formulation(std::string_view name);

// F-bar leaves the variation of det F within an element without volumetric
// stiffness; under strong compression that soft mode lets single Gauss points
// crush. FBar adds (k/2) Σ_k w_k (ln J_k − ln J̄)² with a stabilization
// modulus k of the order of the shear modulus: it vanishes for uniform J and
// under refinement, and (unlike a bulk-modulus-sized term) does not bring
// locking back.
struct ElementOptions {
  ElementFormulation formulation = ElementFormulation::FBar;
  double stabilization = 0.0;  // k [Pa], FBar only
};

// Rest-state data of one element: per Gauss point the map B from element DOFs
// to x, the weight w [m^3] and the radius r [m].
struct QuadGeometry {
  std::array<BMatrix, kGaussPoints> b;
  std::array<double, kGaussPoints> weight;
  std::array<double, kGaussPoints> radius;
};

// rest: 2 × 4 node positions (r, z) [m], counter-clockwise. Throws
// palpa::Error (Internal) for a degenerate or inverted cell.
QuadGeometry quad_geometry(const Eigen::Matrix<double, 2, 4>& rest);

struct ElementResult {
  double energy = 0.0;  // [J]
  Vec8 gradient;        // ∂E/∂u [N]
  Mat8 hessian;         // ∂²E/∂u² [N/m]
};

// Energy (and gradient / Hessian per `order`). Returns false, leaving `out`
// unspecified, if any Gauss point is inverted or degenerate (det F2 <= 0 or
// F_θθ <= 0): the caller treats the configuration as inadmissible. With
// PsdProjection other than None only the material tangent is projected; the
// F-bar geometric terms are kept (use None where exactness matters).
bool element_evaluate(const material::Material& m, const QuadGeometry& g, const Vec8& u,
                      material::EvalOrder order, material::PsdProjection projection,
                      ElementResult& out, const ElementOptions& options = {});

// ∂(∂E/∂u)/∂θ: out is 8 × p; work3 is 3 × p and work5 5 × p scratch.
void element_dgradient_dparam(const material::Material& m, const QuadGeometry& g, const Vec8& u,
                              Eigen::Ref<Eigen::MatrixXd> work3, Eigen::Ref<Eigen::MatrixXd> work5,
                              Eigen::Ref<Eigen::MatrixXd> out,
                              const ElementOptions& options = {});

// Gauss-point averages for output (weights: the Gauss volumes): principal
// stretches in decreasing order (of F̄ for F-bar), det F, and the Cauchy stress
// components σ_rr, σ_zz, σ_rz, σ_θθ [Pa].
struct ElementState {
  Eigen::Vector3d stretches = Eigen::Vector3d::Ones();
  double jacobian = 1.0;
  Eigen::Vector4d cauchy = Eigen::Vector4d::Zero();
};
ElementState element_state(const material::Material& m, const QuadGeometry& g, const Vec8& u,
                           const ElementOptions& options = {});

// Smallest det F (= det F2 · F_θθ) over the Gauss points (of F, not F̄: an
// element is inverted if any point is).
double element_min_jacobian(const QuadGeometry& g, const Vec8& u);

// x at Gauss point k.
Eigen::Matrix<double, 5, 1> gauss_point_gradient(const QuadGeometry& g, int k, const Vec8& u);

}  // namespace palpa::axisym
