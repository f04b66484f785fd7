// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// One support for a cohort of subjects: the cohort design scene
// (design/scene.hpp) of the subjects' bodies, each as `palpa subject body`
// wrote it (<results>/<subject>/body/design.json), on the support, contact
// and design settings of their common design template.

#include <filesystem>
#include <vector>

#include "palpa/core/json.hpp"
#include "palpa/pipeline/subject.hpp"

namespace palpa::pipeline {

// {"palpa_design": 1, "bodies": [{"name", "scene"}...], "cohort":
// {"objective": "mean", "single_designs": true, "start": "baseline"}, and
// the first subject's
// design scene but its body, core and baselines (a cohort's support is
// compared body by body) and its start}. Paths absolute. Throws palpa::Error
// (Input) for fewer than two subjects, subjects whose design templates
// differ (naming both), and a body scene that is not there yet (naming it:
// run `palpa subject body` first).
Json cohort_design_scene(const std::vector<Subject>& subjects, const std::filesystem::path& results);

}  // namespace palpa::pipeline
