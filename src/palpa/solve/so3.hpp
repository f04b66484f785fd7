// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Rotations as rotation vectors: the exponential map of SO(3) and its left
// Jacobian, with which a rigid core's pose is updated and differentiated
// (dof_map.hpp).

#include <Eigen/Core>

namespace palpa {

// [w]×, the cross-product matrix: hat(w) v = w × v.
Eigen::Matrix3d hat(const Eigen::Vector3d& w);
// exp([ω]×) (Rodrigues).
Eigen::Matrix3d exp_so3(const Eigen::Vector3d& w);
// J_l(ω): d exp([ω]×) = [J_l(ω) dω]× exp([ω]×).
Eigen::Matrix3d left_jacobian_so3(const Eigen::Vector3d& w);

}  // namespace palpa
