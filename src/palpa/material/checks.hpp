// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Physical sanity of a material, for `palpa material show` and for fits:
// stress-free rest state, a positive-definite rest Hessian (μ > 0, K > 0), and
// stability along the homogeneous load paths (nominal stress strictly
// increasing with the load, Drucker's condition) over a stretch range.

#include <string>
#include <vector>

#include "palpa/material/material.hpp"

namespace palpa::material {

struct MaterialCheck {
  double rest_stress = 0.0;        // max |∂Ψ/∂λ| at rest [Pa]
  ElasticConstants small_strain;   // linearized constants
  std::vector<std::string> problems;  // empty when every check passed
};

// Checks uniaxial and equibiaxial paths for stretches in [lo, hi] and simple
// shear for |γ| <= hi − 1.
MaterialCheck check_material(const Material& m, double lo = 0.5, double hi = 2.0);

// Where `m` stops resisting uniaxial compression: the stretch below which its
// nominal stress no longer grows in magnitude as the stretch falls (searched
// from 1 down to `floor` in steps of 0.005), or 0 when it keeps growing down to
// `floor`. A body compressed past it can localize (Drucker's condition fails),
// so no mesh resolves its deformation there.
double uniaxial_compression_limit(const Material& m, double floor = 0.1);

}  // namespace palpa::material
