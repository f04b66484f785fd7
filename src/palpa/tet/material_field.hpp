// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A stiffness field over a body (thesis §7.3.1): one material's shape, scaled
// in every tet to the Young's modulus measured there (material/scaled.hpp),
// as the per-element materials of an ElasticModel.
//
// Moduli are grouped in relative steps (a tet's material has the modulus of
// its group, within `step` of its own): neighbouring tets of a smooth field
// then share one material, which keeps the nodal-pressure element's per-vertex
// sums short. A step of 1e-3 is far below what a fit can tell apart.

#include <Eigen/Core>
#include <vector>

#include "palpa/tet/model.hpp"

namespace palpa::tet {

struct MaterialField {
  std::vector<BodyMaterial> materials;
  Eigen::VectorXi element_material;  // #T indices into materials
};

inline constexpr double kDefaultModulusStep = 1e-3;

// young: #T moduli [Pa], each finite and > 0; shape: the material scaled and
// its density (kept). step ≥ 0 (0: a material per distinct modulus). Throws
// palpa::Error (Input) naming the first tet with a modulus that is not a
// finite positive number.
MaterialField scaled_per_element(const BodyMaterial& shape, const Eigen::VectorXd& young,
                                 double step = kDefaultModulusStep);

// Each element's small-strain Young's modulus [Pa] (#T).
Eigen::VectorXd element_young(const ElasticModel& model);

}  // namespace palpa::tet
