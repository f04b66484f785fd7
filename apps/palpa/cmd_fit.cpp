// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa fit: a material (and, if asked, the layer depth) from measured
// force–indentation, plate-compression or homogeneous stress–stretch curves.

#include <fmt/format.h>

#include <string>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/core/error.hpp"
#include "palpa/fit/fit.hpp"
#include "palpa/fit/run.hpp"
#include "palpa/material/material_file.hpp"
#include "palpa/material/registry.hpp"

namespace palpa::cli {

namespace {

CLI::Validator range(const fit::OptionBounds& b) { return finite_range(b.lo, b.hi); }

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

// "LO:HI", -1 < LO < HI < 0.5.
fit::PoissonRange parse_nu_range(const std::string& text) {
  const auto [lo, hi] = parse_range(text, "--nu-range", "0.45:0.4999");
  if (!(lo > -1.0 && hi < 0.5)) {
    throw_input_error(fmt::format("'{}' is not a range of Poisson's ratios", text),
                      ErrorContext{"", 0, 0, "option --nu-range"}, "LO:HI with -1 < LO < HI < 0.5, such as 0.45:0.4999");
  }
  return fit::PoissonRange{lo, hi};
}

void run_fit_command(const FitArgs& a) {
  fit::FitOptions o = fit::fit_options_from(a.model, a.optimizer, a.element);
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
  fit::run_fit_in_folder(a.dataset, a.output, o, a.resume, a.overwrite, a.command_line);
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
  cmd->add_option("-o,--output", a->output, "Output folder (material.json, report.json, report.html, curves, plots)")
      ->required();
  cmd->add_option("--model", a->model,
                  fmt::format("Material model to fit: {} (default spline: Valanis-Landel natural cubic splines)",
                              material::model_names(true)));
  cmd->add_option("--optimizer", a->optimizer,
                  "lm (Levenberg-Marquardt, default) or nlcg (nonlinear conjugate gradients)");
  cmd->add_option("--max-iterations", a->max_iterations, "Iterations of the shape stage per layer depth (default 50)")
      ->check(range(fit::bounds::max_iterations));
  cmd->add_option("--tolerance", a->tolerance,
                  "Stop when an iteration lowers the objective by less than this fraction (default 1e-5)")
      ->check(finite_range(fit::bounds::tolerance.lo, fit::bounds::tolerance.hi));
  cmd->add_option("--smoothing", a->smoothing,
                  "Spline curvature regularization: changing a spline's curvature by the shear modulus at one "
                  "knot costs this many stage-1 RMS errors (default 0.1; 0 = none)")
      ->check(finite_range(fit::bounds::smoothing.lo, fit::bounds::smoothing.hi));
  cmd->add_option("--fix", a->fix, "Parameters held at their start values, e.g. --fix nu")->delimiter(',');
  cmd->add_option("--nu-range", a->nu_range,
                  "Range LO:HI of the small-strain Poisson's ratio the fit may reach, open at both ends "
                  "(default 0.45:0.4999 when the dataset's poisson is above 0.45, else -0.9:0.4999)");
  cmd->add_option("--depth-from", a->depth_from,
                  "How a depth search picks the layer depth: small (default: the modulus at every guess on the "
                  "indentations up to 0.1 min(punch radius, shallowest guess), then the whole fit at the best) "
                  "or whole (every guess fitted on every point, the lowest objective wins)");
  cmd->add_option("--ogden-terms", a->ogden_terms, "Terms of the ogden model (default 2)")
      ->check(range(fit::bounds::ogden_terms));
  cmd->add_option("--starts", a->starts,
                  "Shape-stage starts tried for 5 iterations each before the best goes on: ogden has 3 or 4, "
                  "mooney-rivlin 3, neo-hookean-volume and spline 2, the other models 1 (default 0: all of the "
                  "model's; 1: stage 1's material alone)")
      ->check(range(fit::bounds::starts));
  cmd->add_option("--initial", a->initial,
                  "Material file to start from (its modulus is fitted first); default neo-Hookean "
                  "E = 10 kPa with the dataset's nu");
  cmd->add_flag("--modulus-only", a->modulus_only, "Stop after the modulus stage");
  cmd->add_option("--mesh-level", a->level,
                  "Mesh refinement 0..7 of the simulations; forces are extrapolated from this level and "
                  "the one below it (default 2)")
      ->check(range(fit::bounds::mesh_level));
  cmd->add_flag("--no-extrapolation", a->no_extrapolation,
                "Simulate on the --mesh-level mesh alone, without Richardson extrapolation");
  cmd->add_option("--steps", a->steps, "Simulated depths per curve (default 20)")
      ->check(range(fit::bounds::steps));
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
