// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Ceres' termination types as palpa's, for the modules that link Ceres (fit,
// design). Header-only: the solve module itself does not link Ceres.

#include <ceres/types.h>

#include "palpa/core/termination.hpp"

namespace palpa {

inline Termination termination_of(ceres::TerminationType t) noexcept {
  switch (t) {
    case ceres::CONVERGENCE: return Termination::Converged;
    case ceres::NO_CONVERGENCE: return Termination::IterationLimit;
    case ceres::USER_SUCCESS: return Termination::Converged;
    default: return Termination::Failed;  // FAILURE, USER_FAILURE
  }
}

}  // namespace palpa
