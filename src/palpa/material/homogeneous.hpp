#pragma once
// Homogeneous stress–stretch tests of a material, in closed form up to one
// scalar solve (no FEM): what material curve fitters and `palpa material curve`
// report. Lateral faces are traction-free.
//   uniaxial:     λ = (s, t, t), t from ∂Ψ/∂λ2 = 0
//   equibiaxial:  λ = (s, s, t), t from ∂Ψ/∂λ3 = 0
//   simple shear: F = I + γ e1 e2ᵀ (volume-preserving by kinematics)

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

}  // namespace palpa::material
