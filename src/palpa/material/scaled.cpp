// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/material/scaled.hpp"

#include <fmt/format.h>

#include <cmath>

#include "palpa/core/error.hpp"

namespace palpa::material {

std::unique_ptr<Material> scaled(const Material& m, double factor) {
  if (!(std::isfinite(factor) && factor > 0.0)) {
    throw Error(ErrorKind::Input,
                fmt::format("a stiffness factor of {}: expected a finite factor > 0", factor));
  }
  Eigen::VectorXd theta = m.params();
  for (Eigen::Index k = 0; k < theta.size(); ++k) {
    switch (m.param_info(k).dimension) {
      case Dimension::Pressure:
        theta[k] *= factor;
        break;
      case Dimension::Compliance:
        theta[k] /= factor;
        break;
      case Dimension::Dimensionless:
        break;
      default:
        throw Error(ErrorKind::Internal,
                    fmt::format("the {} parameter {} is neither a modulus, a compliance nor "
                                "dimensionless: the material cannot be scaled",
                                m.model(), m.param_info(k).name));
    }
  }
  std::unique_ptr<Material> out = m.clone();
  out->set_params(theta);
  return out;
}

std::unique_ptr<Material> with_young(const Material& m, double young) {
  if (!(std::isfinite(young) && young > 0.0)) {
    throw Error(ErrorKind::Input,
                fmt::format("a Young's modulus of {} Pa: expected a finite modulus > 0", young));
  }
  return scaled(m, young / small_strain_constants(m).young());
}

}  // namespace palpa::material
