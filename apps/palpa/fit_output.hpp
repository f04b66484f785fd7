// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The output folder of a fit (palpa fit, palpa demo): material.json,
// report.json, curves/<name>.csv, curves.svg, objective.svg and (depth search)
// depth.svg. Every file is written atomically, all at the end.

#include <filesystem>
#include <string>
#include <vector>

#include "palpa/fit/fit.hpp"

namespace palpa::cli {

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
std::vector<std::filesystem::path> fit_output_files(const std::filesystem::path& out, const fit::Dataset& d);

// Simulates every curve with the best guess's stage-1 and fitted materials and
// writes the folder. `command` is recorded in the provenance.
FitSummary write_fit_outputs(const std::filesystem::path& out, const fit::Dataset& d, const fit::FitOptions& o,
                             const fit::FitResult& r, double seconds, const std::string& command);

// Fit options with the model, optimizer and element named as on the command line.
fit::FitOptions fit_options_from(const std::string& model, const std::string& optimizer, const std::string& element);

// Reads the dataset, fits (checkpointing into out/checkpoint.json; resuming
// from it if asked), writes the outputs and logs a summary.
FitSummary run_fit(const std::filesystem::path& dataset_file, const std::filesystem::path& out,
                   const fit::FitOptions& o, bool resume, const std::string& command);

}  // namespace palpa::cli
