// SPDX-License-Identifier: AGPL-3.0-or-later
// Benchmark of material fitting (palpa::fit) on the bundled example datasets
// (examples/fit/*/dataset*.json). Prints one JSON line per figure (see
// BENCHMARKS.md).
//
// Per dataset:
//  - forward_curve: one simulation of the first training curve with the
//    stage-1 material (no sensitivities), median of 3 — the reference;
//  - evaluation: one evaluation of the training objective with its Jacobian
//    (all training curves, with sensitivities), as a multiple of forward_curve;
//  - fit: the whole fit (stage 1 + stage 2, default spline model) with
//    Levenberg–Marquardt and with nonlinear CG, side by side: wall time, as a
//    multiple of forward_curve, stage-2 iterations, objective evaluations,
//    √ε after stage 1 and at the end, RMS error of the training and validation
//    curves, small-strain E. Depth-search datasets are fitted at every guess
//    (in parallel), LM only unless --nlcg-depth.
//
// Options: --quick (the first dataset only, LM only), --only <substring of the
// dataset path>, --max-iterations N (default 50).

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "palpa/fit/fit.hpp"
#include "palpa/fit/optimize.hpp"
#include "palpa/material/models.hpp"

#ifndef PALPA_EXAMPLES_DIR
#error "PALPA_EXAMPLES_DIR must name the bundled examples folder"
#endif

namespace {

namespace fs = std::filesystem;
using namespace palpa;
using clock_type = std::chrono::steady_clock;

using palpa::bench::seconds_since;

std::vector<fs::path> datasets() {
  std::vector<fs::path> out;
  const fs::path root = fs::path(PALPA_EXAMPLES_DIR) / "fit";
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(root, ec)) {
    const std::string name = e.path().filename().string();
    if (e.path().extension() == ".json" && name.rfind("dataset", 0) == 0) out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

struct Rms {
  double train = 0.0, validate = 0.0;
};

Rms rms_errors(const fit::Dataset& d, const fit::GuessResult& g, const fit::FitOptions& o) {
  const auto pred = fit::predict_curves(d, g.layer_depth, *g.material, o.simulation);
  double st = 0.0, sv = 0.0;
  std::size_t nt = 0, nv = 0;
  for (std::size_t i = 0; i < d.curves.size(); ++i) {
    const double s = fit::sum_of_squares(d.curves[i], pred[i]);
    if (d.curves[i].role == fit::CurveRole::Train) {
      st += s;
      nt += d.curves[i].y.size();
    } else {
      sv += s;
      nv += d.curves[i].y.size();
    }
  }
  return {nt ? std::sqrt(st / static_cast<double>(nt)) : 0.0, nv ? std::sqrt(sv / static_cast<double>(nv)) : 0.0};
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, nlcg_depth = false;
  std::string only;
  int max_iterations = 50;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) quick = true;
    else if (!std::strcmp(argv[i], "--nlcg-depth")) nlcg_depth = true;
    else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
    else if (!std::strcmp(argv[i], "--max-iterations") && i + 1 < argc) max_iterations = std::atoi(argv[++i]);
  }
  std::vector<fs::path> files = datasets();
  if (!only.empty()) {
    std::erase_if(files, [&](const fs::path& p) { return p.string().find(only) == std::string::npos; });
  }
  if (quick && files.size() > 1) files.resize(1);
  if (files.empty()) {
    bench::emit({{"bench", "fit"}, {"skipped", "no example datasets found"}});
    return 0;
  }
  for (const auto& file : files) {
    const fit::Dataset d = fit::read_dataset(file);
    const std::string name = fs::relative(file, fs::path(PALPA_EXAMPLES_DIR)).string();
    fit::FitOptions base;
    base.max_iterations = max_iterations;

    // Reference: one forward curve with the stage-1 material of the first depth.
    const auto initial = std::make_shared<material::NeoHookean>(10e3, d.poisson);
    const fit::MeasuredCurve* first = nullptr;
    for (const auto& c : d.curves) {
      if (c.role == fit::CurveRole::Train && first == nullptr) first = &c;
    }
    std::vector<double> times;
    fit::CurvePrediction p;
    for (int rep = 0; rep < 3; ++rep) {
      auto sim = fit::make_curve_simulator(d, *first, d.layer_depths.front(), base.simulation);
      const auto t0 = clock_type::now();
      p = sim->predict(*initial, false);
      times.push_back(seconds_since(t0));
    }
    std::sort(times.begin(), times.end());
    const double forward = times[1];
    bench::emit({{"bench", "fit"},
                 {"dataset", name},
                 {"figure", "forward_curve"},
                 {"curve", first->name},
                 {"seconds", forward},
                 {"newton_iterations", p.newton_iterations},
                 {"factorizations", p.factorizations},
                 {"mesh_level", base.simulation.mesh_level},
                 {"steps", base.simulation.steps}});

    {
      const auto s1 = fit::scaled_material(*initial, 1.0);
      const auto start = fit::stage2_start(*s1, base);
      fit::TrainingProblem problem(d, d.layer_depths.front(), base.simulation, *start, {},
                                   material::small_strain_constants(*s1).mu);
      fit::Evaluation e;
      problem.evaluate(problem.start(), e);  // builds the simulators (analysis)
      const auto t0 = clock_type::now();
      const bool ok = problem.evaluate(problem.start(), e);
      const double t = seconds_since(t0);
      bench::emit({{"bench", "fit"},
                   {"dataset", name},
                   {"figure", "evaluation_with_jacobian"},
                   {"valid", ok},
                   {"parameters", problem.num_free()},
                   {"residuals", problem.num_residuals()},
                   {"seconds", t},
                   {"forward_curves", t / forward}});
    }

    std::vector<fit::Optimizer> optimizers{fit::Optimizer::LevenbergMarquardt};
    if (!quick && (!d.depth_search() || nlcg_depth)) optimizers.push_back(fit::Optimizer::Nlcg);
    for (const auto opt : optimizers) {
      fit::FitOptions o = base;
      o.optimizer = opt;
      const auto t0 = clock_type::now();
      const fit::FitResult r = fit::fit_dataset(d, o);
      const double t = seconds_since(t0);
      const auto& g = r.guesses[r.best];
      const Rms rms = rms_errors(d, g, o);
      nlohmann::json guesses = nlohmann::json::array();
      for (const auto& x : r.guesses) guesses.push_back({x.layer_depth * 1e3, x.objective_final});
      bench::emit({{"bench", "fit"},
                   {"dataset", name},
                   {"figure", "fit"},
                   {"optimizer", std::string(fit::to_string(opt))},
                   {"model", o.model},
                   {"seconds", t},
                   {"forward_curves", t / forward},
                   {"iterations", g.iterations},
                   {"evaluations", g.evaluations},
                   {"sqrt_eps_stage1", std::sqrt(g.objective_stage1)},
                   {"sqrt_eps_final", std::sqrt(g.objective_final)},
                   {"rms_train", rms.train},
                   {"rms_validate", rms.validate},
                   {"young_Pa", material::small_strain_constants(*g.material).young()},
                   {"best_layer_depth_mm", g.layer_depth * 1e3},
                   {"depth_guesses_mm_eps", guesses},
                   {"stop_reason", g.stop_reason}});
    }
  }
  return 0;
}
