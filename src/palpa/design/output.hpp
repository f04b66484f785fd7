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
#include "palpa/report/plot.hpp"

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

// A summary's parts every design run has: the design's settings; the run's
// iterations, solves, times, termination and history.
Json design_settings_json(const DesignScene& scene, const ShapeOptimizer& optimizer, const DesignResult& r);
Json run_json(const DesignResult& r);
// φ, the score term (labelled zeta_label) and γψ per iteration, on a log axis.
report::Plot objective_plot(const DesignResult& r, const std::string& unit_label, const std::string& zeta_label);
// An evaluation's figures for a summary (its first body's): scores, peaks,
// contacts, the maps' forces and metrics, penetration, balance.
Json evaluation_json(const Evaluation& e, double gamma);
// One state (tag: before, after, resolved) of `sim` at evaluation e into
// out: body_<tag>.vtu, support_<tag>.vtu/.ply, skin_<tag>.ply, with the
// Pose-to-Seat estimate beside palpa's pressures (and `displacement`, the
// design's moves, on the support). Returns the estimate's figures and its
// comparison with palpa's support-side map.
Json write_design_state(const std::filesystem::path& out, const std::string& tag, rest::RestSimulation& sim,
                        const Evaluation& e, const Eigen::MatrixX3d* displacement, double threshold);

}  // namespace palpa::design
