// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/fit/run.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <vector>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/input_file.hpp"
#include "palpa/core/progress.hpp"
#include "palpa/material/registry.hpp"

namespace palpa::fit {

FitOptions fit_options_from(const std::string& model, const std::string& optimizer, const std::string& element) {
  FitOptions o;
  o.model = material::model_spec(model, ErrorContext{"", 0, 0, "option --model"}, true).name;
  o.optimizer = parse_optimizer(optimizer);
  o.simulation.element = axisym::parse_element_formulation(element);
  return o;
}

FitSummary run_fit(const std::filesystem::path& dataset_file, const std::filesystem::path& out,
                   const FitOptions& o, bool resume, const std::string& command, const IterationCallback& on_iteration) {
  const Dataset d = read_dataset(dataset_file);
  // An input inside the output folder is refused now, not after the fit.
  for (const auto& f : fit_output_files(out, d)) refuse_overwriting_an_input(f);
  const auto t0 = std::chrono::steady_clock::now();
  OutputFolder folder(out, OutputFolder::OnFailure::RemoveIfEmpty, OutputFolder::Lock::Exclusive,
                      resume ? OutputFolder::Start::Resumed : OutputFolder::Start::Fresh);
  FitControl control;
  control.checkpoint = out / "checkpoint.json";
  control.resume = resume;
  spdlog::info("fit: {} ({}), {} curves ({} train, {} validate), {} layer depth{}, model {}, optimizer {}",
               dataset_file.string(), to_string(d.test), d.curves.size(), d.count(CurveRole::Train),
               d.count(CurveRole::Validate), d.layer_depths.size(), d.depth_search() ? " guesses" : "",
               o.model, to_string(o.optimizer));
  // One unit per recorded iteration (the start of stage 2 included) and guess
  // fitted; a guess that converges early leaves its remaining units to finish().
  Progress progress("fit iterations", static_cast<std::size_t>(o.max_iterations + 1) * guesses_fitted(d, o));
  std::vector<std::size_t> seen(d.layer_depths.size(), 0);
  control.on_iteration = [&](std::size_t g, const GuessResult& r) {
    const std::size_t n = r.history.size();
    if (g < seen.size() && n > seen[g]) {
      progress.advance(n - seen[g]);
      seen[g] = n;
    }
    progress.set_note(fmt::format("D = {:.3g} mm: eps {:.4g}", r.layer_depth * 1e3, r.objective_final));
    if (on_iteration) on_iteration(g, r);
  };
  const FitResult result = fit_dataset(d, o, control);
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
  const char* unit = d.test == TestKind::Homogeneous ? "Pa" : "N";
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

std::optional<FitSummary> run_fit_in_folder(const std::filesystem::path& dataset_file, const std::filesystem::path& out,
                                            const FitOptions& o, bool resume, bool overwrite, const std::string& command,
                                            const IterationCallback& on_iteration) {
  const std::filesystem::path checkpoint = out / "checkpoint.json";
  // --resume where there is nothing to resume starts afresh, so that a
  // workflow can always pass it.
  if (resume && !std::filesystem::exists(checkpoint)) {
    if (!overwrite) require_empty_output(out);  // (--resume was given: not offered again)
    spdlog::info("fit: no checkpoint in {}: starting afresh", out.string());
    resume = false;
  }
  // A finished fit is left exactly as it is (a checkpoint of another fit is
  // refused here, naming what differs).
  if (resume && std::filesystem::exists(out / "report.json") &&
      fit_finished(read_dataset(dataset_file), o, checkpoint)) {
    spdlog::info("fit: the fit in {} is finished (report.json); nothing to resume", out.string());
    return std::nullopt;
  }
  if (!resume && !overwrite) require_empty_output(out, "fit");
  try {
    return run_fit(dataset_file, out, o, resume, command, on_iteration);
  } catch (const Error& e) {
    if (e.kind() == ErrorKind::Interrupted && std::filesystem::exists(checkpoint)) {
      spdlog::warn("fit: interrupted; the last iteration is in {}: continue with the same command and --resume",
                   checkpoint.string());
    }
    throw;
  }
}

}  // namespace palpa::fit
