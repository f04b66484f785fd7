// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Writing the results of a cohort design (`palpa design` on a scene with
// "bodies", design/scene.hpp) into a folder. Every body is solved from
// scratch on the initial and on the optimized support (the automatic contact
// stiffness, no warm start), and those solves are what every figure reports:
//   support.obj, support_mm.stl   the one optimized support [m] / [mm]
//   cohort.csv                    per body: ζ_body, body peak, PPI, mean
//                                 pressure, contact area, before and after
//   cohort.svg                    the cohort's spread: each body's ζ_body
//                                 over its own initial value, and its peak,
//                                 before and after (and with its own design)
//   score.svg                     the objective per iteration
//   bodies/<name>/                per body: body_pressure.svg and
//                                 support_pressure.svg (initial beside
//                                 optimized), body_/support_/skin_ before and
//                                 after (.vtu, .ply), summary.json
//   report.html, summary.json     the cohort's figures and every body's

#include <filesystem>
#include <string>
#include <vector>

#include "palpa/core/json.hpp"
#include "palpa/design/optimizer.hpp"
#include "palpa/design/scene.hpp"
#include "palpa/report/html.hpp"

namespace palpa::design {

// Returns the summary. `singles`: each body's own design's figures (empty
// when the scene asks for none), reported beside the cohort's as the price
// of one support for all. Throws palpa::Error (Solver) naming the body whose
// from-scratch solve fails.
Json write_cohort_outputs(const std::filesystem::path& out, const DesignScene& scene, ShapeOptimizer& optimizer,
                          const DesignResult& result, const std::vector<Json>& singles = {});

// report.html of a cohort design folder (from its summary.json figures and
// the pictures beside it).
report::HtmlReport cohort_report_html(const std::filesystem::path& out, const Json& summary);
// One line: every body's ζ_body before and after, the mean over the cohort.
std::string cohort_headline_text(const Json& summary);

}  // namespace palpa::design
