// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Material identification from measured curves, and layer-depth estimation
// (thesis ch. 6; MODEL.md "Material fitting").
//
// Objective (6.14): ε(θ) = Σ_curves Σ_points (y_sim(θ) − y_meas)² over the
// training curves (forces [N²] for indentation and compression, stresses [Pa²]
// for homogeneous curves).
//
// Stage 1, the modulus: scaling every stress-like parameter of a material by s
// scales Ψ, and so every simulated force, by s (moduli × s, compliances such as
// D1 ÷ s, dimensionless parameters unchanged; the contact penalty and F-bar
// stabilization of a fresh simulator scale with it). So one simulation of the
// training curves with the initial material (default neo-Hookean, E = 10 kPa,
// ν from the dataset) gives the least-squares s in closed form:
// s = Σ y_sim y_meas / Σ y_sim².
//
// Stage 2, the shape: the chosen model (Valanis–Landel spline by default; or
// neo-hookean, neo-hookean-volume, mooney-rivlin, yeoh, ogden), started from the
// stage-1 material, minimizes ε over its free parameters with either
//  - Levenberg–Marquardt (Ceres' trust-region LM on the residuals, Jacobian from
//    the exact sensitivities), the default, or
//  - nonlinear conjugate gradients (the thesis's method: Polak–Ribière+ with
//    restarts, a line search by backtracking with cubic interpolation on ε and
//    its gradient 2 Jᵀr).
// Parameters are optimized in units of a per-parameter scale (moduli: the
// stage-1 shear modulus or their own size; others: their own size), so
// both optimizers see a well-scaled problem. Every trial material is checked
// (material/checks.hpp: stress-free rest state, positive-definite rest
// stiffness, stable homogeneous load paths); an invalid one, or one whose
// simulation fails, is a rejected step, never the answer.
//
// Layer depth: with several guesses, each is fitted independently (in
// parallel) and the one with the lowest final ε wins (§6.3.4).
//
// Checkpoints: after every iteration of every guess the whole state (stage-1
// scale, parameters, history; NLCG's gradient and direction, LM's
// trust-region radius) goes atomically into the checkpoint file; resuming
// continues each guess from its last iteration and takes the steps the
// uninterrupted fit takes.

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "palpa/core/termination.hpp"
#include "palpa/fit/coordinates.hpp"
#include "palpa/fit/dataset.hpp"
#include "palpa/fit/simulate.hpp"
#include "palpa/fit/uncertainty.hpp"
#include "palpa/material/material.hpp"
#include "palpa/material/spline_material.hpp"

namespace palpa::fit {

enum class Optimizer { LevenbergMarquardt, Nlcg };
std::string_view to_string(Optimizer o) noexcept;
// "lm" | "nlcg"; throws palpa::Error (Input) otherwise.
Optimizer parse_optimizer(std::string_view name);

// How a depth search picks the layer depth.
enum class DepthFrom {
  // Stage 1 (the modulus) at every guess on the small-indentation part of the
  // training curves, d ≤ kSmallIndentation·min(a, D_min), where the response is
  // close to linear and the depth shows through geometry (Hayes) rather than
  // through the material law; the lowest ε there picks the depth, and the
  // whole fit (both stages, all points) runs at that depth alone. A material
  // law that does not follow the deep part of the curves (or data that are
  // off there) cannot pull the depth.
  SmallIndentation,
  // Every guess fitted fully on all points; the lowest final ε wins (the
  // thesis's §6.3.4).
  WholeCurves,
};
std::string_view to_string(DepthFrom f) noexcept;
// "small" | "whole"; throws palpa::Error (Input) otherwise.
DepthFrom parse_depth_from(std::string_view name);
inline constexpr double kSmallIndentation = 0.1;

// The ranges of FitOptions' numbers the command line and Python accept
// (closed; a NaN lies in none).
struct OptionBounds {
  double lo, hi;
  bool holds(double v) const { return v >= lo && v <= hi; }
};
namespace bounds {
inline constexpr OptionBounds max_iterations{0, 10000}, tolerance{1e-16, 1.0}, smoothing{0.0, 1e6},
    ogden_terms{1, 6}, starts{0, 10}, mesh_level{0, 7}, steps{2, 1000};
}  // namespace bounds

struct FitOptions {
  std::string model = "spline";   // stage-2 model (see above)
  Optimizer optimizer = Optimizer::LevenbergMarquardt;
  int max_iterations = 50;        // stage-2 iterations per guess
  // Stop when an iteration lowers ε by less than this fraction of ε.
  double function_tolerance = 1e-5;
  SimulationOptions simulation;
  std::vector<std::string> fixed;  // parameter names held at their start values ("nu" in every model but spline)
  // The range of the small-strain Poisson's ratio stage 2 may reach (open at
  // both ends; coordinates.hpp); unset: poisson_range(dataset).
  std::optional<PoissonRange> nu_range;
  // Spline knots: the counts, and the ranges unless adapt_spline_ranges (then
  // layout_covering() of the stretches the stage-1 simulations reached).
  material::SplineLayout spline_layout;
  bool adapt_spline_ranges = true;
  // Spline curvature regularization strength α (optimize.hpp,
  // TrainingProblem::set_curvature_regularization): a change of curvature by
  // the shear modulus at one knot costs α × the stage-1 RMS error at one data
  // point. 0 = none.
  double smoothing = 0.1;
  int ogden_terms = 2;
  // Stage-2 starts tried (stage2_starts), each for start_iterations, the
  // best continued; 0: every start of the model; 1: the projection alone.
  int starts = 0;
  int start_iterations = 5;
  // Stage-1 starting material (its model is kept for stage 1 only); null: the
  // neo-Hookean E = 10 kPa with the dataset's ν.
  std::shared_ptr<const material::Material> initial;
  bool modulus_only = false;       // stop after stage 1
  DepthFrom depth_from = DepthFrom::SmallIndentation;
};

struct IterationRecord {
  int iteration = 0;       // 0: the start of stage 2
  double objective = 0.0;  // ε
  int evaluations = 0;     // simulations of the training curves so far (this guess)
  double seconds = 0.0;    // since the guess started
};

// One stage-2 start tried for FitOptions::start_iterations.
struct StartTrial {
  std::string label;        // "alpha 2, 5 (shares 1, 0)"
  double objective_start = 0.0;  // ε at the start (inf: rejected)
  double objective_end = 0.0;    // ε after the trial iterations
  int evaluations = 0;
};

struct GuessResult {
  double layer_depth = 0.0;            // [m]
  double modulus_scale = 1.0;          // stage-1 s
  double objective_initial = 0.0;      // ε of the initial material
  double objective_stage1 = 0.0;       // ε after stage 1 (start of stage 2)
  double objective_final = 0.0;        // ε of `material`
  std::shared_ptr<material::Material> stage1_material;
  std::shared_ptr<material::Material> stage2_start;  // where stage 2 started (the best trial's end)
  std::vector<StartTrial> starts;                    // the starts tried (empty: one start)
  Eigen::VectorXd x_final;             // stage 2's coordinates at `material` (coordinates.hpp)
  double sum_sim_squared = 0.0;        // Σ y_sim² of the initial material (stage 1's curvature)
  std::shared_ptr<material::Material> material;      // the fitted material
  std::vector<IterationRecord> history;
  int iterations = 0;
  int evaluations = 0;
  double seconds = 0.0;
  Stop stop;  // why stage 2 stopped (NotRun: a guess the depth search did not choose)
  bool done = false;
};

// The depth profile on the small-indentation part (DepthFrom::SmallIndentation).
struct SmallIndentationProfile {
  std::vector<double> objective;  // ε of the stage-1 material at each guess [N²]
  std::vector<double> young;      // its E at each guess [Pa]
  std::vector<double> cut;        // per training curve: the deepest indentation used [m]
  int points = 0;                 // training points used
};

struct FitResult {
  // In the dataset's order of layer depths. With DepthFrom::SmallIndentation
  // only the chosen guess is fitted; the others hold their stage-1 material
  // on the small-indentation part, NaN objectives and no history.
  std::vector<GuessResult> guesses;
  std::size_t best = 0;              // index of the chosen (lowest final ε) guess
  std::optional<SmallIndentationProfile> small_profile;
  int training_points = 0;
  // Of the best guess's material (uncertainty.hpp), with the layer depth in a
  // depth search.
  Uncertainty uncertainty;
  // What a user should look at: a negative ν, a parameter at an end of its
  // range, and the uncertainty's trade-offs.
  std::vector<std::string> warnings;
};

struct FitControl {
  std::filesystem::path checkpoint;  // empty: no checkpoints
  bool resume = false;               // continue from `checkpoint`
  // Called (serialized) after each iteration of a guess; for progress output.
  std::function<void(std::size_t guess, const GuessResult&)> on_iteration;
};

// The default range of ν for a dataset: (0.45, 0.4999) when its "poisson" is
// above 0.45 (rubber-like or tissue data, declared nearly incompressible: a
// fit that trades compressibility for a lower error there is not what the
// user measured), else (−0.9, 0.4999) (0.45 is also the value of a dataset
// that does not say).
PoissonRange poisson_range(const Dataset& d, const FitOptions& o);

// How many layer-depth guesses go through stage 2: one when a depth search
// chooses on the small indentations (and the curves have the points for it),
// else every guess.
std::size_t guesses_fitted(const Dataset& d, const FitOptions& o);

// Runs the fit. Throws palpa::Error: (Input) bad options or a checkpoint of
// another fit, (Solver) when the initial material cannot be simulated,
// (Interrupted) on Ctrl-C (the checkpoint then holds the last iteration).
FitResult fit_dataset(const Dataset& d, const FitOptions& o, const FitControl& control = {});

// Whether the checkpoint at `checkpoint` records every layer-depth guess of
// this fit as done (a finished fit: resuming it has nothing left to do).
// Throws palpa::Error (Input) if it is malformed or belongs to another fit.
bool fit_finished(const Dataset& d, const FitOptions& o, const std::filesystem::path& checkpoint);

// Materials that start stage 2 for `model`, all matching `stage1` at small
// strain. The first is stage 1 projected into the model: the same material
// where the model contains it (ogden with α1 = 2 and the other terms' μ zero,
// neo-hookean-volume with volume_share 0: stage 1's neo-Hookean), its
// isochoric form with the same bulk modulus otherwise (mooney-rivlin with
// C01 = 0, yeoh with C20 = C30 = 0; different only in the volumetric term,
// which matters little at the ν of rubber and tissue), the spline whose
// stresses match it best (SplineMaterial::fit_stresses with `layout`). So
// stage 2 does not start worse than stage 1. More starts, for the models
// whose minima depend on where they start: ogden with exponent sets (2, 5,
// −2, 8, −4, 10), (4, −2, 8, 2, −4, 12) and (−2, 3, 10, −4, 6, 2), equal
// shares of μ0; mooney-rivlin with C01 = 10% and 50% of μ0/2;
// neo-hookean-volume with volume_share 0.5; spline sampled from a one-term
// Ogden material with α = 5 (the stage-1 spline can stall where it starts).
struct Stage2Start {
  std::string label;
  std::unique_ptr<material::Material> material;
};
std::vector<Stage2Start> stage2_starts(const material::Material& stage1, const FitOptions& o,
                                       const material::SplineLayout& layout);
// The first of them.
std::unique_ptr<material::Material> stage2_start(const material::Material& stage1, const FitOptions& o,
                                                 const material::SplineLayout& layout);
inline std::unique_ptr<material::Material> stage2_start(const material::Material& stage1, const FitOptions& o) {
  return stage2_start(stage1, o, o.spline_layout);
}

// Knot ranges that cover the principal stretches a simulation reached (thesis
// §6.1, Fig. 6.1: the knots span the λ distribution of the deepest poke): f
// over every λi, g over every λiλj, h over J = λ1λ2λ3, each range at least
// [0.9, 1.1] and widened by one knot interval on each side (a natural
// spline's end intervals bend its slope toward zero), and never narrower
// than `base`'s ranges; the knot counts are `base`'s.
// Quantiles are energy-weighted: the central 98% of the strain energy (the
// few cells at a sharp punch rim reach extreme stretches but carry little of
// it); homogeneous curves use every point (tail 0).
material::SplineLayout layout_covering(const std::vector<CurvePrediction::StretchSample>& stretches,
                                       const material::SplineLayout& base, double tail = 0.01);

// Every stress-like parameter × s (compliances ÷ s): Ψ × s.
std::unique_ptr<material::Material> scaled_material(const material::Material& m, double s);

// Simulated curves of the dataset (all of them, train and validate) for a
// material at one layer depth; with the fit's discretization. A curve whose
// simulation stops early is returned partial (CurvePrediction::failure).
std::vector<CurvePrediction> predict_curves(const Dataset& d, double layer_depth, const material::Material& m,
                                            const SimulationOptions& o);
// The same for several materials in one parallel pass over every (material,
// curve) pair, so that the slowest curves of each run side by side: out[k]
// holds the curves of materials[k]. on_curve (if set; called from the worker
// threads) is told each (material, curve) pair as it finishes.
std::vector<std::vector<CurvePrediction>> predict_curves(
    const Dataset& d, double layer_depth, const std::vector<const material::Material*>& materials,
    const SimulationOptions& o, const std::function<void(std::size_t material, std::size_t curve)>& on_curve = {});

// ε contribution and root-mean-square error of one curve, over the points the
// prediction reached (a partial prediction is NaN beyond; see compared_points).
double sum_of_squares(const MeasuredCurve& c, const CurvePrediction& p);
double rms_error(const MeasuredCurve& c, const CurvePrediction& p);
std::size_t compared_points(const MeasuredCurve& c, const CurvePrediction& p);

}  // namespace palpa::fit
