// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A whole design run into an output folder, as `palpa design` runs it: read
// the scene, optimize with a checkpoint (resuming from it if asked), write the
// folder (output.hpp) and say what came of it.

#include <filesystem>
#include <optional>
#include <string>

#include "palpa/core/json.hpp"
#include "palpa/design/optimizer.hpp"

namespace palpa::design {

struct DesignRun {
  std::filesystem::path scene;     // the scene file (with `scene_json`: its nominal path, for messages and
                                   // relative paths)
  std::optional<Json> scene_json;  // the scene itself, when it is not read from `scene`
  std::filesystem::path out;
  bool resume = false;     // go on from out/checkpoint.json (afresh when there is none)
  bool overwrite = false;  // write into a folder that holds files
  bool baselines = true;   // also score the scene's baselines
  std::optional<int> iterations;  // overrides the scene's design.iterations
  std::optional<int> threads;     // overrides the scene's design.threads
  std::optional<DesignMethod> method;
  // Overrides the scene's design.start: a baseline's name, or "scene" for
  // the scene's own support.
  std::optional<std::string> start;
};

// Runs it. Returns the summary (summary.json), or nothing when a resumed run
// was already finished (it is left exactly as it is). `optimized`, if given,
// receives the optimized support [m]. Interrupted: the last
// finished iteration's support is written as support_interrupted.obj and the
// error is rethrown. A failure while writing takes back what was written.
std::optional<Json> run_design(const DesignRun& run, SurfaceMesh* optimized = nullptr);

// One line: both shapes solved from scratch, the optimizer's own view, the
// baselines it is worse than, iterations and time.
std::string design_headline(const Json& summary);

}  // namespace palpa::design
