// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The output folder of a fit (palpa fit, palpa demo): material.json,
// report.json, curves/<name>.csv, curves.svg, objective.svg and (depth search)
// depth.svg. Every file is written atomically, all at the end; and the
// one-line texts a summary prints.

#include <filesystem>
#include <string>
#include <vector>

#include "palpa/fit/fit.hpp"

namespace palpa::fit {

struct FitSummary {
  double sqrt_objective_stage1 = 0.0;
  double sqrt_objective_final = 0.0;
  double rms_train = 0.0;     // over all training points, fitted material
  double rms_validate = 0.0;  // over the validation points simulated (NaN without any)
  std::size_t validate_points = 0;        // validation points compared
  std::size_t validate_points_total = 0;  // validation points measured
  // Validation curves the fitted material's simulation did not carry to their
  // last point: "r1.03mm to 3.61 of 4.05 mm".
  std::vector<std::string> validate_short;
  double seconds = 0.0;
};

// Every file write_fit_outputs and the checkpoint write into `out`.
std::vector<std::filesystem::path> fit_output_files(const std::filesystem::path& out, const Dataset& d);

// Simulates every curve with the best guess's stage-1 and fitted materials and
// writes the folder. `command` is recorded in the provenance.
FitSummary write_fit_outputs(const std::filesystem::path& out, const Dataset& d, const FitOptions& o,
                             const FitResult& r, double seconds, const std::string& command);

// "0.067 N (over 48 of 52 points: simulated r1.03mm to 3.61 of 4.05 mm)", or
// "n/a (no validation curve)"; `unit` of the residuals.
std::string validation_text(const FitSummary& s, const char* unit);

// "E (small strain) = 88.06 kPa, 95% 87.61 to 88.5 kPa; nu = 0.4999, 95% ...;
// layer depth ..." (the depth when `layer_depth` > 0).
std::string estimates_text(const Uncertainty& u, const material::Material& m, double layer_depth);

}  // namespace palpa::fit
