// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/design/optimizer.hpp"

#include <ceres/gradient_problem.h>
#include <ceres/gradient_problem_solver.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <random>

#include "palpa/contact/contact.hpp"
#include "palpa/contact/detail/cgal_checks.hpp"
#include "palpa/contact/penalty.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/interrupt.hpp"
#include "palpa/core/json.hpp"
#include "palpa/core/parallel.hpp"
#include "palpa/core/ranks.hpp"
#include "palpa/core/stopwatch.hpp"
#include "palpa/design/checkpoint.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/mesh/csg.hpp"
#include "palpa/rest/adjoint.hpp"
#include "palpa/solve/blas.hpp"
#include "palpa/solve/ceres_termination.hpp"

namespace palpa::design {

namespace {

constexpr int kTrialNewtonIterations = 50;

// φ/φ0 over u = θ/c for Ceres. Exceptions (Ctrl-C) are kept and the
// evaluation reported as failed; the callback then stops the solver. The
// last few evaluations are kept, so that the callback can take the point
// the line search accepted (not always the last one it tried).
class ScaledObjective final : public ceres::FirstOrderFunction {
 public:
  using Evaluate_fn = std::function<Evaluation(const Eigen::VectorXd& theta, bool gradient)>;
  ScaledObjective(Evaluate_fn f, Eigen::Index n, double c, double phi0)
      : f_(std::move(f)), n_(n), c_(c), phi0_(phi0) {}
  bool Evaluate(const double* u, double* cost, double* gradient) const override {
    if (error_) return false;
    try {
      const Eigen::VectorXd theta = c_ * Eigen::Map<const Eigen::VectorXd>(u, n_);
      Evaluation e = f_(theta, gradient != nullptr);
      ++evaluations_;
      if (!e.ok) {
        spdlog::debug("design: a line-search trial failed, shorter step: {}", e.failure);
        return false;
      }
      *cost = e.phi / phi0_;
      if (gradient != nullptr) Eigen::Map<Eigen::VectorXd>(gradient, n_) = grad_of_(e) * (c_ / phi0_);
      if (recent_.size() == kKept) recent_.erase(recent_.begin());
      recent_.push_back({Eigen::Map<const Eigen::VectorXd>(u, n_), theta, std::move(e)});
      return true;
    } catch (...) {
      error_ = std::current_exception();
      return false;
    }
  }
  int NumParameters() const override { return static_cast<int>(n_); }
  void set_gradient_map(std::function<Eigen::VectorXd(const Evaluation&)> g) { grad_of_ = std::move(g); }
  // The newest evaluation with a gradient at exactly u, or null.
  struct Kept {
    Eigen::VectorXd u, theta;
    Evaluation evaluation;
  };
  Kept* find(const Eigen::VectorXd& u) const {
    for (auto it = recent_.rbegin(); it != recent_.rend(); ++it) {
      if (it->u == u && it->evaluation.gradient.rows() > 0) return &*it;
    }
    return nullptr;
  }
  mutable std::exception_ptr error_;
  mutable int evaluations_ = 0;

 private:
  Evaluate_fn f_;
  std::function<Eigen::VectorXd(const Evaluation&)> grad_of_;
  Eigen::Index n_;
  double c_, phi0_;
  static constexpr std::size_t kKept = 6;
  mutable std::vector<Kept> recent_;
};

class LbfgsCallback final : public ceres::IterationCallback {
 public:
  explicit LbfgsCallback(std::function<bool(const ceres::IterationSummary&)> f) : f_(std::move(f)) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    return f_(s) ? ceres::SOLVER_CONTINUE : ceres::SOLVER_ABORT;
  }

 private:
  std::function<bool(const ceres::IterationSummary&)> f_;
};

// Whether Ceres stopped because the objective fell by at most `tolerance`
// of itself in its last iteration (its function-tolerance test), rather than
// by its gradient or parameter tolerance: the figures of the last iteration
// decide, as in Ceres' own test.
bool function_tolerance_reached(const ceres::GradientProblemSolver::Summary& summary, double tolerance) {
  if (summary.iterations.empty()) return false;
  // The terminating iteration is the last one recorded when Ceres records it
  // before its tests (its cost is then the final cost); otherwise it follows
  // the last one recorded.
  const ceres::IterationSummary& last = summary.iterations.back();
  const bool recorded = summary.final_cost == last.cost;
  const double change = recorded ? last.cost_change : last.cost - summary.final_cost;
  const double previous = recorded ? last.cost + last.cost_change : last.cost;
  return std::abs(change) <= tolerance * std::abs(previous);
}

}  // namespace

DesignSpace::DesignSpace(const Eigen::MatrixX3d& X0, const Eigen::MatrixX3i& F, std::vector<int> vertices,
                         bool normal_only, double filter_radius)
    : X0_(X0), normals_(geometry::vertex_normals(SurfaceMesh{X0, F}, geometry::NormalWeighting::Area)), vertices_(std::move(vertices)), normal_only_(normal_only) {
  if (vertices_.empty()) {
    throw Error(ErrorKind::Input, "the design region holds no support vertex: nothing to optimize",
                {}, "a region around the contact");
  }
  for (int v : vertices_) {
    if (v < 0 || v >= X0_.rows()) {
      throw Error(ErrorKind::Input, fmt::format("design vertex {} is not a support vertex (0…{})", v, X0_.rows() - 1));
    }
  }
  filter_ = std::make_unique<DesignFilter>(SurfaceMesh{X0, F}, vertices_, filter_radius);
}

DesignSpace::~DesignSpace() = default;

double DesignSpace::filter_radius() const noexcept { return filter_->radius(); }

Eigen::MatrixX3d DesignSpace::moves(const Eigen::VectorXd& d) const {
  const auto n = static_cast<Eigen::Index>(vertices_.size());
  // θ as one row per design vertex, then filtered.
  const Eigen::MatrixXd S = filter_->apply(normal_only_ ? Eigen::MatrixXd(d)
                                                        : Eigen::MatrixXd(Eigen::Map<const Eigen::MatrixXd>(d.data(), 3, n).transpose()));
  Eigen::MatrixX3d M = Eigen::MatrixX3d::Zero(X0_.rows(), 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const int v = vertices_[static_cast<std::size_t>(i)];
    M.row(v) = normal_only_ ? Eigen::RowVector3d(S(i, 0) * normals_.row(v)) : Eigen::RowVector3d(S.row(i));
  }
  return M;
}

Eigen::MatrixX3d DesignSpace::shape(const Eigen::VectorXd& theta) const { return X0_ + moves(theta); }

Eigen::VectorXd DesignSpace::restrict(const Eigen::MatrixX3d& G) const {
  const auto n = static_cast<Eigen::Index>(vertices_.size());
  Eigen::MatrixXd R(n, normal_only_ ? 1 : 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const int v = vertices_[static_cast<std::size_t>(i)];
    if (normal_only_) {
      R(i, 0) = G.row(v).dot(normals_.row(v));
    } else {
      R.row(i) = G.row(v);
    }
  }
  const Eigen::MatrixXd T = filter_->apply_transpose(R);
  if (normal_only_) return T.col(0);
  const Eigen::MatrixXd Tt = T.transpose();  // 3 × n: θ's order, x y z per vertex
  return Eigen::Map<const Eigen::VectorXd>(Tt.data(), Tt.size());
}

double DesignSpace::max_move(const Eigen::VectorXd& d) const {
  const Eigen::MatrixX3d M = moves(d);
  double m = 0.0;
  for (int v : vertices_) m = std::max(m, M.row(v).norm());
  return m;
}

std::vector<rest::RestState> Evaluation::states() const {
  std::vector<rest::RestState> out;
  out.reserve(bodies.size());
  for (const BodyEvaluation& b : bodies) out.push_back(b.state);
  return out;
}

int Evaluation::newton_iterations() const {
  int n = 0;
  for (const BodyEvaluation& b : bodies) n += b.rest.newton_iterations;
  return n;
}

ShapeOptimizer::ShapeOptimizer(const rest::RestBody& body, const SurfaceMesh& support, const rest::RestOptions& rest,
                               std::vector<int> design_vertices, DesignOptions options)
    : ShapeOptimizer(std::vector<DesignBody>{DesignBody{{}, body, rest}}, support, std::move(design_vertices),
                     std::move(options)) {}

ShapeOptimizer::ShapeOptimizer(std::vector<DesignBody> bodies, const SurfaceMesh& support,
                               std::vector<int> design_vertices, DesignOptions options)
    : options_(std::move(options)) {
  if (options_.moves.empty()) throw Error(ErrorKind::Input, "no step lengths to try");
  for (double m : options_.moves) {
    if (!(m > 0.0) || !std::isfinite(m)) {
      throw Error(ErrorKind::Input, fmt::format("step lengths must be finite and > 0 m, got {}", m));
    }
  }
  if (options_.max_iterations < 0) throw Error(ErrorKind::Input, "the iteration limit must be ≥ 0");
  if (bodies.empty()) throw Error(ErrorKind::Input, "a design needs a body");
  if (bodies.size() > 1 && !options_.cohort) {
    throw Error(ErrorKind::Input, fmt::format("{} bodies on one support need a cohort objective", bodies.size()));
  }
  if (options_.cohort) cohort_value(*options_.cohort, Eigen::VectorXd::Ones(1));  // refuses bad settings now
  // Spread over ranks (core/ranks.hpp): body i on rank i mod ranks, each rank
  // with one body at least.
  ranks_ = options_.local ? 1 : ranks::size();
  rank_ = options_.local ? 0 : ranks::rank();
  const int ranks = ranks_;
  if (static_cast<std::size_t>(ranks) > bodies.size()) {
    throw Error(ErrorKind::Input, fmt::format("{} processes for {} bod{}: each process holds one body at least", ranks,
                                              bodies.size(), bodies.size() == 1 ? "y" : "ies"),
                {}, fmt::format("mpirun -np {} or fewer", bodies.size()));
  }
  unit_move_ = 0.5 * std::min_element(bodies.begin(), bodies.end(), [](const DesignBody& a, const DesignBody& b) {
                       return a.rest.target_penetration < b.rest.target_penetration;
                     })->rest.target_penetration;
  int threads = options_.threads;
  if (threads <= 0) {
    // Cores: this machine's, or fewer when palpa was told so (--threads).
    const std::size_t cores = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
    threads = static_cast<int>(std::min<std::size_t>(options_.moves.size(), std::max<std::size_t>(1, cores)));
  }
  threads = std::min(threads, static_cast<int>(options_.moves.size()));

  // Each body's initial equilibrium, with the automatic contact stiffness, on
  // the rank that holds it.
  const bool several = bodies.size() > 1;
  std::vector<BodyEvaluation> built(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    DesignBody& b = bodies[i];
    names_.push_back(b.name);
    rest_.push_back(b.rest);
    owner_.push_back(static_cast<int>(i % static_cast<std::size_t>(ranks)));
    if (owner_.back() != rank_) {
      bodies_.push_back(nullptr);
      continue;
    }
    built[i].ok = true;
    try {
      bodies_.push_back(std::make_unique<BodyProblem>(std::move(b), support, options_.score, threads,
                                                      kTrialNewtonIterations));
      equilibrium_seconds_ += bodies_.back()->equilibrium_seconds();
    } catch (const Error& e) {
      if (ranks == 1) {
        // A cohort's failure names its body; the run stops there.
        if (!several || e.kind() == ErrorKind::Interrupted) throw;
        throw Error(e.kind(), fmt::format("the body '{}': {}", names_.back(), e.what()));
      }
      built[i].error = e.kind();
      built[i].failure = e.what();
      bodies_.push_back(nullptr);
    }
  }
  if (ranks > 1) {
    share(built, false);
    for (std::size_t i = 0; i < built.size(); ++i) {
      if (built[i].error) throw Error(*built[i].error, fmt::format("the body '{}': {}", names_[i], built[i].failure));
    }
  }
  BodyProblem& first = *bodies_[static_cast<std::size_t>(rank_)];
  const Eigen::MatrixX3d X0 = first.simulation().support_rest_vertices();
  // A deformable support's base stays where it is.
  std::erase_if(design_vertices, [&](int v) { return first.simulation().support_vertex_fixed(v); });
  if (design_vertices.empty()) {
    throw Error(ErrorKind::Input, "no support vertex may move: the design region holds only the support's fixed base");
  }
  F_ = first.simulation().support().triangles();
  const Eigen::MatrixX3i& F = F_;
  const double radius = options_.filter_radius.value_or(kFilterEdges * design_edge_length(SurfaceMesh{X0, F}, design_vertices));
  space_ = std::make_unique<DesignSpace>(X0, F, std::move(design_vertices), options_.normal_only, radius);
  smoothness_ = std::make_unique<Smoothness>(F, X0.rows(), space_->vertices(), options_.taubin_iterations);

  // γ: γψ = ζ on the initial shape (a cohort's aggregate: 1), times 10^j.
  const double zeta0 = options_.cohort ? 1.0 : first.score().evaluate(first.simulation(), false).zeta;
  std::vector<rest::RestState> s0;
  for (const auto& b : bodies_) s0.push_back(b ? b->initial_state() : rest::RestState{});
  initial_ = evaluate(X0, s0, true, 0);
  if (!initial_.ok) throw Error(ErrorKind::Solver, "the initial shape: " + initial_.failure);
  // Each body's own ζ on the initial shape: a cohort's normalization.
  zeta0_.resize(static_cast<Eigen::Index>(bodies_.size()));
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    zeta0_[static_cast<Eigen::Index>(i)] = initial_.bodies[i].zeta;
    if (options_.cohort && !(initial_.bodies[i].zeta > 0.0)) {
      throw Error(ErrorKind::Input, fmt::format("the body '{}' does not touch the initial support (ζ = 0): a cohort "
                                                "normalizes each body's score by its value there",
                                                names_[i]));
    }
  }

  double psi0 = smoothness_->evaluate(X0);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> noise(-1e-4, 1e-4);
  Eigen::VectorXd rough(space_->size());
  for (Eigen::Index i = 0; i < rough.size(); ++i) rough[i] = noise(rng);
  // Per-vertex noise, not filtered: a roughness, whatever the filter.
  const DesignSpace raw(X0, F, space_->vertices(), options_.normal_only, 0.0);
  const double psi_ref = smoothness_->evaluate(raw.shape(rough));
  if (psi0 < 1e-3 * psi_ref) psi0 = psi_ref;
  if (options_.gamma) {
    if (!(*options_.gamma >= 0.0) || !std::isfinite(*options_.gamma)) {
      throw Error(ErrorKind::Input, fmt::format("the smoothing strength γ must be finite and ≥ 0, got {}", *options_.gamma));
    }
    gamma_ = *options_.gamma;
  } else {
    gamma_ = psi0 > 0.0 ? std::pow(10.0, options_.smoothing_exponent) * zeta0 / psi0 : 0.0;
  }
  // φ with γ (evaluate above used γ = 0).
  Eigen::MatrixX3d dpsi;
  initial_.psi = smoothness_->evaluate(X0, &dpsi);
  combine(initial_, &dpsi);
  if (!initial_.ok) throw Error(ErrorKind::Solver, "the initial shape: " + initial_.failure);
}

ShapeOptimizer::~ShapeOptimizer() = default;

BodyProblem& ShapeOptimizer::body(std::size_t i) {
  if (!bodies_.at(i)) {
    throw Error(ErrorKind::Internal, fmt::format("the body '{}' is held by rank {}", names_[i], owner_[i]));
  }
  return *bodies_[i];
}

BodyProblem& ShapeOptimizer::simulation_body() {
  for (auto& b : bodies_) {
    if (b) return *b;
  }
  throw Error(ErrorKind::Internal, "this rank holds no body");
}

void ShapeOptimizer::combine(Evaluation& ev, const Eigen::MatrixX3d* dpsi) const {
  ev.ok = true;
  for (std::size_t i = 0; i < ev.bodies.size(); ++i) {
    if (ev.bodies[i].ok) continue;
    ev.ok = false;
    ev.failure = bodies_.size() > 1 ? fmt::format("body '{}': {}", names_[i], ev.bodies[i].failure)
                                    : ev.bodies[i].failure;
    return;
  }
  const bool gradient = dpsi != nullptr;
  // Before the normalization is known (the initial shape), or one body: ζ itself.
  if (!options_.cohort || zeta0_.size() == 0) {
    ev.zeta = ev.bodies.front().zeta;
    if (gradient) ev.gradient = ev.bodies.front().gradient;
  } else {
    const auto n = static_cast<Eigen::Index>(ev.bodies.size());
    Eigen::VectorXd r(n), w;
    for (Eigen::Index i = 0; i < n; ++i) r[i] = ev.bodies[static_cast<std::size_t>(i)].zeta / zeta0_[i];
    ev.zeta = cohort_value(*options_.cohort, r, gradient ? &w : nullptr);
    if (gradient) {
      // Summed in the bodies' order: the same gradient however they were solved.
      ev.gradient = Eigen::MatrixX3d::Zero(ev.support.rows(), 3);
      for (Eigen::Index i = 0; i < n; ++i) {
        if (w[i] != 0.0) ev.gradient += (w[i] / zeta0_[i]) * ev.bodies[static_cast<std::size_t>(i)].gradient;
      }
    }
  }
  ev.phi = ev.zeta + gamma_ * ev.psi;
  if (gradient) ev.gradient += gamma_ * *dpsi;
  ev.ok = std::isfinite(ev.phi);
  if (!ev.ok) ev.failure = "the score is not finite";
}

Evaluation ShapeOptimizer::evaluate(const Eigen::MatrixX3d& X, const std::vector<rest::RestState>& warm, bool gradient,
                                    int slot) {
  // Several bodies factor at once: a multi-threaded BLAS under each of them
  // would oversubscribe the cores.
  std::optional<ScopedBlasThreads> blas;
  if (bodies_.size() > 1) blas.emplace(1);
  Pending p = evaluate_local(X, warm, gradient, slot);
  finish(p);
  return std::move(p.ev);
}

ShapeOptimizer::Pending ShapeOptimizer::evaluate_local(const Eigen::MatrixX3d& X,
                                                       const std::vector<rest::RestState>& warm, bool gradient,
                                                       int slot) {
  const auto t0 = Clock::now();
  Pending p;
  p.gradient = gradient;
  Evaluation& ev = p.ev;
  ev.support = X;
  if (warm.size() != bodies_.size()) {
    throw Error(ErrorKind::Internal, fmt::format("{} warm starts for {} bodies", warm.size(), bodies_.size()));
  }
  // A shape that crosses itself cannot be made (nor solved from scratch):
  // the trial fails, and a shorter step is tried. (Every rank finds the same.)
  if (const auto crossing = contact::detail::self_intersections(X, F_, 1); crossing.pairs > 0) {
    ev.failure = fmt::format("the support would cross itself (triangles {} and {})", crossing.first, crossing.second);
    p.crossed = true;
    ev.seconds = seconds_since(t0);
    return p;
  }
  ev.bodies.resize(bodies_.size());
  // This rank's bodies at once, each on its own simulation; each body's
  // result does not depend on how many are solved beside it. Spread over
  // ranks, an error is kept and raised once every rank has shared its bodies.
  const bool spread = ranks_ > 1;
  std::vector<std::size_t> mine;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (bodies_[i]) mine.push_back(i);
  }
  const auto one = [&](std::size_t i) {
    if (!spread) {
      ev.bodies[i] = bodies_[i]->evaluate(X, warm[i], gradient, slot);
      return;
    }
    try {
      ev.bodies[i] = bodies_[i]->evaluate(X, warm[i], gradient, slot);
    } catch (const Error& e) {
      ev.bodies[i].error = e.kind();
      ev.bodies[i].failure = e.what();
    } catch (const std::exception& e) {
      ev.bodies[i].error = ErrorKind::Internal;
      ev.bodies[i].failure = e.what();
    }
  };
  if (mine.size() == 1) {
    one(mine.front());
  } else {
    parallel_for_each_index(mine.size(), [&](std::size_t k) { one(mine[k]); });
  }
  ev.psi = smoothness_ ? smoothness_->evaluate(X, gradient ? &p.dpsi : nullptr) : 0.0;
  ev.seconds = seconds_since(t0);
  return p;
}

void ShapeOptimizer::broadcast(std::string& bytes, int root) const {
  if (ranks_ > 1) ranks::broadcast(bytes, root);
}

void ShapeOptimizer::share(std::vector<BodyEvaluation>& bodies, bool gradient) const {
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    std::string bytes;
    if (bodies_[i]) bytes = pack_shared(bodies[i], gradient);
    broadcast(bytes, owner_[i]);
    if (!bodies_[i]) bodies[i] = unpack_shared(bytes);
  }
}

void ShapeOptimizer::finish(Pending& p) const {
  Evaluation& ev = p.ev;
  if (p.crossed) return;
  if (ranks_ > 1) {
    share(ev.bodies, p.gradient);
    for (std::size_t i = 0; i < ev.bodies.size(); ++i) {
      if (ev.bodies[i].error) throw Error(*ev.bodies[i].error, ev.bodies[i].failure);
    }
  }
  for (const BodyEvaluation& b : ev.bodies) ev.adjoint_seconds += b.adjoint_seconds;
  combine(ev, p.gradient ? &p.dpsi : nullptr);
}

Evaluation solve_from_scratch(const rest::RestBody& body, const SurfaceMesh& support, const rest::RestOptions& rest,
                              const ScoreOptions& score_options, std::unique_ptr<rest::RestSimulation>* keep) {
  const auto t0 = Clock::now();
  // A shape that rose into where the scene places the body: the body is
  // lifted clear of it first (then lowered by its weight as from anywhere).
  rest::RestBody placed = body;
  if (const double lift = rest::place_clear_of(placed, support, -rest.gravity, 1e-3); lift > 0.0) {
    spdlog::info("design: the body starts inside this support: lifted {:.3g} mm before it is lowered onto it", lift * 1e3);
  }
  auto sim = std::make_unique<rest::RestSimulation>(placed, support, rest);
  Evaluation ev;
  ev.support = sim->support_rest_vertices();
  BodyEvaluation& b = ev.bodies.emplace_back();
  try {
    b.rest = sim->solve();
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Solver) throw;
    ev.failure = b.failure = e.what();
    return ev;
  }
  const ErgonomicScore score(*sim, score_options);
  b.score = score.evaluate(*sim, false);
  b.zeta = ev.zeta = ev.phi = b.score.zeta;
  b.state = sim->state();
  b.ok = ev.ok = std::isfinite(ev.zeta);
  b.seconds = ev.seconds = seconds_since(t0);
  if (keep != nullptr) *keep = std::move(sim);
  return ev;
}

std::vector<Evaluation> ShapeOptimizer::evaluate_all(const std::vector<Eigen::MatrixX3d>& shapes,
                                                     const std::vector<rest::RestState>& warm) {
  std::vector<Pending> pending(shapes.size());
  const int slots = simulation_body().slots();
  // The trials factor concurrently, one per core: a multi-threaded BLAS under
  // each of them would oversubscribe the cores.
  const ScopedBlasThreads one_blas_thread(slots > 1 || bodies_.size() > 1 ? 1 : blas_threads());
  parallel_for_each_index(static_cast<std::size_t>(slots), [&](std::size_t s) {
    for (std::size_t i = s; i < shapes.size(); i += static_cast<std::size_t>(slots)) {
      pending[i] = evaluate_local(shapes[i], warm, true, static_cast<int>(s));
    }
  });
  // Shared between the ranks, one shape after another, from this thread.
  std::vector<Evaluation> out;
  out.reserve(shapes.size());
  for (Pending& p : pending) {
    finish(p);
    out.push_back(std::move(p.ev));
  }
  return out;
}

DesignResult ShapeOptimizer::run(const std::function<void(const IterationRecord&)>& progress) {
  const auto t0 = Clock::now();
  DesignResult result;
  result.initial = initial_;
  result.gamma = gamma_;
  result.equilibrium_seconds = equilibrium_seconds_;
  result.evaluations = 1;
  result.newton_iterations = initial_.newton_iterations();

  Eigen::VectorXd theta = Eigen::VectorXd::Zero(space_->size());
  Evaluation base = initial_;
  Eigen::VectorXd g = space_->restrict(base.gradient);
  Eigen::VectorXd d = -g;
  bool steepest = true;
  int first = 1;
  double earlier_seconds = 0.0;  // a resumed run: the seconds before the resume
  // Per body: its contact model could not be chosen anew, it stays frozen.
  std::vector<bool> refreeze_failed(bodies_.size(), false);

  // This run's checkpoint as it would stand now; `like` for reading one.
  const auto checkpoint = [&](int iteration) {
    DesignCheckpoint c;
    c.method = options_.method;
    c.gamma = gamma_;
    c.moves = options_.moves;
    c.filter_radius = space_->filter_radius();
    c.iteration = iteration;
    c.theta = theta;
    c.direction = d;
    c.gradient = g;
    c.steepest = steepest;
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      c.bodies.push_back({names_[i], base.bodies[i].state, base.bodies[i].rest.max_penetration,
                          refreeze_failed[i]});
    }
    c.phi = base.phi;
    c.zeta = base.zeta;
    c.psi = base.psi;
    c.history = result.history;
    c.evaluations = result.evaluations;
    c.newton_iterations = result.newton_iterations;
    c.seconds = earlier_seconds + seconds_since(t0);
    return c;
  };
  if (options_.resume) {
    if (options_.checkpoint.empty()) throw Error(ErrorKind::Input, "--resume needs a checkpoint file");
    const DesignCheckpoint c = read_design_checkpoint(options_.checkpoint, checkpoint(0));
    earlier_seconds = c.seconds;
    theta = c.theta;
    d = c.direction;
    g = c.gradient;
    steepest = c.steepest;
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      base.bodies[i].state = c.bodies[i].state;
      base.bodies[i].rest.max_penetration = c.bodies[i].max_penetration;
      refreeze_failed[i] = c.bodies[i].refreeze_failed;
    }
    base.support = space_->shape(theta);
    accepted_ = base.support;
    base.phi = c.phi;
    base.zeta = c.zeta;
    base.psi = c.psi;
    result.history = c.history;
    result.evaluations = c.evaluations;
    result.newton_iterations = c.newton_iterations;
    first = c.iteration + 1;
    result.resumed = true;
    spdlog::info("design: resuming after iteration {} (φ = {:.6g})", first - 1, base.phi);
  }

  auto save = [&](int iteration) {
    accepted_ = base.support;
    if (options_.checkpoint.empty()) return;
    DesignCheckpoint c = checkpoint(iteration);
    // Rank 0 writes it, with every body's state from the rank that holds it.
    for (std::size_t i = 0; i < bodies_.size() && ranks_ > 1; ++i) {
      if (owner_[i] == 0) continue;
      std::string bytes;
      if (bodies_[i]) bytes = pack_state(c.bodies[i].state);
      broadcast(bytes, owner_[i]);
      if (rank_ == 0) c.bodies[i].state = unpack_state(bytes);
    }
    if (rank_ == 0) write_json_file(options_.checkpoint, checkpoint_json(c));
  };

  // The contact model follows the design: when an accepted shape's deepest
  // penetration leaves the band the automatic stiffness rule accepts, k (and
  // the spring areas) are chosen anew there, as a solve from scratch chooses
  // them, and φ and its gradient are measured again with them; the search
  // direction restarts. So the optimizer's φ stays the from-scratch φ within
  // that band, and it cannot gain by letting the frozen springs sink deeper.
  // (Each body's band is its own rank's to judge.)
  auto out_of_band_body = [&](const Evaluation& e, std::size_t i) {
    if (refreeze_failed[i]) return false;
    const bool out = bodies_[i] && bodies_[i]->out_of_band(e.bodies[i].rest.max_penetration);
    return ranks_ > 1 ? ranks::broadcast_flag(out, owner_[i]) : out;
  };
  auto out_of_band = [&](const Evaluation& e) {
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      if (out_of_band_body(e, i)) return true;
    }
    return false;
  };
  auto named = [&](std::size_t i) {
    return bodies_.size() > 1 ? fmt::format(" (body '{}')", names_[i]) : std::string();
  };
  auto refreeze = [&](int it) {
    std::vector<rest::RestState> warm = base.states();
    std::vector<std::size_t> chosen;
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      if (!out_of_band_body(base, i)) continue;
      // On the rank that holds the body; what came of it, to every rank:
      // its Newton iterations, or why it failed (an error other than a
      // failed solve is raised on every rank).
      std::string outcome;
      if (bodies_[i]) {
        try {
          const rest::RestResult r = bodies_[i]->refreeze(base.support, base.bodies[i].state);
          warm[i] = bodies_[i]->simulation().state();
          outcome = fmt::format("ok {}", r.newton_iterations);
        } catch (const Error& e) {
          if (ranks_ == 1 && e.kind() != ErrorKind::Solver) throw;
          outcome = e.kind() == ErrorKind::Solver ? fmt::format("failed {}", e.what())
                                                  : fmt::format("error{} {}", static_cast<int>(e.kind()), e.what());
        }
      }
      broadcast(outcome, owner_[i]);
      if (outcome.starts_with("ok ")) {
        ++result.evaluations;
        result.newton_iterations += std::stoi(outcome.substr(3));
        chosen.push_back(i);
      } else if (outcome.starts_with("failed ")) {
        spdlog::warn("design: the contact model could not be chosen anew at iteration {}{} ({}); it stays frozen", it,
                     named(i), outcome.substr(7));
        refreeze_failed[i] = true;
      } else {
        const std::size_t space = outcome.find(' ');
        throw Error(static_cast<ErrorKind>(std::stoi(outcome.substr(5, space - 5))), outcome.substr(space + 1));
      }
    }
    if (chosen.empty()) return;
    Evaluation again = evaluate(base.support, warm, true, 0);
    ++result.evaluations;
    if (!again.ok) {
      spdlog::warn("design: the contact model chosen anew at iteration {} fails ({}); it stays frozen", it, again.failure);
      for (std::size_t i : chosen) refreeze_failed[i] = true;
      return;
    }
    result.newton_iterations += again.newton_iterations();
    for (std::size_t i : chosen) {
      spdlog::info("design: iteration {}{}: penetration {:.2f}× the target, contact stiffness chosen anew: "
                   "k {:.4g} → {:.4g}",
                   it, named(i), base.bodies[i].rest.max_penetration / rest_[i].target_penetration,
                   base.bodies[i].state.stiffness, again.bodies[i].state.stiffness);
    }
    spdlog::info("design: iteration {}: φ {:.6g} → {:.6g} with the contact model chosen anew", it, base.phi, again.phi);
    base = std::move(again);
    g = space_->restrict(base.gradient);
    d = -g;
    steepest = true;
    ++result.refreezes;
    if (!result.history.empty()) {
      result.history.back().refrozen = true;
      result.history.back().stiffness = base.body().state.stiffness;
    }
    save(it);
  };

  result.stop = Stop{Termination::IterationLimit, fmt::format("the iteration limit ({})", options_.max_iterations)};
  int iteration = first - 1;
  // A run killed between an iteration's checkpoint and the refreeze that
  // follows it refreezes now, as the uninterrupted run did then.
  if (result.resumed && out_of_band(base)) refreeze(iteration);
  // One iteration of the ladder of step lengths along d (CG, and L-BFGS's
  // fallback when its line search stalls). Returns 0 when a step was taken,
  // 1 when it was taken but φ barely fell, 2 when no step lowers φ.
  auto ladder = [&](int it) -> int {
    check_interrupt();
    const auto ti = Clock::now();
    IterationRecord rec;
    rec.iteration = it;
    int best = -1;
    std::vector<Evaluation> trials;
    Eigen::VectorXd step;
    for (int attempt = 0; attempt < 2; ++attempt) {
      if (g.dot(d) >= 0.0 && !steepest) {
        d = -g;
        steepest = true;
        rec.restarted = true;
      }
      const double m = space_->max_move(d);
      if (!(m > 0.0)) break;
      std::vector<Eigen::MatrixX3d> shapes;
      std::vector<Eigen::VectorXd> steps;
      for (double move : options_.moves) {
        steps.push_back(theta + (move / m) * d);
        shapes.push_back(space_->shape(steps.back()));
      }
      trials = evaluate_all(shapes, base.states());
      rec.evaluations += static_cast<int>(trials.size());
      result.evaluations += static_cast<int>(trials.size());
      for (std::size_t i = 0; i < trials.size(); ++i) {
        if (trials[i].ok) result.newton_iterations += trials[i].newton_iterations();
        if (trials[i].ok && trials[i].phi < base.phi && (best < 0 || trials[i].phi < trials[static_cast<std::size_t>(best)].phi)) {
          best = static_cast<int>(i);
        }
      }
      if (best >= 0) {
        step = steps[static_cast<std::size_t>(best)];
        rec.move = options_.moves[static_cast<std::size_t>(best)];
        break;
      }
      if (steepest) break;
      d = -g;
      steepest = true;
      rec.restarted = true;
    }
    if (best < 0) {
      result.stop = space_->max_move(d) > 0.0
                        ? Stop{Termination::NoProgress, "no step length lowers φ along the steepest descent"}
                        : Stop{Termination::Converged, "the gradient vanishes"};
      return 2;
    }
    Evaluation& next = trials[static_cast<std::size_t>(best)];
    const Eigen::VectorXd g_next = space_->restrict(next.gradient);
    const double beta = std::max(0.0, g_next.dot(g_next - g) / std::max(g.squaredNorm(), 1e-300));
    d = -g_next + beta * d;
    steepest = beta == 0.0;
    g = g_next;
    theta = step;
    const double decrease = base.phi - next.phi;
    const double previous = base.phi;
    base = std::move(next);
    rec.phi = base.phi;
    rec.zeta = base.zeta;
    rec.psi = base.psi;
    rec.stiffness = base.body().state.stiffness;
    rec.seconds = seconds_since(ti);
    result.history.push_back(rec);
    iteration = it;
    save(it);
    spdlog::info("design: iteration {}: φ = {:.6g} (ζ = {:.6g}, γψ = {:.3g}), step {:.3g} mm, {} equilibria, {:.1f} s",
                 it, base.phi, base.zeta, gamma_ * base.psi, rec.move * 1e3, rec.evaluations, rec.seconds);
    if (progress) progress(rec);
    if (decrease < options_.min_relative_decrease * std::abs(previous)) {
      result.stop = Stop{Termination::Converged,
                         fmt::format("φ fell by less than {:.3g} of itself", options_.min_relative_decrease)};
      return 1;
    }
    return 0;
  };

  // L-BFGS runs until its line search gives up (contact changes make φ only
  // piecewise smooth, and stale curvature pairs then mislead it); it is then
  // restarted from where it stopped with a fresh memory, until a restart
  // makes no progress.
  while (options_.method == DesignMethod::Lbfgs && iteration < options_.max_iterations) {
    // Scale: a unit step along −∇ moves the support by at most half the
    // target penetration, so that no contact changes by more than that.
    const double gmax = std::max(space_->max_move(g), 1e-300);
    const double phi0 = std::abs(base.phi);
    const double c = std::sqrt(unit_move_ * phi0 / gmax);
    std::vector<rest::RestState> warm = base.states();
    const double max_step = *std::max_element(options_.moves.begin(), options_.moves.end());
    auto* objective = new ScaledObjective(
        [&](const Eigen::VectorXd& th, bool with_gradient) {
          // Steps longer than the ladder's longest are refused without a
          // solve: Ceres then backtracks (a trust region of sorts).
          if (space_->max_move(th - theta) > max_step) {
            Evaluation refused;
            refused.failure = "longer than the longest step";
            return refused;
          }
          // Every trial starts from the accepted point: φ of a shape does
          // not depend on the trials before it.
          Evaluation e = evaluate(space_->shape(th), warm, with_gradient, 0);
          ++result.evaluations;
          if (e.ok) result.newton_iterations += e.newton_iterations();
          return e;
        },
        space_->size(), c, phi0);
    objective->set_gradient_map([&](const Evaluation& e) { return Eigen::VectorXd(space_->restrict(e.gradient)); });
    ceres::GradientProblem problem(objective);  // owns it
    Eigen::VectorXd u = theta / c;
    auto ti = Clock::now();
    int evaluations_before = 0;
    bool refreeze_pending = false;
    const int start = iteration;
    LbfgsCallback callback([&](const ceres::IterationSummary& sum) {
      if (objective->error_) return false;
      if (sum.iteration == 0 || !sum.step_is_successful) return true;
      ++iteration;
      // The accepted point: Ceres has written it to u.
      if (ScaledObjective::Kept* k = objective->find(u)) {
        base = std::move(k->evaluation);
        theta = k->theta;
      } else {
        theta = c * u;
        base = evaluate(space_->shape(theta), warm, true, 0);
        ++result.evaluations;
        if (!base.ok) throw Error(ErrorKind::Solver, "the point L-BFGS accepted: " + base.failure);
        result.newton_iterations += base.newton_iterations();
      }
      warm = base.states();
      g = space_->restrict(base.gradient);
      d = -g;
      IterationRecord rec;
      rec.iteration = iteration;
      rec.phi = base.phi;
      rec.zeta = base.zeta;
      rec.psi = base.psi;
      rec.stiffness = base.body().state.stiffness;
      rec.move = sum.step_norm * c;
      rec.evaluations = objective->evaluations_ - evaluations_before;
      rec.restarted = iteration == start + 1 && start > first - 1;
      evaluations_before = objective->evaluations_;
      rec.seconds = seconds_since(ti);
      ti = Clock::now();
      result.history.push_back(rec);
      save(iteration);
      spdlog::info("design: iteration {} (L-BFGS): φ = {:.6g} (ζ = {:.6g}, γψ = {:.3g}), {} evaluations, {:.1f} s",
                   iteration, base.phi, base.zeta, gamma_ * base.psi, rec.evaluations, rec.seconds);
      if (progress) progress(rec);
      if (out_of_band(base)) {
        refreeze_pending = true;
        return false;
      }
      return !interrupt_requested();
    });
    ceres::GradientProblemSolver::Options so;
    so.line_search_direction_type = ceres::LBFGS;
    so.max_num_iterations = options_.max_iterations - iteration;
    so.function_tolerance = options_.min_relative_decrease;
    so.gradient_tolerance = 1e-14;
    so.parameter_tolerance = 1e-14;
    so.logging_type = ceres::SILENT;
    so.update_state_every_iteration = true;  // the callback reads the accepted point from u
    so.callbacks.push_back(&callback);
    ceres::GradientProblemSolver::Summary summary;
    ceres::Solve(so, problem, u.data(), &summary);
    if (objective->error_) std::rethrow_exception(objective->error_);
    check_interrupt();
    if (refreeze_pending) {
      refreeze(iteration);
      continue;  // a fresh L-BFGS on the new contact model
    }
    result.stop = Stop{termination_of(summary.termination_type), "L-BFGS: " + summary.message};
    if (summary.termination_type == ceres::CONVERGENCE && function_tolerance_reached(summary, so.function_tolerance)) {
      break;  // φ fell by less than min_relative_decrease
    }
    if (iteration >= options_.max_iterations) break;
    // Stalled: one ladder step along the steepest descent, then a fresh start.
    spdlog::info("design: L-BFGS stalled at iteration {}; one step of the ladder, then a fresh start", iteration);
    d = -g;
    steepest = true;
    if (ladder(iteration + 1) != 0) break;
    if (out_of_band(base)) refreeze(iteration);
  }
  for (int it = first; options_.method == DesignMethod::ConjugateGradient && it <= options_.max_iterations; ++it) {
    if (ladder(it) != 0) break;
    if (out_of_band(base)) refreeze(it);
  }
  result.iterations = iteration;

  if (out_of_band(base)) refreeze(iteration);
  // The optimized shape, solved once more so that simulation 0 holds it.
  result.final = evaluate(base.support, base.states(), false, 0);
  ++result.evaluations;
  if (!result.final.ok) throw Error(ErrorKind::Solver, "the optimized shape: " + result.final.failure);
  if (options_.post_smoothing > 0) {
    SurfaceMesh m{base.support, F_};
    std::vector<bool> movable(static_cast<std::size_t>(m.V.rows()), false);
    for (int v : space_->vertices()) movable[static_cast<std::size_t>(v)] = true;
    mesh::taubin_smooth(m, options_.post_smoothing, &movable);
    Evaluation smoothed = evaluate(m.V, base.states(), false, 0);
    ++result.evaluations;
    if (!smoothed.ok) throw Error(ErrorKind::Solver, "the post-smoothed shape: " + smoothed.failure);
    result.before_post_smoothing = std::move(result.final);
    result.final = std::move(smoothed);
  }
  result.seconds = earlier_seconds + seconds_since(t0);
  return result;
}

}  // namespace palpa::design
