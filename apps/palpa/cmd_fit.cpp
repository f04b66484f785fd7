// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa fit: a material (and, if asked, the layer depth) from measured
// force–indentation, plate-compression or homogeneous stress–stretch curves.

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>

#include "cli_common.hpp"
#include "commands.hpp"
#include "fit_output.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/input_file.hpp"
#include "palpa/core/progress.hpp"
#include "palpa/fit/fit.hpp"
#include "palpa/material/material_file.hpp"

namespace palpa::cli {

namespace {

struct FitArgs {
  std::string dataset;
  std::string output;
  std::string model = "spline";
  std::string optimizer = "lm";
  std::string element = "fbar";
  std::string initial;
  std::vector<std::string> fix;
  std::string nu_range;
  std::string depth_from = "small";
  int max_iterations = 50;
  double tolerance = 1e-5;
  double smoothing = 0.1;
  int level = 2;
  bool no_extrapolation = false;
  int steps = 20;
  int ogden_terms = 2;
  int starts = 0;
  double fillet = 0.0;
  bool modulus_only = false;
  bool resume = false;
  bool overwrite = false;
  std::string command_line;
};

}  // namespace

fit::FitOptions fit_options_from(const std::string& model, const std::string& optimizer, const std::string& element) {
  fit::FitOptions o;
  o.model = model;
  o.optimizer = fit::parse_optimizer(optimizer);
  if (element == "fbar") {
    o.simulation.element = axisym::ElementFormulation::FBar;
  } else if (element == "standard") {
    o.simulation.element = axisym::ElementFormulation::Standard;
  } else {
    throw_input_error(fmt::format("unknown element '{}'", element), ErrorContext{"", 0, 0, "option --element"},
                      "fbar or standard");
  }
  return o;
}

namespace {

// "0.067 N (48 of 52 points: r1.03mm to 3.61 of 4.05 mm)", or "n/a (no
// validation curve)".
std::string validation_text(const FitSummary& s, const char* unit) {
  if (s.validate_points_total == 0) return "n/a (no validation curve)";
  if (s.validate_points == 0) return "n/a (no validation point could be simulated)";
  std::string text = fmt::format("{:.3g} {}", s.rms_validate, unit);
  if (s.validate_points < s.validate_points_total) {
    text += fmt::format(" (over {} of {} points: simulated {})", s.validate_points, s.validate_points_total,
                        fmt::join(s.validate_short, ", "));
  }
  return text;
}

// "E (small strain) = 88.06 kPa, 95% 87.61 to 88.5 kPa; nu = 0.4999, 95% ...".
std::string estimates_text(const fit::Uncertainty& u, const material::Material& m, double layer_depth) {
  const material::ElasticConstants c = material::small_strain_constants(m);
  const auto pressure = [](double v) { return fmt::format("{:.4g} kPa", v * 1e-3); };
  if (!u.defined) {
    return fmt::format("E (small strain) = {}, nu = {:.4g} (no intervals: {})", pressure(c.young()), c.poisson(),
                       u.why_not);
  }
  const bool nu_held = std::find(u.held.begin(), u.held.end(), "nu") != u.held.end();
  std::string text;
  if (const fit::Estimate* e = u.find("E")) {
    text += std::isfinite(e->standard_error)
                ? fmt::format("E (small strain) = {}, 95% {:.4g} to {}", pressure(e->value), e->lo * 1e-3,
                              pressure(e->hi))
                : fmt::format("E (small strain) = {} (not determined by the curves)", pressure(e->value));
    if (nu_held) text += " given nu";
  }
  if (const fit::Estimate* nu = u.find("nu")) {
    if (nu_held) {
      text += fmt::format("; nu = {:.5g} (at an end of its range)", nu->value);
    } else if (!std::isfinite(nu->standard_error)) {
      text += fmt::format("; nu = {:.5g} (not determined by the curves)", nu->value);
    } else if (nu->standard_error > 0.0) {
      text += fmt::format("; nu = {:.5g}, 95% {:.5g} to {:.5g}", nu->value, nu->lo, nu->hi);
    } else {
      text += fmt::format("; nu = {:.5g} (held)", nu->value);
    }
  }
  if (const fit::Estimate* dd = u.find("layer_depth")) {
    text += fmt::format("; layer depth {:.3g} mm", layer_depth * 1e3);
    if (std::isfinite(dd->standard_error)) {
      text += fmt::format(" (the objective's minimum {:.3g} mm, 95% {:.3g} to {:.3g} mm)", dd->value * 1e3,
                          dd->lo * 1e3, dd->hi * 1e3);
    }
  }
  return text;
}

}  // namespace

FitSummary run_fit(const std::filesystem::path& dataset_file, const std::filesystem::path& out,
                   const fit::FitOptions& o, bool resume, const std::string& command) {
  const fit::Dataset d = fit::read_dataset(dataset_file);
  // An input inside the output folder is refused now, not after the fit.
  for (const auto& f : fit_output_files(out, d)) refuse_overwriting_an_input(f);
  const auto t0 = std::chrono::steady_clock::now();
  OutputFolder folder(out, OutputFolder::OnFailure::RemoveIfEmpty, OutputFolder::Lock::Exclusive,
                      resume ? OutputFolder::Start::Resumed : OutputFolder::Start::Fresh);
  fit::FitControl control;
  control.checkpoint = out / "checkpoint.json";
  control.resume = resume;
  spdlog::info("fit: {} ({}), {} curves ({} train, {} validate), {} layer depth{}, model {}, optimizer {}",
               dataset_file.string(), fit::to_string(d.test), d.curves.size(), d.count(fit::CurveRole::Train),
               d.count(fit::CurveRole::Validate), d.layer_depths.size(), d.depth_search() ? " guesses" : "",
               o.model, fit::to_string(o.optimizer));
  // One unit per recorded iteration (the start of stage 2 included) and guess
  // fitted; a guess that converges early leaves its remaining units to finish().
  Progress progress("fit iterations", static_cast<std::size_t>(o.max_iterations + 1) * fit::guesses_fitted(d, o));
  std::vector<std::size_t> seen(d.layer_depths.size(), 0);
  control.on_iteration = [&](std::size_t g, const fit::GuessResult& r) {
    const std::size_t n = r.history.size();
    if (g < seen.size() && n > seen[g]) {
      progress.advance(n - seen[g]);
      seen[g] = n;
    }
    progress.set_note(fmt::format("D = {:.3g} mm: eps {:.4g}", r.layer_depth * 1e3, r.objective_final));
  };
  const fit::FitResult result = fit::fit_dataset(d, o, control);
  progress.finish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const FitSummary s = write_fit_outputs(out, d, o, result, seconds, command);
  const auto& best = result.guesses[result.best];
  if (d.depth_search()) {
    for (std::size_t k = 0; k < result.guesses.size(); ++k) {
      const auto& g = result.guesses[k];
      const std::string whole = std::isfinite(g.objective_final)
                                    ? fmt::format("eps {:.4g} after {} iterations", g.objective_final, g.iterations)
                                    : std::string("not fitted further");
      if (result.small_profile) {
        spdlog::info("fit: layer depth {:.4g} mm: small indentations eps {:.4g} (E {:.4g} kPa); {}{}",
                     g.layer_depth * 1e3, result.small_profile->objective[k], result.small_profile->young[k] * 1e-3,
                     whole, k == result.best ? "  <- chosen" : "");
      } else {
        spdlog::info("fit: layer depth {:.4g} mm: {}{}", g.layer_depth * 1e3, whole,
                     k == result.best ? "  <- best" : "");
      }
    }
  }
  const char* unit = d.test == fit::TestKind::Homogeneous ? "Pa" : "N";
  spdlog::info("fit: sqrt(eps) {:.4g} -> {:.4g} {} ({} iterations, {} evaluations, {:.1f} s of fitting); "
               "RMS error train {:.3g} {}, validate {}; wrote {}",
               s.sqrt_objective_stage1, s.sqrt_objective_final, unit, best.iterations, best.evaluations, best.seconds,
               s.rms_train, unit, validation_text(s, unit), out.string());
  spdlog::info("fit: {}",
               estimates_text(result.uncertainty, *best.material, d.depth_search() ? best.layer_depth : 0.0));
  for (const auto& w : result.warnings) spdlog::warn("fit: {}", w);
  folder.keep();
  return s;
}

namespace {

// "LO:HI", -1 < LO < HI < 0.5.
fit::PoissonRange parse_nu_range(const std::string& text) {
  const ErrorContext where{"", 0, 0, "option --nu-range"};
  const char* expected = "LO:HI with -1 < LO < HI < 0.5, such as 0.45:0.4999";
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos) throw_input_error(fmt::format("'{}' has no ':'", text), where, expected);
  fit::PoissonRange r;
  try {
    std::size_t used_lo = 0, used_hi = 0;
    r.lo = std::stod(text.substr(0, colon), &used_lo);
    r.hi = std::stod(text.substr(colon + 1), &used_hi);
    if (used_lo != colon || used_hi != text.size() - colon - 1) throw std::invalid_argument("trailing characters");
  } catch (const std::exception&) {
    throw_input_error(fmt::format("'{}' is not two numbers", text), where, expected);
  }
  if (!(r.lo > -1.0 && r.lo < r.hi && r.hi < 0.5)) {
    throw_input_error(fmt::format("'{}' is not an increasing range of Poisson's ratios", text), where, expected);
  }
  return r;
}

void run_fit_command(const FitArgs& a) {
  fit::FitOptions o = fit_options_from(a.model, a.optimizer, a.element);
  o.max_iterations = a.max_iterations;
  o.function_tolerance = a.tolerance;
  o.smoothing = a.smoothing;
  o.simulation.mesh_level = a.level;
  o.simulation.extrapolate = !a.no_extrapolation;
  o.simulation.steps = a.steps;
  o.simulation.fillet_radius = a.fillet;
  o.fixed = a.fix;
  if (!a.nu_range.empty()) o.nu_range = parse_nu_range(a.nu_range);
  o.ogden_terms = a.ogden_terms;
  o.starts = a.starts;
  o.depth_from = fit::parse_depth_from(a.depth_from);
  o.modulus_only = a.modulus_only;
  if (!a.initial.empty()) o.initial = material::read_material_file(a.initial).material;
  const std::filesystem::path out = a.output;
  bool resume = a.resume;
  // --resume where there is nothing to resume starts afresh, so that a
  // workflow can always pass it.
  if (resume && !std::filesystem::exists(out / "checkpoint.json")) {
    spdlog::info("fit: no checkpoint in {}: starting afresh", out.string());
    resume = false;
  }
  // A finished fit is left exactly as it is (a checkpoint of another fit is
  // refused here, naming what differs).
  if (resume && std::filesystem::exists(out / "report.json") &&
      fit::fit_finished(fit::read_dataset(a.dataset), o, out / "checkpoint.json")) {
    spdlog::info("fit: the fit in {} is finished (report.json); nothing to resume", out.string());
    return;
  }
  if (!resume && !a.overwrite) require_empty_output(out, "fit");
  try {
    run_fit(a.dataset, out, o, resume, a.command_line);
  } catch (const Error& e) {
    if (e.kind() == ErrorKind::Interrupted && std::filesystem::exists(out / "checkpoint.json")) {
      spdlog::warn("fit: interrupted; the last iteration is in {}: continue with the same command and --resume",
                   (out / "checkpoint.json").string());
    }
    throw;
  }
}

}  // namespace

void add_fit_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "fit",
      "Fit a material (and, for a range of layer depths, the depth) to measured curves: first the "
      "modulus in closed form, then the model's shape.\n"
      "  palpa fit examples/fit/foam/dataset.json -o fit-foam\n"
      "  palpa fit examples/fit/silicone/dataset-depth.json --model neo-hookean -o fit-depth\n"
      "  palpa fit examples/fit/foam/dataset.json -o fit-foam --resume    (continue an interrupted fit)");
  auto a = std::make_shared<FitArgs>();
  cmd->add_option("dataset", a->dataset, "Dataset file (JSON, see the README)")->required();
  cmd->add_option("-o,--output", a->output, "Output folder (material.json, report.json, curves, plots)")
      ->required();
  cmd->add_option("--model", a->model,
                  "spline (Valanis-Landel natural cubic splines, default), neo-hookean, neo-hookean-volume, "
                  "neo-hookean-isochoric, mooney-rivlin, yeoh or ogden");
  cmd->add_option("--optimizer", a->optimizer,
                  "lm (Levenberg-Marquardt, default) or nlcg (nonlinear conjugate gradients)");
  cmd->add_option("--max-iterations", a->max_iterations, "Iterations of the shape stage per layer depth (default 50)")
      ->check(CLI::Range(0, 10000));
  cmd->add_option("--tolerance", a->tolerance,
                  "Stop when an iteration lowers the objective by less than this fraction (default 1e-5)")
      ->check(CLI::Range(1e-16, 1.0));
  cmd->add_option("--smoothing", a->smoothing,
                  "Spline curvature regularization: changing a spline's curvature by the shear modulus at one "
                  "knot costs this many stage-1 RMS errors (default 0.1; 0 = none)")
      ->check(CLI::Range(0.0, 1e6));
  cmd->add_option("--fix", a->fix, "Parameters held at their start values, e.g. --fix nu")->delimiter(',');
  cmd->add_option("--nu-range", a->nu_range,
                  "Range LO:HI of the small-strain Poisson's ratio the fit may reach, open at both ends "
                  "(default 0.45:0.4999 when the dataset's poisson is above 0.45, else -0.9:0.4999)");
  cmd->add_option("--depth-from", a->depth_from,
                  "How a depth search picks the layer depth: small (default: the modulus at every guess on the "
                  "indentations up to 0.1 min(punch radius, shallowest guess), then the whole fit at the best) "
                  "or whole (every guess fitted on every point, the lowest objective wins)");
  cmd->add_option("--ogden-terms", a->ogden_terms, "Terms of the ogden model (default 2)")->check(CLI::Range(1, 6));
  cmd->add_option("--starts", a->starts,
                  "Shape-stage starts tried for 5 iterations each before the best goes on: ogden has 3 or 4, "
                  "mooney-rivlin 3, neo-hookean-volume and spline 2, the other models 1 (default 0: all of the model's; "
                  "1: stage 1's material alone)")
      ->check(CLI::Range(0, 10));
  cmd->add_option("--initial", a->initial,
                  "Material file to start from (its modulus is fitted first); default neo-Hookean "
                  "E = 10 kPa with the dataset's nu");
  cmd->add_flag("--modulus-only", a->modulus_only, "Stop after the modulus stage");
  cmd->add_option("--mesh-level", a->level,
                  "Mesh refinement 0..7 of the simulations; forces are extrapolated from this level and "
                  "the one below it (default 2)")
      ->check(CLI::Range(0, 7));
  cmd->add_flag("--no-extrapolation", a->no_extrapolation,
                "Simulate on the --mesh-level mesh alone, without Richardson extrapolation");
  cmd->add_option("--steps", a->steps, "Simulated depths per curve (default 20)")->check(CLI::Range(2, 1000));
  cmd->add_option("--element", a->element, "fbar (default) or standard");
  add_quantity_option(*cmd, "--fillet", a->fillet, Dimension::Length, "Punch rim radius (default 0: sharp)",
                      Sign::NonNegative);
  cmd->add_flag("--resume", a->resume, "Continue the interrupted fit whose checkpoint is in the output folder");
  cmd->add_flag("--overwrite", a->overwrite, "Write into a non-empty output folder");
  declare_paths(*cmd, {"dataset", "--initial"}, {"-o"});
  cmd->callback([a] {
    a->command_line = fmt::format("palpa fit {} --model {} --optimizer {} --mesh-level {} --steps {} --element {}",
                                  a->dataset, a->model, a->optimizer, a->level, a->steps, a->element);
    if (a->no_extrapolation) a->command_line += " --no-extrapolation";
    if (!a->fix.empty()) a->command_line += " --fix " + fmt::format("{}", fmt::join(a->fix, ","));
    if (!a->nu_range.empty()) a->command_line += " --nu-range " + a->nu_range;
    if (a->starts != 0) a->command_line += fmt::format(" --starts {}", a->starts);
    if (a->depth_from != "small") a->command_line += " --depth-from " + a->depth_from;
    if (!a->initial.empty()) a->command_line += " --initial " + a->initial;
    run_fit_command(*a);
  });
}

}  // namespace palpa::cli
