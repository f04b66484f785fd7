// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Ergonomic shape optimization of a support, rigid or deformable (thesis
// §7.4).
//
// Objective. φ(X) = ζ(X) + γ ψ(X) (7.15): the ergonomic score of the resting
// equilibrium on the support X and the smoothness of X (design/score.hpp). γ
// is set so that γψ = ζ on the initial shape, times 10^j (j the user's
// smoothing exponent, −2 by default; the thesis explores j ∈ −4…4). When the
// initial design region is already smooth (ψ below 1e-3 of ψ_ref), ψ_ref of a
// reference roughness — the region moved by up to 0.1 mm of seeded random
// noise — stands in for it.
//
// The contact model is frozen after the initial equilibrium: the penalty
// stiffness k (chosen there for the target penetration) and the spring areas
// stay as they are, so φ is one smooth function of X between changes of the
// contact set. When an accepted shape's deepest penetration leaves the band
// the automatic rule accepts (0.85–1.15× the target), the model is chosen
// anew there and frozen again, and the search restarts: the optimizer's φ is
// then what a solve from scratch measures, not a softer frozen model's.
//
// Gradient (7.17–7.20), one extra linear solve per gradient. At the
// equilibrium y(X) of the CoreSystem (body/core_system.hpp) g(y, X) = 0, so
//   dφ/dX = ∂ζ/∂X + γ ∂ψ/∂X − (∂g/∂X)ᵀ z,   K z = Pᵀ ∂ζ/∂Y,
// K the true Hessian at the equilibrium (NewtonSolver::factor_hessian, the
// analysis of the Newton solves reused), P the coupling of y to the body's
// vertex positions Y, and ∂g/∂X the mixed second derivatives of the penalty
// contacts, ∂²E/∂p∂q (contact/penalty.hpp), applied to w = P z.
//
// A deformable support (RestOptions::deformable_support, §7.4.3): X is its
// rest shape. Its DOFs join the equilibrium (rest/coupled.hpp), ζ sees its
// deformed surface, and X enters g only through the support's elastic
// forces, so (7.21–7.23) K z = ∂ζ/∂y over body and support DOFs and
// −(∂g/∂X)ᵀ z is the support's rest-shape derivative
// (tet::ElasticModel::rest_gradient_product). Its fixed base never moves.
// Both cases live in rest::RestSimulation::shape_derivative().
//
// A cohort (DesignOptions::cohort): several bodies on one support, each a
// BodyProblem (design/body_problem.hpp) with its own simulations, contact
// model and refreezes; φ's score term is the cohort's aggregate of each
// body's ζ over its value on the initial shape (design/cohort.hpp), and
// dφ/dX the weighted sum of the bodies' adjoint gradients, summed in the
// bodies' order. Bodies are solved at once, and across MPI ranks
// (core/ranks.hpp) body i lives on rank i mod ranks: each rank solves its
// bodies and sends the others what φ and dφ/dX need (pack_shared), so that
// every rank takes the same steps on the same numbers; rank 0 writes the
// checkpoint, with every body's state. A body's result does not depend on
// where or beside what it was solved: the design is bit for bit the same on
// any number of ranks.
//
// Design variables θ: moves of the design vertices (a region of the
// support), either free in 3D (3 per vertex) or only along their initial
// normals (1 per vertex, so the outline stays put), smoothed by the design
// filter S (design/filter.hpp): X = X0 + B S θ. Its radius defaults to
// 1.5 mean edge lengths of the region; 0 gives per-vertex moves.
//
// Optimizer: nonlinear conjugate gradients (Polak–Ribière+, restarted on a
// non-descent direction). Each iteration tries a fixed ladder of step lengths,
// each chosen so the largest vertex move is one of `moves` (1 µm … 2 mm in the
// thesis), evaluates them in parallel (each on its own simulation, warm-
// started from the current equilibrium) and takes the one with the lowest φ.
// If none lowers φ the direction restarts as steepest descent; if that fails
// too the run stops. Every accepted iteration is checkpointed (atomic JSON):
// `resume` continues bit for bit where it stopped.
//
// L-BFGS (DesignMethod::Lbfgs, the default): the same φ and gradient handed
// to Ceres' GradientProblemSolver, variables scaled so that a unit step along
// the gradient moves the support by at most half the target penetration
// (0.15 mm by default); every trial is warm-started from the accepted
// point, and the iterate taken is the point the line search accepted. Trials longer than the longest ladder step are refused unsolved, and
// a trial equilibrium that needs more than 50 Newton iterations counts as
// failed (Ceres then tries a shorter step), as does a trial shape whose
// surface would cross itself. When its line search stalls
// (φ is only piecewise smooth), one ladder iteration along the steepest
// descent is taken and L-BFGS starts afresh. Checkpoints hold the iterate,
// so a resumed run continues from it, but with a fresh L-BFGS memory (Ceres
// does not expose it): not bit for bit.

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "palpa/core/termination.hpp"
#include "palpa/design/body_problem.hpp"
#include "palpa/design/cohort.hpp"
#include "palpa/design/filter.hpp"
#include "palpa/design/score.hpp"
#include "palpa/rest/rest.hpp"

namespace palpa::design {

class DesignSpace {
 public:
  // X0: the support's vertices (world [m]); F: its outward triangles;
  // vertices: the design vertices (rows of X0). Throws palpa::Error (Input)
  // for no design vertex or one out of range.
  DesignSpace(const Eigen::MatrixX3d& X0, const Eigen::MatrixX3i& F, std::vector<int> vertices, bool normal_only,
              double filter_radius = 0.0);
  ~DesignSpace();
  Eigen::Index size() const noexcept { return normal_only_ ? static_cast<Eigen::Index>(vertices_.size())
                                                           : 3 * static_cast<Eigen::Index>(vertices_.size()); }
  const std::vector<int>& vertices() const noexcept { return vertices_; }
  bool normal_only() const noexcept { return normal_only_; }
  const Eigen::MatrixX3d& initial() const noexcept { return X0_; }
  const Eigen::MatrixX3d& normals() const noexcept { return normals_; }  // unit, per vertex
  double filter_radius() const noexcept;  // [m]
  // X0 + B S θ.
  Eigen::MatrixX3d shape(const Eigen::VectorXd& theta) const;
  // B S d: the vertex moves (#V×3) of a change d of θ.
  Eigen::MatrixX3d moves(const Eigen::VectorXd& d) const;
  // Sᵀ Bᵀ G: a gradient over the vertices (#V×3) as one over θ.
  Eigen::VectorXd restrict(const Eigen::MatrixX3d& G) const;
  // The largest vertex move of B S d [m].
  double max_move(const Eigen::VectorXd& d) const;

 private:
  Eigen::MatrixX3d X0_;
  Eigen::MatrixX3d normals_;
  std::vector<int> vertices_;
  bool normal_only_;
  std::unique_ptr<DesignFilter> filter_;
};

// The default design filter radius in mean edge lengths of the region.
inline constexpr double kFilterEdges = 1.5;

enum class DesignMethod {
  ConjugateGradient,  // the thesis's scheme (above)
  Lbfgs,              // Ceres' L-BFGS with a Wolfe line search, one equilibrium per evaluation
};

struct DesignOptions {
  DesignMethod method = DesignMethod::Lbfgs;  // the faster of the two on every example (bench/design_bench.cpp)
  ScoreOptions score;
  int taubin_iterations = 5;          // m of (7.14)
  double smoothing_exponent = -2.0;   // j: γ = 10^j · (ζ/ψ on the initial shape)
  std::optional<double> gamma;        // given: used as is [Pa^e]
  bool normal_only = false;
  // The design filter's radius [m]; unset: kFilterEdges mean edge lengths of
  // the design region; 0: per-vertex moves.
  std::optional<double> filter_radius;
  int max_iterations = 30;
  // Stops when an iteration lowers φ by less than this fraction.
  double min_relative_decrease = 1e-4;
  std::vector<double> moves{1e-6, 1e-5, 1e-4, 2e-4, 5e-4, 7e-4, 1e-3, 2e-3};  // [m]
  int threads = 0;                    // simulations evaluated at once; 0: min(#moves, cores)
  int post_smoothing = 0;             // Taubin rounds on the design vertices after the run
  double pose_to_seat_threshold = 2e-3;  // contact distance of the estimate without elasticity [m]
  // Several bodies on one support: φ's score term aggregates their ζ, each
  // normalized by its value on the initial shape. Unset: one body, its ζ.
  std::optional<CohortObjective> cohort;
  // This process alone, even under MPI (a body's own design beside a
  // cohort's, on the rank that holds the body).
  bool local = false;
  std::filesystem::path checkpoint;   // empty: none
  bool resume = false;                // continue from `checkpoint`
};

// φ and everything measured at one support shape.
struct Evaluation {
  bool ok = false;
  std::string failure;            // why not ok (an equilibrium failed: the body is named in a cohort)
  // φ = zeta + γ psi. zeta: one body's ζ, or a cohort's aggregate of its
  // bodies' normalized ζ (design/cohort.hpp).
  double phi = 0.0, zeta = 0.0, psi = 0.0;
  Eigen::MatrixX3d support;       // X [m]
  Eigen::MatrixX3d gradient;      // dφ/dX (#V×3), when asked for
  std::vector<BodyEvaluation> bodies;  // one per body, in the design's order
  double seconds = 0.0;
  double adjoint_seconds = 0.0;

  // The (first) body's: a one-body design's whole story.
  BodyEvaluation& body(std::size_t i = 0) { return bodies.at(i); }
  const BodyEvaluation& body(std::size_t i = 0) const { return bodies.at(i); }
  // Each body's equilibrium: where the next evaluation is warm-started.
  std::vector<rest::RestState> states() const;
  int newton_iterations() const;
};

struct IterationRecord {
  int iteration = 0;
  double phi = 0.0, zeta = 0.0, psi = 0.0;
  double move = 0.0;          // largest vertex move of the step taken [m]
  int evaluations = 0;        // equilibria solved this iteration
  bool restarted = false;     // the CG direction was reset
  double seconds = 0.0;       // wall time of the iteration
  double stiffness = 0.0;     // the contact stiffness k after it [N/m]
  bool refrozen = false;      // k was chosen anew after it
};

struct DesignResult {
  Evaluation initial;         // the starting shape
  Evaluation final;           // the optimized shape (after post-smoothing if asked)
  std::optional<Evaluation> before_post_smoothing;
  double gamma = 0.0;
  std::vector<IterationRecord> history;
  int iterations = 0;
  int evaluations = 0;        // equilibria solved (initial one included)
  int newton_iterations = 0;
  int refreezes = 0;          // times the contact model was chosen anew
  double seconds = 0.0;       // the whole run (a resumed run: with the seconds before the resume)
  double equilibrium_seconds = 0.0;  // the initial equilibrium from scratch
  Stop stop;  // why the run stopped
  bool resumed = false;
};

// ζ of a support solved from scratch, as `palpa rest` solves it: the
// contact settings of `rest` with the stiffness chosen for this support, the
// body lifted clear where it starts inside the support and lowered by its
// weight, a deformable support meshed from its rest surface. φ = ζ. A failed
// equilibrium gives ok = false. With `keep`, the solved simulation is handed
// over (for its fields).
Evaluation solve_from_scratch(const rest::RestBody& body, const SurfaceMesh& support, const rest::RestOptions& rest,
                              const ScoreOptions& score, std::unique_ptr<rest::RestSimulation>* keep = nullptr);

class ShapeOptimizer {
 public:
  // Builds the simulations (one per thread), solves the initial equilibrium
  // with the automatic contact stiffness and freezes the contact model.
  // design_vertices: rows of support.V that may move.
  ShapeOptimizer(const rest::RestBody& body, const SurfaceMesh& support, const rest::RestOptions& rest,
                 std::vector<int> design_vertices, DesignOptions options);
  // The same for several bodies on one support (options.cohort says how
  // their scores add up; set, it may hold one body). Each body's initial
  // equilibrium and contact model are its own.
  ShapeOptimizer(std::vector<DesignBody> bodies, const SurfaceMesh& support, std::vector<int> design_vertices,
                 DesignOptions options);
  ~ShapeOptimizer();

  const DesignSpace& space() const noexcept { return *space_; }
  double gamma() const noexcept { return gamma_; }
  const Evaluation& initial() const noexcept { return initial_; }
  // The support of the last accepted iteration (empty before the first): what
  // an interrupted run has to show.
  const Eigen::MatrixX3d& last_accepted() const noexcept { return accepted_; }
  std::size_t num_bodies() const noexcept { return names_.size(); }
  const std::string& body_name(std::size_t i) const { return names_.at(i); }
  // Whether this rank holds body i (every body without MPI), and it.
  bool holds(std::size_t i) const { return bodies_.at(i) != nullptr; }
  // The rank that holds body i.
  int owner(std::size_t i) const { return owner_.at(i); }
  BodyProblem& body(std::size_t i = 0);
  // Simulation `slot` of the first body this rank holds (rank 0: the first
  // body).
  rest::RestSimulation& simulation(int slot = 0) { return simulation_body().simulation(slot); }
  // Each body's ζ on the initial shape: what a cohort normalizes by.
  const Eigen::VectorXd& initial_zeta() const noexcept { return zeta0_; }

  // φ at X, warm-started from `warm` (one state per body), on simulation
  // `slot` of each body; with dφ/dX when `gradient`. A failed equilibrium
  // gives ok = false; Ctrl-C propagates.
  Evaluation evaluate(const Eigen::MatrixX3d& X, const std::vector<rest::RestState>& warm, bool gradient, int slot = 0);

  // solve_from_scratch (above) with body i's contact settings: how every
  // reported result is checked (the initial and optimized shapes, the
  // baselines).
  Evaluation solve_from_scratch(const rest::RestBody& body, const SurfaceMesh& support,
                                std::unique_ptr<rest::RestSimulation>* keep = nullptr, std::size_t i = 0) const {
    rest::RestOptions o = rest_.at(i);
    o.log_solves = false;
    return design::solve_from_scratch(body, support, o, options_.score, keep);
  }

  // The optimization. progress: called after every iteration.
  DesignResult run(const std::function<void(const IterationRecord&)>& progress = {});

 private:
  // An evaluation as this rank solves it (its bodies), before the ranks
  // share their bodies (finish): evaluate in two steps, so that the solves
  // of several shapes run at once and MPI is called from one thread.
  struct Pending {
    Evaluation ev;
    Eigen::MatrixX3d dpsi;
    bool gradient = false;
    bool crossed = false;  // the shape crosses itself: failed on every rank
  };
  Pending evaluate_local(const Eigen::MatrixX3d& X, const std::vector<rest::RestState>& warm, bool gradient, int slot);
  void finish(Pending& p) const;
  // Every body's shared figures from the rank that holds it (pack_shared).
  void share(std::vector<BodyEvaluation>& bodies, bool gradient) const;
  // ranks::broadcast among this design's ranks (none when it is local).
  void broadcast(std::string& bytes, int root) const;
  BodyProblem& simulation_body();
  std::vector<Evaluation> evaluate_all(const std::vector<Eigen::MatrixX3d>& shapes,
                                       const std::vector<rest::RestState>& warm);
  // zeta, phi and the gradient of e from its bodies' (ok when all are).
  void combine(Evaluation& e, const Eigen::MatrixX3d* dpsi) const;

  DesignOptions options_;
  std::vector<std::string> names_;        // every body's
  std::vector<rest::RestOptions> rest_;   // every body's rest settings (solves from scratch)
  std::vector<int> owner_;                // the rank that holds each body
  int ranks_ = 1, rank_ = 0;              // the ranks this design is spread over, and this one's
  std::vector<std::unique_ptr<BodyProblem>> bodies_;  // null where another rank holds it
  Eigen::MatrixX3i F_;                    // the support's triangles
  std::unique_ptr<Smoothness> smoothness_;
  std::unique_ptr<DesignSpace> space_;
  Eigen::VectorXd zeta0_;
  Evaluation initial_;
  Eigen::MatrixX3d accepted_;
  double gamma_ = 0.0;
  double equilibrium_seconds_ = 0.0;
  double unit_move_ = 1.5e-4;  // L-BFGS: the largest vertex move of a unit step along −∇ [m]
};

}  // namespace palpa::design
