// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Writing the results of `palpa design` into a folder (each file atomic):
//   support.obj              the optimized support [m]
//   support_mm.stl           the same in millimetres, for slicers
//   support_before.vtu/.ply, support_after.vtu/.ply
//                            pressure_Pa, pressure_smoothed_Pa (p̄ of the
//                            score); after: design_displacement_m from the
//                            initial shape
//   body_before.vtu, body_after.vtu, skin_before.ply, skin_after.ply
//                            the deformed body with its pressures
//   score.svg                φ, ζ and γψ per iteration
//   pressure_histogram.svg   contact pressures before and after
//   body_pressure.svg, support_pressure.svg
//                            each side's map as a picture, initial beside
//                            optimized on one colour scale
//   summary.json             scores, reduction, peaks, penetration, balance,
//                            iterations, solves, times, per-iteration history
// (checkpoint.json, written during the run, stays for --resume; an
// interrupted run leaves support_interrupted.obj and _mm.stl, its last
// accepted shape, which a finished run removes.)

#include <filesystem>
#include <string>

#include "palpa/core/json.hpp"
#include "palpa/design/optimizer.hpp"
#include "palpa/design/scene.hpp"
#include "palpa/report/html.hpp"

namespace palpa::design {

// Re-solves the initial and the final shape on simulation 0 (warm: a few
// Newton iterations at most) to write their fields. Returns the summary.
Json write_design_outputs(const std::filesystem::path& out, const DesignScene& scene, ShapeOptimizer& optimizer,
                          const DesignResult& result);

// A support shape to make: out/<stem>.obj [m] and out/<stem>_mm.stl [mm].
// report.html of a design folder: the pressure maps before and after, the
// scores of the initial, designed and baseline supports, the score history
// (from its summary.json figures and the pictures beside it).
report::HtmlReport design_report_html(const std::filesystem::path& out, const Json& summary);
// Its sections, for a report that holds a design among other things.
void add_design_sections(report::HtmlReport& h, const std::filesystem::path& out, const Json& summary);
// One line of a design's summary: ζ and the body's peak before and after.
std::string design_headline_text(const Json& summary);

void write_support_shape(const std::filesystem::path& out, const std::string& stem, const SurfaceMesh& shape);

}  // namespace palpa::design
