// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A material stiffer or softer by a factor: the same model with its energy
// scaled, Ψ_s(λ) = s Ψ(λ).
//
// An energy density is in Pa and a model's only dimensional parameters are
// moduli (Pa) and compliances (1/Pa), so by dimensional analysis Ψ is
// homogeneous of degree one in its moduli: multiplying every modulus by s and
// dividing every compliance by s scales Ψ, its stresses and its tangent by s
// exactly, and keeps every dimensionless property (Poisson's ratio, the shape
// of its stress-strain curves). The result is a material of the same model,
// with the parameters a material file holds.
//
// This is how a body carries a stiffness field measured at a few places
// (thesis §7.3.1): one fitted material's shape, scaled per tet to the Young's
// modulus found there.

#include <memory>

#include "palpa/material/material.hpp"

namespace palpa::material {

// The material with Ψ scaled by factor (> 0, finite). Throws palpa::Error
// (Input) for another factor, (Internal) for a model with a parameter that is
// neither a modulus, a compliance nor dimensionless.
std::unique_ptr<Material> scaled(const Material& m, double factor);

// The material scaled so that its small-strain Young's modulus is `young`
// [Pa] (> 0, finite).
std::unique_ptr<Material> with_young(const Material& m, double young);

}  // namespace palpa::material
