// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The coordinates x a fit's optimizers move in, and the material parameters θ
// they stand for (fit.hpp). A small pure kernel: θ(x), dθ/dx and the start x
// of a material, with no simulation in it.
//
// Each free parameter is one coordinate, in units of a per-parameter scale
// (moduli: the stage-1 shear modulus or their own size; others: their own
// size), so that both optimizers see a well-scaled problem; volume_share and
// the positive moduli have box bounds in x.
//
// Compressibility is fitted as the small-strain Poisson's ratio ν in a range
// (lo, hi) (PoissonRange), through a logistic coordinate: ν = lo + (hi − lo)·σ(x),
// σ(x) = 1/(1 + e^−x). Neither end is reachable, so the optimizers never stick
// to a bound, and a step of one in x near ν → 0.5 changes 0.5 − ν by a factor
// rather than by an amount (near-incompressibility is where the data are
// least sensitive to it). Models parametrized by ν use it directly; models
// with a volumetric compliance D1 (Ψ ∋ (J − 1)²/D1: neo-hookean-isochoric,
// mooney-rivlin, yeoh) get the same coordinate in place of D1, and D1 follows
// the moduli: D1 = 2/K = 3(1 − 2ν)/(μ0(1 + ν)), μ0 the small-strain shear
// modulus, linear in their moduli. So "nu" names the same thing in every
// model: --fix nu holds ν (D1 then follows the shear modulus), --fix D1 holds
// D1 itself.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "palpa/material/material.hpp"

namespace palpa::fit {

// The range of the small-strain Poisson's ratio a fit may reach (open). Its
// top stops short of 0.5: these models are compressible, and as ν → 0.5 the
// bulk modulus K = 2μ(1 + ν)/(3(1 − 2ν)) grows without bound, the simulations
// grow ill-conditioned and the curves stop seeing ν (0.4999: K = 5000 μ, where
// homogeneous and indentation responses are within a fraction of a percent of
// the incompressible ones).
struct PoissonRange {
  double lo = -0.9;
  double hi = 0.4999;
};

class Coordinates {
 public:
  // start: the material whose parameters x = start() stands for (its ν moved
  // inside `nu` if it lies outside, unless ν is held); fixed: parameter names held at the
  // start's values (throws palpa::Error (Input) for a name the model does not
  // have, or when every parameter is fixed); mu0: the shear modulus that
  // scales moduli.
  Coordinates(const material::Material& start, const std::vector<std::string>& fixed, double mu0,
              PoissonRange nu = {});

  Eigen::Index size() const noexcept { return static_cast<Eigen::Index>(param_.size()); }
  Eigen::VectorXd start() const;
  Eigen::VectorXd theta(const Eigen::VectorXd& x) const;
  // dθ/dx: num_params × size().
  Eigen::MatrixXd dtheta_dx(const Eigen::VectorXd& x) const;
  // Box bounds in x (±inf where open).
  const std::vector<double>& lower() const noexcept { return lower_; }
  const std::vector<double>& upper() const noexcept { return upper_; }
  // The material parameter of coordinate i (for D1's ν coordinate: D1).
  Eigen::Index param(Eigen::Index i) const { return param_[static_cast<std::size_t>(i)]; }
  // Whether coordinate i sits at an end of its range at x: a box bound
  // (within 1e-9 of its size), or for ν within 0.1% of the range's width of an
  // end (where its logistic coordinate has all but stopped moving ν). -1: the
  // lower end, +1: the upper end, 0: inside.
  int at_bound(const Eigen::VectorXd& x, Eigen::Index i) const;
  // Whether coordinate i is the logistic ν coordinate, and the range.
  bool is_poisson(Eigen::Index i) const { return i == nu_coordinate_; }
  PoissonRange poisson_range() const noexcept { return nu_; }

 private:
  double nu_of(double x) const noexcept;
  double dnu_dx(double x) const noexcept;
  // Small-strain shear modulus of θ (models with D1: linear in θ).
  double mu0_of(const Eigen::VectorXd& theta) const { return mu0_gradient_.dot(theta); }

  Eigen::VectorXd theta0_;
  PoissonRange nu_;
  std::vector<Eigen::Index> param_;
  std::vector<double> scale_, lower_, upper_;
  Eigen::Index nu_coordinate_ = -1;  // the logistic ν coordinate (-1: none free)
  Eigen::Index nu_param_ = -1;       // the material's ν, or its D1 when d1_follows_
  bool d1_follows_ = false;          // D1 = 3(1 − 2ν)/(μ0(1 + ν))
  double nu0_ = 0.0;                 // ν at the start (within the range)
  Eigen::VectorXd mu0_gradient_;     // ∂μ0/∂θ (models with D1)
};

}  // namespace palpa::fit
