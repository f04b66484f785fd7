// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The coordinates x a fit's optimizers move in, and the material parameters θ
// they stand for (fit.hpp). A small pure kernel: θ(x), dθ/dx and the start x
// of a material, with no simulation in it.
//
// Each free parameter is one coordinate, in units of a per-parameter scale
// (moduli: the stage-1 shear modulus or their own size; others: their own
// size), so that both optimizers see a well-scaled problem. Parameters with a
// closed physical range have box bounds in x.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "palpa/material/material.hpp"

namespace palpa::fit {

class Coordinates {
 public:
  // start: the material whose parameters x = start() stands for; fixed:
  // parameter names held at the start's values (throws palpa::Error (Input)
  // for a name the model does not have, or when every parameter is fixed);
  // mu0: the shear modulus that scales moduli.
  Coordinates(const material::Material& start, const std::vector<std::string>& fixed, double mu0);

  Eigen::Index size() const noexcept { return static_cast<Eigen::Index>(param_.size()); }
  Eigen::VectorXd start() const;
  Eigen::VectorXd theta(const Eigen::VectorXd& x) const;
  // dθ/dx: num_params × size().
  Eigen::MatrixXd dtheta_dx(const Eigen::VectorXd& x) const;
  // Box bounds in x (±inf where open).
  const std::vector<double>& lower() const noexcept { return lower_; }
  const std::vector<double>& upper() const noexcept { return upper_; }
  // The material parameter of coordinate i.
  Eigen::Index param(Eigen::Index i) const { return param_[static_cast<std::size_t>(i)]; }

 private:
  Eigen::VectorXd theta0_;
  std::vector<Eigen::Index> param_;
  std::vector<double> scale_, lower_, upper_;
};

}  // namespace palpa::fit
