// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/fit/fit.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>

#include "palpa/core/error.hpp"
#include "palpa/core/parallel.hpp"
#include "palpa/fit/checkpoint.hpp"
#include "palpa/fit/optimize.hpp"
#include "palpa/material/models.hpp"
#include "palpa/material/registry.hpp"

namespace palpa::fit {

using material::Material;

std::string_view to_string(Optimizer o) noexcept {
  return o == Optimizer::LevenbergMarquardt ? "lm" : "nlcg";
}

std::string_view to_string(DepthFrom f) noexcept { return f == DepthFrom::SmallIndentation ? "small" : "whole"; }

DepthFrom parse_depth_from(std::string_view name) {
  if (name == "small") return DepthFrom::SmallIndentation;
  if (name == "whole") return DepthFrom::WholeCurves;
  throw_input_error(fmt::format("unknown depth choice '{}'", name), ErrorContext{"", 0, 0, "depth-from"},
                    "\"small\" (the small-indentation part of the curves) or \"whole\" (every point)");
}

Optimizer parse_optimizer(std::string_view name) {
  if (name == "lm") return Optimizer::LevenbergMarquardt;
  if (name == "nlcg") return Optimizer::Nlcg;
  throw_input_error(fmt::format("unknown optimizer '{}'", name), ErrorContext{"", 0, 0, "optimizer"},
                    "\"lm\" (Levenberg-Marquardt) or \"nlcg\" (nonlinear conjugate gradients)");
}

std::unique_ptr<Material> scaled_material(const Material& m, double s) {
  auto out = m.clone();
  Eigen::VectorXd theta = m.params();
  for (Eigen::Index k = 0; k < theta.size(); ++k) {
    const Dimension dim = m.param_info(k).dimension;
    if (dim == Dimension::Pressure) theta[k] *= s;
    if (dim == Dimension::Compliance) theta[k] /= s;
  }
  out->set_params(theta);
  return out;
}

namespace {

// The weighted `q` and 1 − q quantiles of (value, weight) pairs.
std::pair<double, double> weighted_range(std::vector<std::pair<double, double>> v, double q) {
  std::sort(v.begin(), v.end());
  double total = 0.0;
  for (const auto& [x, w] : v) total += w;
  if (v.empty()) return {1.0, 1.0};
  if (!(total > 0.0) || q <= 0.0) return {v.front().first, v.back().first};
  double lo = v.front().first, hi = v.back().first, acc = 0.0;
  bool lo_set = false;
  for (const auto& [x, w] : v) {
    acc += w;
    if (!lo_set && acc >= q * total) {
      lo = x;
      lo_set = true;
    }
    if (acc <= (1.0 - q) * total) hi = x;
  }
  return {lo, hi};
}

}  // namespace

material::SplineLayout layout_covering(const std::vector<CurvePrediction::StretchSample>& stretches,
                                       const material::SplineLayout& base, double tail) {
  if (stretches.empty()) return base;
  std::vector<std::pair<double, double>> fv, gv, hv;
  for (const auto& s : stretches) {
    const Eigen::Vector3d& l = s.stretches;
    if (!(l.minCoeff() > 0.0) || !l.allFinite()) continue;  // inverted or broken: not the material's range
    const double w = std::max(s.weight, 0.0);
    for (int i = 0; i < 3; ++i) {
      fv.emplace_back(l[i], w);
      gv.emplace_back(l[i] * l[(i + 1) % 3], w);
    }
    hv.emplace_back(l.prod(), w);
  }
  const auto [f0, f1] = weighted_range(fv, tail);
  const auto [g0, g1] = weighted_range(gv, tail);
  const auto [h0, h1] = weighted_range(hv, tail);
  const double f_lo = std::min(0.9, f0), f_hi = std::max(1.1, f1);
  const double g_lo = std::min(0.9, g0), g_hi = std::max(1.1, g1);
  const double h_lo = std::min(0.9, h0), h_hi = std::max(1.1, h1);
  // A natural spline has zero curvature at its end knots, which distorts the
  // stress (its slope) in the end intervals: the knots reach one interval
  // beyond the data on each side (log-uniform spacing over n − 3 intervals
  // across the data).
  // Never narrower than `base`: curves the fit did not train on (a smaller
  // punch, a deeper poke) reach further, and inside the knots the curvature
  // regularization keeps the unseen parts near the stage-1 material, which
  // extrapolates far better than a spline's parabolic continuation.
  const auto widen = [](double lo, double hi, const material::SplineRange& b) {
    const double step = std::log(hi / lo) / std::max(1, b.knots - 3);
    return material::SplineRange{std::min(b.lo, lo * std::exp(-step)), std::max(b.hi, hi * std::exp(step)), b.knots};
  };
  material::SplineLayout out = base;
  out.f = widen(f_lo, f_hi, base.f);
  out.g = widen(g_lo, g_hi, base.g);
  out.h = widen(h_lo, h_hi, base.h);
  return out;
}

std::vector<Stage2Start> stage2_starts(const Material& stage1, const FitOptions& o,
                                       const material::SplineLayout& layout) {
  const material::ElasticConstants c = material::small_strain_constants(stage1);
  const double mu = c.mu;
  const double nu = std::clamp(c.poisson(), -0.9, 0.499);
  const double bulk = c.bulk();
  const std::string& m = o.model;
  std::vector<Stage2Start> out;
  const auto add = [&](std::string label, std::unique_ptr<Material> material) {
    out.push_back(Stage2Start{std::move(label), std::move(material)});
  };
  if (m == stage1.model()) {
    add("stage 1", stage1.clone());
  } else if (m == "spline") {
    add("stage 1 sampled",
        std::make_unique<material::SplineMaterial>(material::SplineMaterial::fit_stresses(stage1, layout)));
    // A shape that stiffens in tension, with stage 1's constants.
    const material::Ogden stiffening({2.0 * mu / 5.0}, {5.0}, nu);
    add("Ogden alpha 5 sampled",
        std::make_unique<material::SplineMaterial>(material::SplineMaterial::fit_stresses(stiffening, layout)));
  } else if (m == "neo-hookean") {
    add("stage 1 constants", std::make_unique<material::NeoHookean>(c.young(), nu));
  } else if (m == "neo-hookean-volume") {
    for (const double share : {0.0, 0.5}) {
      add(fmt::format("volume_share {:g}", share),
          std::make_unique<material::NeoHookean>(material::NeoHookean::with_volume_term(c.young(), nu, share)));
    }
  } else if (m == "neo-hookean-isochoric") {
    add("stage 1 constants", std::make_unique<material::IsochoricInvariant>(
                                 material::IsochoricInvariant::neo_hookean(0.5 * mu, 2.0 / bulk)));
  } else if (m == "mooney-rivlin") {
    for (const double share : {0.0, 0.1, 0.5}) {
      add(fmt::format("C01 {:g} of mu0/2", share),
          std::make_unique<material::IsochoricInvariant>(
              material::IsochoricInvariant::mooney_rivlin((1.0 - share) * 0.5 * mu, share * 0.5 * mu, 2.0 / bulk)));
    }
  } else if (m == "yeoh") {
    add("C20 = C30 = 0", std::make_unique<material::IsochoricInvariant>(
                             material::IsochoricInvariant::yeoh(0.5 * mu, 0.0, 0.0, 2.0 / bulk)));
  } else if (m == "ogden") {
    const int n = o.ogden_terms;
    if (n < 1 || n > 6) {
      throw_input_error(fmt::format("{} Ogden terms", n), ErrorContext{"", 0, 0, "ogden-terms"}, "1 to 6 terms");
    }
    static constexpr double kSets[3][6] = {
        {2.0, 5.0, -2.0, 8.0, -4.0, 10.0}, {4.0, -2.0, 8.0, 2.0, -4.0, 12.0}, {-2.0, 3.0, 10.0, -4.0, 6.0, 2.0}};
    // μ0 = ½ Σ μp αp: term p carries share[p] of it.
    const auto ogden = [&](const double* alpha, const std::vector<double>& share) {
      std::vector<double> mus, alphas;
      for (int p = 0; p < n; ++p) {
        alphas.push_back(alpha[p]);
        mus.push_back(2.0 * mu * share[static_cast<std::size_t>(p)] / alpha[p]);
      }
      std::string label = "alpha";
      for (int p = 0; p < n; ++p) label += fmt::format("{}{:g}", p ? ", " : " ", alpha[p]);
      return std::pair{label, std::make_unique<material::Ogden>(mus, alphas, nu)};
    };
    std::vector<double> first(static_cast<std::size_t>(n), 0.0);
    first[0] = 1.0;
    auto [label0, projection] = ogden(kSets[0], first);
    add(label0 + (n > 1 ? " (stage 1: the first term only)" : " (stage 1)"), std::move(projection));
    const std::vector<double> equal(static_cast<std::size_t>(n), 1.0 / n);
    for (int set = n > 1 ? 0 : 1; set < 3; ++set) {
      auto [label, material] = ogden(kSets[set], equal);
      add(label, std::move(material));
    }
  } else {
    material::model_spec(m, ErrorContext{"", 0, 0, "model"}, true);  // names the fittable models
    throw_input_error(fmt::format("no stage-2 start for model '{}'", m), ErrorContext{"", 0, 0, "model"});
  }
  return out;
}

std::unique_ptr<Material> stage2_start(const Material& stage1, const FitOptions& o,
                                       const material::SplineLayout& layout) {
  return std::move(stage2_starts(stage1, o, layout).front().material);
}

double sum_of_squares(const MeasuredCurve& c, const CurvePrediction& p) {
  double s = 0.0;
  for (std::size_t j = 0; j < c.y.size(); ++j) {
    if (std::isfinite(p.y[j])) s += (p.y[j] - c.y[j]) * (p.y[j] - c.y[j]);
  }
  return s;
}

std::size_t compared_points(const MeasuredCurve& c, const CurvePrediction& p) {
  std::size_t n = 0;
  for (std::size_t j = 0; j < c.y.size(); ++j) n += std::isfinite(p.y[j]) ? 1 : 0;
  return n;
}

double rms_error(const MeasuredCurve& c, const CurvePrediction& p) {
  const std::size_t n = compared_points(c, p);
  return n == 0 ? std::numeric_limits<double>::quiet_NaN() : std::sqrt(sum_of_squares(c, p) / static_cast<double>(n));
}

std::vector<CurvePrediction> predict_curves(const Dataset& d, double layer_depth, const Material& m,
                                            const SimulationOptions& o) {
  return std::move(predict_curves(d, layer_depth, std::vector<const Material*>{&m}, o).front());
}

std::vector<std::vector<CurvePrediction>> predict_curves(
    const Dataset& d, double layer_depth, const std::vector<const Material*>& materials, const SimulationOptions& o,
    const std::function<void(std::size_t material, std::size_t curve)>& on_curve) {
  const std::size_t n = d.curves.size();
  std::vector<std::vector<CurvePrediction>> out(materials.size(), std::vector<CurvePrediction>(n));
  parallel_for_each_index(materials.size() * n, [&](std::size_t k) {
    const std::size_t m = k / n, i = k % n;
    auto sim = make_curve_simulator(d, d.curves[i], layer_depth, o);
    sim->allow_partial(true);
    out[m][i] = sim->predict(*materials[m], false);
    if (on_curve) on_curve(m, i);
  });
  return out;
}


// ---------------------------------------------------------------------------

namespace {

// Stage 1 on one layer depth: ε of the initial material and the best scale.
struct Stage1 {
  std::vector<CurvePrediction::StretchSample> stretches;  // of the deepest states
  double scale = 1.0;
  double sum_sim_squared = 0.0;  // Σ y_sim² (the scale's curvature)
  double objective_initial = 0.0;
  double objective_scaled = 0.0;
};

Stage1 fit_modulus(const Dataset& d, double layer_depth, const Material& initial, const SimulationOptions& so) {
  std::vector<const MeasuredCurve*> train;
  for (const auto& c : d.curves) {
    if (c.role == CurveRole::Train) train.push_back(&c);
  }
  std::vector<CurvePrediction> preds(train.size());
  parallel_for_each_index(train.size(), [&](std::size_t i) {
    auto sim = make_curve_simulator(d, *train[i], layer_depth, so);
    sim->record_stretches(true);
    preds[i] = sim->predict(initial, false);
  });
  double sy = 0.0, yy = 0.0;
  Stage1 s;
  for (std::size_t i = 0; i < train.size(); ++i) {
    for (std::size_t j = 0; j < train[i]->y.size(); ++j) {
      sy += preds[i].y[j] * train[i]->y[j];
      yy += preds[i].y[j] * preds[i].y[j];
    }
    s.objective_initial += sum_of_squares(*train[i], preds[i]);
  }
  if (!(yy > 0.0) || !(sy > 0.0)) {
    throw_solver_error(fmt::format("the modulus cannot be fitted at layer depth {} mm: the simulated and measured "
                                   "training curves do not correlate (Σ y_sim·y_meas = {:.3g})",
                                   layer_depth * 1e3, sy));
  }
  s.scale = sy / yy;
  s.sum_sim_squared = yy;
  for (std::size_t i = 0; i < train.size(); ++i) {
    for (std::size_t j = 0; j < train[i]->y.size(); ++j) {
      const double r = s.scale * preds[i].y[j] - train[i]->y[j];
      s.objective_scaled += r * r;
    }
    s.stretches.insert(s.stretches.end(), preds[i].stretches.begin(), preds[i].stretches.end());
  }
  return s;
}

std::unique_ptr<Material> default_initial(const Dataset& d) {
  return std::make_unique<material::NeoHookean>(10e3, d.poisson);
}

// The training curves cut to d ≤ kSmallIndentation·min(a, D_min), each kept
// if it has two points beyond zero there; cut[i]: the deepest point kept per
// training curve (0 if left out). Nothing when fewer than kMinSmallPoints
// points beyond zero are left: too few to choose a depth on.
constexpr int kMinSmallPoints = 6;
std::optional<Dataset> small_indentation_part(const Dataset& d, std::vector<double>& cut) {
  Dataset s = d;
  s.curves.clear();
  const double d_min = *std::min_element(d.layer_depths.begin(), d.layer_depths.end());
  int points = 0;
  for (const auto& c : d.curves) {
    if (c.role != CurveRole::Train) continue;
    const double limit = kSmallIndentation * std::min(c.radius, d_min) * (1.0 + 1e-9);
    MeasuredCurve k = c;
    k.x.clear();
    k.y.clear();
    for (std::size_t j = 0; j < c.x.size(); ++j) {
      if (c.x[j] > limit) break;
      k.x.push_back(c.x[j]);
      k.y.push_back(c.y[j]);
    }
    int nonzero = 0;
    for (double x : k.x) nonzero += x > 0.0 ? 1 : 0;
    cut.push_back(nonzero >= 2 ? k.x.back() : 0.0);
    if (nonzero < 2) continue;
    points += nonzero;
    s.curves.push_back(std::move(k));
  }
  if (points < kMinSmallPoints) return std::nullopt;
  return s;
}

// Parameters at an end of their range at x (Coordinates::at_bound).
std::vector<std::string> bound_warnings(const TrainingProblem& p, const Eigen::VectorXd& x) {
  std::vector<std::string> out;
  const Coordinates& c = p.coordinates();
  const auto m = p.material_at(x);
  const Eigen::VectorXd theta = p.theta(x);
  for (Eigen::Index i = 0; i < c.size(); ++i) {
    const int end = c.at_bound(x, i);
    if (end == 0) continue;
    if (c.is_poisson(i)) {
      const PoissonRange r = c.poisson_range();
      const double nu = material::small_strain_constants(*m).poisson();
      out.push_back(end > 0 ? fmt::format("nu = {:.5g} is at the top of its range ({:g}:{:g}): the data ask for a "
                                          "material at least this incompressible",
                                          nu, r.lo, r.hi)
                            : fmt::format("nu = {:.4g} is at the bottom of its range ({:g}:{:g}): the data ask for "
                                          "a more compressible material than the range allows (--nu-range to "
                                          "widen it, if the sample can be)",
                                          nu, r.lo, r.hi));
      continue;
    }
    out.push_back(fmt::format("{} = {:.4g} is at the {} end of its range", m->param_info(c.param(i)).name,
                              theta[c.param(i)], end < 0 ? "lower" : "upper"));
  }
  return out;
}

}  // namespace

PoissonRange poisson_range(const Dataset& d, const FitOptions& o) {
  if (o.nu_range) return *o.nu_range;
  return d.poisson > 0.45 ? PoissonRange{0.45, PoissonRange{}.hi} : PoissonRange{};
}

std::size_t guesses_fitted(const Dataset& d, const FitOptions& o) {
  std::vector<double> cut;
  const bool one = d.depth_search() && o.depth_from == DepthFrom::SmallIndentation &&
                   small_indentation_part(d, cut).has_value();
  return one ? 1 : d.layer_depths.size();
}

bool fit_finished(const Dataset& d, const FitOptions& o, const std::filesystem::path& checkpoint) {
  const std::shared_ptr<const Material> initial =
      o.initial ? o.initial : std::shared_ptr<const Material>(default_initial(d));
  Checkpoint c(checkpoint, d, o, *initial);
  c.load();
  // Choosing the depth from the small indentations fits one guess only.
  std::size_t done = 0;
  for (std::size_t g = 0; g < d.layer_depths.size(); ++g) done += c.done(g) ? 1 : 0;
  return done >= guesses_fitted(d, o);
}

FitResult fit_dataset(const Dataset& d, const FitOptions& o, const FitControl& control) {
  if (o.max_iterations < 0 || o.max_iterations > 10000) {
    throw_input_error(fmt::format("{} iterations", o.max_iterations), ErrorContext{"", 0, 0, "max-iterations"},
                      "0 to 10000");
  }
  if (d.layer_depths.empty()) {
    throw Error(ErrorKind::Internal, "fit_dataset: the dataset has no layer depth (read_dataset sets one)");
  }
  const std::shared_ptr<const Material> initial =
      o.initial ? o.initial : std::shared_ptr<const Material>(default_initial(d));

  FitResult result;
  for (const auto& c : d.curves) {
    if (c.role == CurveRole::Train) result.training_points += static_cast<int>(c.y.size());
  }
  result.guesses.resize(d.layer_depths.size());
  Checkpoint checkpoint(control.checkpoint, d, o, *initial);
  if (control.resume) checkpoint.load();

  std::mutex mutex;  // guards checkpoint writes and the callback
  auto publish = [&](std::size_t g, const GuessResult& r, const GuessState& state,
                     const std::vector<axisym::WarmStart>* warm = nullptr) {
    std::lock_guard lock(mutex);
    checkpoint.store(g, r, state, warm);
    if (control.on_iteration) control.on_iteration(g, r);
  };

  // Each guess keeps its own error: after a failure the other guesses stop at
  // their next iteration (after an interrupt, at their next check), and the
  // errors are rethrown once every guess has stopped.
  // Stage 2's problem from `start` at guess r's depth: μ0 and the curvature
  // regularization (a change of a spline's curvature by μ0 at one knot costs
  // as much as `smoothing` × the stage-1 RMS error at one point) from stage 1.
  auto make_problem = [&](const GuessResult& r, const Material& start) {
    const double mu0 = material::small_strain_constants(*r.stage1_material).mu;
    auto p = std::make_unique<TrainingProblem>(d, r.layer_depth, o.simulation, start, o.fixed, mu0,
                                               poisson_range(d, o));
    const double rms1 = std::sqrt(r.objective_stage1 / std::max<Eigen::Index>(1, p->num_data_residuals()));
    p->set_curvature_regularization(o.smoothing * rms1 / mu0);
    return p;
  };
  auto optimize = [&](TrainingProblem& p, const GuessState& state, const OptimizeOptions& oo,
                      const OptimizerCallbacks& cb) {
    return o.optimizer == Optimizer::LevenbergMarquardt ? levenberg_marquardt(p, state, oo, cb)
                                                        : nonlinear_cg(p, state, oo, cb);
  };
  // Several starts: each runs start_iterations (in parallel); stage 2 goes on
  // from where the best one ended.
  auto try_starts = [&](std::vector<Stage2Start>& starts, GuessResult& r) {
    std::vector<StartTrial> trials(starts.size());
    std::vector<std::shared_ptr<Material>> ends(starts.size());
    parallel_for_each_index(starts.size(), [&](std::size_t k) {
      StartTrial& t = trials[k];
      t.label = starts[k].label;
      t.objective_start = t.objective_end = std::numeric_limits<double>::infinity();
      try {
        auto p = make_problem(r, *starts[k].material);
        GuessState st;
        st.x = p->start();
        OptimizeOptions oo;
        oo.max_iterations = std::min(o.start_iterations, o.max_iterations);
        oo.function_tolerance = o.function_tolerance;
        OptimizerCallbacks cb;
        cb.on_iteration = [&](const Eigen::VectorXd& x, double eps, const GuessState&) {
          if (!std::isfinite(t.objective_start)) t.objective_start = eps - p->regularization(x);
        };
        const OptimizeOutcome out = optimize(*p, st, oo, cb);
        t.objective_end = out.objective - p->regularization(out.x);
        ends[k] = std::shared_ptr<Material>(p->material_at(out.x));
        t.evaluations = p->evaluations();
      } catch (const Error& e) {
        if (e.kind() != ErrorKind::Solver) throw;
        // (a start the simulations reject is skipped)
      }
    });
    std::size_t best = 0;
    for (std::size_t k = 0; k < trials.size(); ++k) {
      r.evaluations += trials[k].evaluations;
      if (trials[k].objective_end < trials[best].objective_end) best = k;
    }
    if (!ends[best]) {
      throw_solver_error(fmt::format("stage 2 cannot start at layer depth {:.4g} mm: every start is rejected",
                                     r.layer_depth * 1e3));
    }
    r.stage2_start = ends[best];
    r.starts = trials;
    std::string line;
    for (const auto& t : trials) {
      line += fmt::format("; {}: eps {:.4g} -> {:.4g}", t.label, t.objective_start, t.objective_end);
    }
    spdlog::info("layer depth {:.4g} mm: stage 2 tried {} starts for {} iterations each{}; going on from {}",
                 r.layer_depth * 1e3, trials.size(), std::min(o.start_iterations, o.max_iterations), line,
                 trials[best].label);
  };
  struct Stopped {};  // a guess stopped because another one failed
  std::vector<std::exception_ptr> errors(d.layer_depths.size());
  std::atomic<bool> failed{false};
  auto fit_guess = [&](std::size_t g) {
    if (failed) throw Stopped{};
    const auto t0 = std::chrono::steady_clock::now();
    GuessResult& r = result.guesses[g];
    GuessState state;
    std::vector<axisym::WarmStart> warm;
    const bool resumed = checkpoint.restore(g, r, state, &warm);
    const double elapsed0 = resumed ? r.seconds : 0.0;
    auto seconds = [&] {
      return elapsed0 + std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    r.layer_depth = d.layer_depths[g];
    if (resumed && r.done) {
      r.x_final = state.x;
      return;
    }
    if (!resumed) {
      const Stage1 s1 = fit_modulus(d, r.layer_depth, *initial, o.simulation);
      r.modulus_scale = s1.scale;
      r.sum_sim_squared = s1.sum_sim_squared;
      r.objective_initial = s1.objective_initial;
      r.objective_stage1 = s1.objective_scaled;
      r.stage1_material = std::shared_ptr<Material>(scaled_material(*initial, s1.scale));
      r.material = std::shared_ptr<Material>(r.stage1_material->clone());
      const material::SplineLayout layout =
          o.adapt_spline_ranges
              ? layout_covering(s1.stretches, o.spline_layout, d.test == TestKind::Homogeneous ? 0.0 : 0.01)
              : o.spline_layout;
      std::vector<Stage2Start> starts = stage2_starts(*r.stage1_material, o, layout);
      const auto keep = static_cast<std::size_t>(o.starts);
      if (keep > 0 && starts.size() > keep) starts.resize(keep);
      r.stage2_start = std::shared_ptr<Material>(std::move(starts.front().material));
      r.objective_final = r.objective_stage1;
      r.evaluations = 1;
      r.seconds = seconds();
      spdlog::info("layer depth {:.4g} mm: stage 1 (modulus) scale {:.5g}, eps {:.4g} -> {:.4g}",
                   r.layer_depth * 1e3, s1.scale, s1.objective_initial, s1.objective_scaled);
      if (o.modulus_only) {
        r.done = true;
        r.stop = Stop{Termination::Converged, "modulus only"};
        publish(g, r, state);
        return;
      }
      if (starts.size() > 1) {
        starts.front().material = r.stage2_start->clone();
        try_starts(starts, r);
      }
    }
    if (failed) throw Stopped{};
    const int evaluations0 = r.evaluations;
    if (!r.stage2_start) r.stage2_start = std::shared_ptr<Material>(stage2_start(*r.stage1_material, o));
    auto made = make_problem(r, *r.stage2_start);
    TrainingProblem& problem = *made;
    if (!resumed || state.x.size() != problem.num_free()) {
      state = GuessState{};
      state.x = problem.start();
    } else {
      problem.set_warm_starts(std::move(warm));
    }

    OptimizerCallbacks cb;
    cb.on_iteration = [&](const Eigen::VectorXd& x, double eps, const GuessState& st) {
      if (failed) throw Stopped{};
      r.material = std::shared_ptr<Material>(problem.material_at(x));
      const double data_eps = eps - problem.regularization(x);
      r.objective_final = data_eps;
      r.evaluations = evaluations0 + problem.evaluations();
      r.seconds = seconds();
      r.history.push_back(
          IterationRecord{static_cast<int>(r.history.size()), data_eps, r.evaluations, r.seconds});
      r.iterations = static_cast<int>(r.history.size()) - 1;
      const std::vector<axisym::WarmStart> warm_now = problem.warm_starts();
      publish(g, r, st, &warm_now);
    };
    OptimizeOptions oo;
    oo.max_iterations = o.max_iterations;
    oo.function_tolerance = o.function_tolerance;
    oo.done_iterations = std::max(0, static_cast<int>(r.history.size()) - 1);
    oo.start_recorded = !r.history.empty();
    const OptimizeOutcome out = optimize(problem, state, oo, cb);
    r.material = std::shared_ptr<Material>(problem.material_at(out.x));
    r.objective_final = out.objective - problem.regularization(out.x);
    r.stop = out.stop;
    r.x_final = out.x;
    r.evaluations = evaluations0 + problem.evaluations();
    r.seconds = seconds();
    r.done = true;
    spdlog::info("layer depth {:.4g} mm: stage 2 ({}, {}) eps {:.4g} -> {:.4g} after {} iterations ({})",
                 r.layer_depth * 1e3, o.model, to_string(o.optimizer), r.objective_stage1, r.objective_final,
                 r.iterations, out.stop.detail);
    GuessState final_state;
    final_state.x = out.x;
    publish(g, r, final_state);
  };
  // The depth from the small indentations: stage 1 at every guess there
  // (cheap: short curves), then only the lowest goes through the whole fit.
  std::optional<std::size_t> chosen;
  std::vector<std::string> depth_notes;
  SmallIndentationProfile profile;
  const std::optional<Dataset> small = d.depth_search() && o.depth_from == DepthFrom::SmallIndentation
                                           ? small_indentation_part(d, profile.cut)
                                           : std::nullopt;
  if (d.depth_search() && o.depth_from == DepthFrom::SmallIndentation && !small) {
    depth_notes.push_back(fmt::format("fewer than {} training points at small indentation (up to {:g} min(punch "
                                      "radius, shallowest guess)): the depth is chosen on the whole curves",
                                      kMinSmallPoints, kSmallIndentation));
    spdlog::warn("fit: {}", depth_notes.back());
  }
  if (small) {
    for (const auto& c : small->curves) profile.points += static_cast<int>(c.y.size());
    std::vector<Stage1> s1(d.layer_depths.size());
    parallel_for_each_index(d.layer_depths.size(), [&](std::size_t g) {
      s1[g] = fit_modulus(*small, d.layer_depths[g], *initial, o.simulation);
    });
    const double young1 = material::small_strain_constants(*initial).young();
    for (std::size_t g = 0; g < s1.size(); ++g) {
      profile.objective.push_back(s1[g].objective_scaled);
      profile.young.push_back(s1[g].scale * young1);
      if (!chosen || s1[g].objective_scaled < s1[*chosen].objective_scaled) chosen = g;
    }
    spdlog::info("layer depth from the small indentations (d <= {:g} min(a, {:.3g} mm), {} points): eps {:.4g} -> "
                 "{:.4g} mm",
                 kSmallIndentation, d.layer_depths.front() * 1e3, profile.points, fmt::join(profile.objective, ", "),
                 d.layer_depths[*chosen] * 1e3);
    for (std::size_t g = 0; g < s1.size(); ++g) {
      if (g == *chosen) continue;
      GuessResult& r = result.guesses[g];
      r.layer_depth = d.layer_depths[g];
      r.modulus_scale = s1[g].scale;
      r.sum_sim_squared = s1[g].sum_sim_squared;
      r.stage1_material = std::shared_ptr<Material>(scaled_material(*initial, s1[g].scale));
      r.material = std::shared_ptr<Material>(r.stage1_material->clone());
      r.objective_initial = r.objective_stage1 = r.objective_final = std::numeric_limits<double>::quiet_NaN();
      r.stop = Stop{Termination::NotRun, "not fitted: the small indentations chose another depth"};
      r.done = true;
    }
    result.small_profile = std::move(profile);
  }
  parallel_for_each_index(d.layer_depths.size(), [&](std::size_t g) {
    if (chosen && g != *chosen) return;
    try {
      fit_guess(g);
    } catch (const Stopped&) {
      // the failed guess's error is rethrown below
    } catch (...) {
      errors[g] = std::current_exception();
      failed = true;
    }
  });
  rethrow_first(errors);  // an interrupt first (the user asked to stop), else the first guess's error

  if (chosen) {
    result.best = *chosen;
  } else {
    for (std::size_t g = 1; g < result.guesses.size(); ++g) {
      if (result.guesses[g].objective_final < result.guesses[result.best].objective_final) result.best = g;
    }
  }
  // How sure: from the Jacobian at the best guess's minimum (one more
  // evaluation there), and the depth from ε over the guesses.
  const GuessResult& best = result.guesses[result.best];
  if (o.modulus_only || best.x_final.size() == 0) {
    const material::ElasticConstants c = material::small_strain_constants(*initial);
    result.uncertainty = modulus_uncertainty(best.objective_stage1, result.training_points, best.modulus_scale,
                                             best.sum_sim_squared, c.young(), c.poisson());
  } else {
    auto problem = make_problem(best, *best.stage2_start);
    Evaluation e;
    if (problem->evaluate(best.x_final, e)) {
      result.uncertainty = fit_uncertainty(*problem, best.x_final, e, o.model != "spline");
    } else {
      result.uncertainty.why_not = "the fitted material cannot be simulated again: " + e.reason;
    }
    result.warnings = bound_warnings(*problem, best.x_final);
  }
  const double nu = material::small_strain_constants(*best.material).poisson();
  if (nu < 0.0) {
    result.warnings.push_back(fmt::format("the fitted nu = {:.3g} is negative (the sample would get thinner "
                                          "under compression): not tissue or rubber; --fix nu, or --nu-range 0:0.4999",
                                          nu));
  }
  if (result.small_profile) {
    // The profile's own residual scale: stage 1 on the small indentations.
    const SmallIndentationProfile& sp = *result.small_profile;
    const double sigma = std::sqrt(sp.objective[result.best] / std::max(1, sp.points - 1));
    add_depth_uncertainty(result.uncertainty, d.layer_depths, sp.objective, sp.young, result.best, sigma,
                          sp.points - 1);
  } else if (d.depth_search()) {
    std::vector<double> objectives, young;
    for (const auto& g : result.guesses) {
      objectives.push_back(g.objective_final);
      young.push_back(material::small_strain_constants(*g.material).young());
    }
    add_depth_uncertainty(result.uncertainty, d.layer_depths, objectives, young, result.best,
                          result.uncertainty.sigma,
                          result.uncertainty.points - result.uncertainty.effective_parameters);
  }
  result.warnings.insert(result.warnings.end(), depth_notes.begin(), depth_notes.end());
  result.warnings.insert(result.warnings.end(), result.uncertainty.warnings.begin(),
                         result.uncertainty.warnings.end());
  return result;
}

}  // namespace palpa::fit
