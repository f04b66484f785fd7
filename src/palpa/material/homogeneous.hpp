// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Homogeneous stress–stretch tests of a material, in closed form up to one
// scalar solve (no FEM): what material curve fitters and `palpa material curve`
// report. Lateral faces are traction-free.
//   uniaxial:     λ = (s, t, t), t from ∂Ψ/∂λ2 = 0
//   equibiaxial:  λ = (s, s, t), t from ∂Ψ/∂λ3 = 0
//   simple shear: F = I + γ e1 e2ᵀ (volume-preserving by kinematics)
//
// Parameter sensitivities (for fitting θ to measured curves): the derivatives
// of a curve point with respect to every material parameter θk at fixed load,
// exact up to the lateral solve. With r(t, θ) the lateral residual above,
//   dt/dθ = −(∂r/∂θ)/(∂r/∂t),   dP/dθ = ∂P/∂θ + (∂P/∂t) dt/dθ,
// where t enters both lateral stretches in uniaxial (∂/∂t = ∂/∂λ2 + ∂/∂λ3).
// Simple shear has no unknown: the principal frame of F does not depend on θ,
// so dP/dθ = U diag(∂²Ψ/∂λ∂θ) Vᵀ (kinematics.hpp, dP_dparam); at γ = 0 it is 0.
// The differentiated stresses are those of CurvePoint: P11 = ∂Ψ/∂λ1 (in
// equibiaxial the nominal stress of each loaded direction, P11 = P22, not their
// sum) and σ11 = P11 s / J; in shear P12 and σ12 (= P12, since J = 1).

#include <Eigen/Core>
#include <span>
#include <string_view>
#include <vector>

#include "palpa/material/material.hpp"

namespace palpa::material {

enum class LoadCase { Uniaxial, Equibiaxial, SimpleShear };

// "uniaxial" | "equibiaxial" | "shear"; throws palpa::Error (Input) otherwise.
LoadCase parse_load_case(std::string_view name);

struct CurvePoint {
  double load = 0.0;            // stretch s (uniaxial, equibiaxial) or shear γ
  double lateral = 1.0;         // free stretch t (1 for shear)
  double nominal = 0.0;         // first Piola–Kirchhoff P11 (P12 for shear) [Pa]
  double cauchy = 0.0;          // Cauchy σ11 (σ12 for shear) [Pa]
  double cauchy_11 = 0.0;       // shear only: normal Cauchy stresses [Pa]
  double cauchy_22 = 0.0;
  double energy = 0.0;          // Ψ [Pa]
};

// One point; `guess` is a starting value for the lateral stretch (continuation).
// Throws palpa::Error (Solver) if the lateral equilibrium cannot be found.
CurvePoint homogeneous_point(const Material& m, LoadCase c, double load, double guess = 1.0);

// `count` points with the load from `from` to `to` (inclusive), solved in
// continuation from the rest state outward so each solve starts close.
std::vector<CurvePoint> homogeneous_curve(const Material& m, LoadCase c, double from, double to,
                                          int count);

// A curve point and its derivatives with respect to the material parameters θ
// (each a vector of size m.num_params(), entry k per unit of θk, in SI).
struct CurvePointSensitivity {
  CurvePoint point;
  Eigen::VectorXd dnominal_dparams;  // d(point.nominal)/dθ [Pa per unit θk]
  Eigen::VectorXd dcauchy_dparams;   // d(point.cauchy)/dθ [Pa per unit θk]
  Eigen::VectorXd dlateral_dparams;  // d(point.lateral)/dθ [1 per unit θk]; 0 for shear
};

// Derivatives of many curve points, one row per load (#loads × num_params):
// the Jacobian blocks a Gauss–Newton / Levenberg–Marquardt fit of θ needs.
struct CurveSensitivity {
  std::vector<CurvePoint> points;    // as homogeneous_point, in the order of `loads`
  Eigen::MatrixXd dnominal_dparams;  // #loads × num_params [Pa per unit θk]
  Eigen::MatrixXd dcauchy_dparams;   // #loads × num_params [Pa per unit θk]
  Eigen::MatrixXd dlateral_dparams;  // #loads × num_params [1 per unit θk]; 0 for shear
};

// homogeneous_point and its parameter derivatives. Throws like
// homogeneous_point, and palpa::Error (Solver) if the lateral equilibrium is
// singular (∂r/∂t = 0) there, so that t does not depend smoothly on θ.
CurvePointSensitivity homogeneous_point_sensitivity(const Material& m, LoadCase c, double load,
                                                    double guess = 1.0);

// Points and derivatives at arbitrary loads (any order, repeats allowed), e.g.
// the stretches of a measured curve. The lateral stretch is solved in
// continuation outward from the rest state (s = 1, γ = 0) on either side, each
// solve starting from the previous solution on its side. Throws palpa::Error
// (Input) for a non-finite load, otherwise as homogeneous_point_sensitivity.
CurveSensitivity homogeneous_curve_sensitivity(const Material& m, LoadCase c,
                                               std::span<const double> loads);

}  // namespace palpa::material
