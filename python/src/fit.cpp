// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa._fit: `palpa fit` into an output folder, with a Python progress
// callback; palpa.fit (the package) wraps it and reads the results back.

#include <fmt/format.h>
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <optional>

#include "common.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/interrupt.hpp"
#include "palpa/fit/fit.hpp"
#include "palpa/fit/run.hpp"
#include "palpa/material/material_file.hpp"

namespace palpa::python {

namespace {

struct FitArgs {
  std::string dataset, out, model, optimizer, element, depth_from;
  bool resume = false, overwrite = false;
  int max_iterations = 50, starts = 0, ogden_terms = 2, mesh_level = 2, steps = 20;
  double tolerance = 1e-5, smoothing = 0.1;
  std::vector<std::string> fix;
  std::optional<std::pair<double, double>> nu_range;
  std::optional<std::string> initial;
};

// The command line's ranges, with the keyword's name.
void check_in(const char* name, double value, const fit::OptionBounds& b) {
  if (!b.holds(value)) {
    throw_input_error(fmt::format("{} = {}", name, value), ErrorContext{"", 0, 0, name},
                      fmt::format("a number from {:g} to {:g}", b.lo, b.hi));
  }
}

bool run(const FitArgs& a, const py::object& progress) {
  check_in("max_iterations", a.max_iterations, fit::bounds::max_iterations);
  check_in("tolerance", a.tolerance, fit::bounds::tolerance);
  check_in("smoothing", a.smoothing, fit::bounds::smoothing);
  check_in("ogden_terms", a.ogden_terms, fit::bounds::ogden_terms);
  check_in("starts", a.starts, fit::bounds::starts);
  check_in("mesh_level", a.mesh_level, fit::bounds::mesh_level);
  check_in("steps", a.steps, fit::bounds::steps);
  fit::FitOptions o = fit::fit_options_from(a.model, a.optimizer, a.element);
  o.max_iterations = a.max_iterations;
  o.function_tolerance = a.tolerance;
  o.smoothing = a.smoothing;
  o.simulation.mesh_level = a.mesh_level;
  o.simulation.steps = a.steps;
  o.fixed = a.fix;
  if (a.nu_range) {
    const auto [lo, hi] = *a.nu_range;
    if (!(lo > -1.0 && lo < hi && hi < 0.5)) {
      throw_input_error(fmt::format("({}, {})", lo, hi), ErrorContext{"", 0, 0, "nu_range"},
                        "(lo, hi) with -1 < lo < hi < 0.5");
    }
    o.nu_range = fit::PoissonRange{lo, hi};
  }
  o.ogden_terms = a.ogden_terms;
  o.starts = a.starts;
  o.depth_from = fit::parse_depth_from(a.depth_from);
  if (a.initial) o.initial = material::read_material_file(*a.initial).material;
  // A progress callback runs with the GIL; an exception it raises stops the
  // fit as Ctrl-C would (the checkpoint keeps the last iteration) and is
  // raised again here.
  std::optional<py::error_already_set> raised;
  fit::IterationCallback on_iteration;
  if (!progress.is_none()) {
    on_iteration = [&](std::size_t g, const fit::GuessResult& r) {
      py::gil_scoped_acquire gil;  // (the calls are serialized: `raised` needs no other lock)
      if (raised) return;
      try {
        py::dict info;
        info["guess"] = g;
        info["layer_depth"] = r.layer_depth;
        info["iteration"] = r.iterations;
        info["objective"] = r.objective_final;
        info["evaluations"] = r.evaluations;
        info["seconds"] = r.seconds;
        progress(info);
      } catch (py::error_already_set& e) {
        raised = std::move(e);
        request_interrupt();
      }
    };
  }
  std::optional<fit::FitSummary> summary;
  try {
    LongCall call;
    summary = fit::run_fit_in_folder(a.dataset, a.out, o, a.resume, a.overwrite,
                                     fmt::format("palpa.fit('{}', model='{}')", a.dataset, a.model), on_iteration);
  } catch (const Error& e) {
    if (raised && e.kind() == ErrorKind::Interrupted) throw std::move(*raised);
    throw;
  }
  if (raised) throw std::move(*raised);
  return summary.has_value();
}

}  // namespace

void bind_fit(py::module_& m) {
  m.def(
      "_fit",
      [](const std::string& dataset, const std::string& out, const std::string& model, const std::string& optimizer,
         bool resume, bool overwrite, const py::object& progress, int max_iterations, double tolerance,
         const std::vector<std::string>& fix, std::optional<std::pair<double, double>> nu_range, int starts,
         int ogden_terms, const std::string& element, int mesh_level, int steps, const std::string& depth_from,
         double smoothing, std::optional<std::string> initial) {
        FitArgs a{dataset, out, model, optimizer, element, depth_from, resume, overwrite, max_iterations, starts,
                  ogden_terms, mesh_level, steps, tolerance, smoothing, fix, nu_range, initial};
        return run(a, progress);
      },
      py::arg("dataset"), py::arg("out"), py::arg("model"), py::arg("optimizer"), py::arg("resume"),
      py::arg("overwrite"), py::arg("progress"), py::arg("max_iterations"), py::arg("tolerance"), py::arg("fix"),
      py::arg("nu_range"), py::arg("starts"), py::arg("ogden_terms"), py::arg("element"), py::arg("mesh_level"),
      py::arg("steps"), py::arg("depth_from"), py::arg("smoothing"), py::arg("initial"),
      "Runs `palpa fit` into `out`; False when a resumed fit was already finished. Use palpa.fit.");
}

}  // namespace palpa::python
