// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A whole fit into an output folder, as `palpa fit` and `palpa demo` run it:
// read the dataset, fit with progress and a checkpoint, write the folder
// (output.hpp) and log the summary.

#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "palpa/fit/fit.hpp"
#include "palpa/fit/output.hpp"

namespace palpa::fit {

// Fit options with the model, optimizer and element named as on the command
// line (an unknown element is an Input error naming option --element).
FitOptions fit_options_from(const std::string& model, const std::string& optimizer, const std::string& element);

// Called (serialized) after each recorded iteration of a layer-depth guess.
using IterationCallback = std::function<void(std::size_t guess, const GuessResult&)>;

// Reads the dataset, fits (checkpointing into out/checkpoint.json; resuming
// from it if asked), writes the outputs and logs a summary. `command` is
// recorded in the provenance.
FitSummary run_fit(const std::filesystem::path& dataset_file, const std::filesystem::path& out, const FitOptions& o,
                   bool resume, const std::string& command, const IterationCallback& on_iteration = {});

// run_fit as a command runs it: `resume` goes on from out/checkpoint.json
// (afresh when there is none) and leaves a finished fit exactly as it is
// (returning nothing); without it the folder must be empty unless
// `overwrite`. Interrupted: says where the checkpoint is and rethrows.
std::optional<FitSummary> run_fit_in_folder(const std::filesystem::path& dataset_file, const std::filesystem::path& out,
                                            const FitOptions& o, bool resume, bool overwrite, const std::string& command,
                                            const IterationCallback& on_iteration = {});

}  // namespace palpa::fit
