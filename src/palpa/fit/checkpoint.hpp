// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The checkpoint file of a fit (JSON, written atomically after every
// iteration): a fingerprint of the inputs (dataset and curve files, options,
// initial material) and, per layer-depth guess, its results so far and the
// optimizer state. Resuming refuses a checkpoint whose fingerprint differs.

#include <filesystem>
#include <string>

#include "palpa/axisym/poke.hpp"
#include "palpa/core/json.hpp"
#include "palpa/fit/fit.hpp"
#include "palpa/fit/optimize.hpp"

namespace palpa::fit {

class Checkpoint {
 public:
  // An empty path disables checkpoints.
  Checkpoint(std::filesystem::path path, const Dataset& d, const FitOptions& o, const material::Material& initial);

  // Reads the file. Throws palpa::Error (Input) if it is missing, malformed or
  // belongs to another fit.
  void load();
  // Records guess g and writes the file. `warm` (may be null): the curve
  // simulators' warm starts (TrainingProblem::warm_starts), kept in a binary
  // file beside the checkpoint (named in it, with its size and fingerprint;
  // written first, under a new name each time, so the checkpoint never names a
  // half-written one).
  void store(std::size_t g, const GuessResult& r, const GuessState& s,
             const std::vector<axisym::WarmStart>* warm = nullptr);
  // Fills r and s (and warm, if the checkpoint has them) from the loaded
  // file; false if guess g was not started. Throws palpa::Error (Input) if
  // the warm-start file it names is missing or damaged.
  bool restore(std::size_t g, GuessResult& r, GuessState& s, std::vector<axisym::WarmStart>* warm = nullptr) const;

  // Whether the loaded file records guess g as done.
  bool done(std::size_t g) const;

  const std::string& fingerprint() const noexcept { return fingerprint_; }

 private:
  std::filesystem::path path_;
  std::vector<int> warm_serial_;  // per guess: how many warm-start files were written
  std::string fingerprint_;
  Json doc_;
};

}  // namespace palpa::fit
