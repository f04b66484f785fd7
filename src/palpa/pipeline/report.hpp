// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The subject's report (pipeline step "report"): one self-contained HTML file
// (report/html.hpp) from what the pipeline wrote in the subject's results
// folder: per location the measured and fitted curves and the material; the
// depth and stiffness fields on the body; the body at rest on the initial
// support; the designed support's pressure maps before and after, its score
// history and baselines; the measured map against the simulated one. A step
// that did not run leaves a line saying so, not a failure.

#include <filesystem>

#include "palpa/pipeline/subject.hpp"
#include "palpa/report/html.hpp"

namespace palpa::pipeline {

// results: the subject's folder (fits/, body/, rest/, design/, compare.json).
report::HtmlReport subject_report(const Subject& s, const std::filesystem::path& results);

}  // namespace palpa::pipeline
