// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Simulated counterparts of measured curves, with exact parameter
// sensitivities (thesis §6.2).
//
// An indentation (or plate-compression) curve is simulated by depth
// continuation on a uniform schedule of `steps` depths up to the deepest
// measured indentation; the force at each measured depth is the cubic Lagrange
// interpolant of the four nearest simulated depths. The interpolation is linear
// in the simulated forces, so the same weights carry the sensitivities dF/dθ
// (one back-solve per simulated depth, PokeSimulator). With 20 steps the
// interpolation error is far below measurement noise (O(h⁴); tested).

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "palpa/axisym/poke.hpp"
#include "palpa/fit/dataset.hpp"
#include "palpa/material/material.hpp"

namespace palpa::fit {

// How the axisymmetric model of a dataset is discretized.
struct SimulationOptions {
  int mesh_level = 2;
  bool extrapolate = true;                                     // axisym::PokeSetup::extrapolate
  int steps = 20;                                              // depths per curve
  axisym::ElementFormulation element = axisym::ElementFormulation::FBar;
  double fillet_radius = 0.0;                                  // [m]
};

struct CurvePrediction {
  std::vector<double> y;         // simulated at the measured x (force [N] or stress [Pa])
  Eigen::MatrixXd dy_dparams;    // #x × p when sensitivities were asked
  std::vector<double> grid_x;    // the simulated curve on its own schedule
  std::vector<double> grid_y;
  int newton_iterations = 0;
  std::int64_t factorizations = 0;
  // Principal stretches of every element (homogeneous: every point) in the
  // deepest state with the strain energy there (element: Ψ × volume [J];
  // homogeneous: Ψ [Pa]), when recorded: what the spline's knots must cover.
  struct StretchSample {
    Eigen::Vector3d stretches;
    double weight = 0.0;
  };
  std::vector<StretchSample> stretches;
  // Set when partial results were allowed and the simulation stopped early:
  // why, and the deepest depth reached; y is NaN beyond it.
  std::string failure;
  double reached = 0.0;
};

// Weights w (#x × #grid) of the cubic Lagrange interpolant of values on the
// increasing `grid` at the points `x` (inside [grid.front(), grid.back()]; the
// two nearest intervals are used at the ends; fewer than 4 grid points: lower
// degree). Row j sums to 1.
Eigen::MatrixXd interpolation_weights(const std::vector<double>& grid, const std::vector<double>& x);

// Simulates one measured curve for a material. Keeps its model (mesh, Hessian
// pattern, symbolic factorization) across calls with the same material model;
// the contact penalty and F-bar stabilization moduli are fixed by the material
// at the first call (see axisym/poke.hpp), so sensitivities stay exact while a
// fit changes the parameters.
class CurveSimulator {
 public:
  virtual ~CurveSimulator() = default;
  // Throws palpa::Error (Solver) when the simulation fails, (Interrupted) on Ctrl-C.
  virtual CurvePrediction predict(const material::Material& m, bool sensitivities) = 0;
  // Also record CurvePrediction::stretches from now on.
  void record_stretches(bool on) noexcept { record_stretches_ = on; }
  // A simulation that stops early (solver failure) returns what it reached
  // (CurvePrediction::failure) instead of throwing: for showing validation
  // curves, never inside a fit.
  void allow_partial(bool on) noexcept { allow_partial_ = on; }
  // The equilibria the next predict() starts from (axisym::PokeSimulator::
  // warm_start); empty for simulators without a warm start.
  virtual axisym::WarmStart warm_start() const { return {}; }
  virtual void set_warm_start(axisym::WarmStart) {}

 protected:
  bool record_stretches_ = false;
  bool allow_partial_ = false;
};

// The simulator of curve `c` of dataset `d` at layer depth `layer_depth`.
// `reference` (optional, copied) is the material that fixes the contact penalty
// and F-bar stabilization; without it the material of the first predict() call
// does. A fit passes its start material, so that the forces at a point do not
// depend on which point was simulated first (a resumed fit gives the same
// numbers as an uninterrupted one).
std::unique_ptr<CurveSimulator> make_curve_simulator(const Dataset& d, const MeasuredCurve& c,
                                                     double layer_depth, const SimulationOptions& o,
                                                     const material::Material* reference = nullptr);

// The axisymmetric set-up of an indentation or compression curve (outer radius:
// the default far field, or half the lateral size when that is smaller).
axisym::PokeSetup poke_setup(const Dataset& d, const MeasuredCurve& c, double layer_depth,
                             const SimulationOptions& o);

}  // namespace palpa::fit
