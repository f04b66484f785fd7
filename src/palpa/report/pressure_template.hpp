// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A simulated pressure map against a measured template on a grid (a plantar
// template such as MUN104: the mean pressure of many people's feet on a
// sensor grid), compared where neither shares a mesh with the other:
//
//   const report::PressureGrid t = report::read_pressure_grid("MUN104L.csv", 5e-3, 1e3);
//   const report::TemplateComparison c = report::compare_with_template(skin, pressure, {0, 0, 1},
//   t); report::write_template_comparison_svg("template.svg", c, t, "simulated", "MUN104 (left)");
//
// Alignment: each footprint (the template's pixels with a pressure; the
// simulated skin triangles with a pressure at any corner, seen along the
// plate's normal) has a centroid and principal axes (its area's second
// moments); the simulated footprint is moved onto the template's, its major
// axis onto the template's major axis, and stretched along each axis so that
// their spreads (the square roots of the second moments) agree. Of the four
// ways the axes can point (heel to toe or back, the arch on either side) the
// one that correlates best is kept; the comparison reports which, and the
// stretches, so that a foot compared with the wrong side shows.
//
// The simulated map is then read as the template's sensors read pressure: the
// mean over each pixel (4 × 4 points across it; linear over the skin
// triangles, the largest where triangles overlap in the view, 0 off the
// footprint), and the two compared by Pearson's correlation over the
// pixels where either has a pressure: a pattern's likeness, blind to scale (a
// template of walking and a simulation of standing differ in level).

#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "palpa/geometry/mesh.hpp"

namespace palpa::report {

// Pressures on a regular grid: pressure(r, c) [Pa] at the pixel centre
// x = (c + ½)·pixel, y = (r + ½)·pixel.
struct PressureGrid {
  Eigen::MatrixXd pressure;
  double pixel = 5e-3;  // [m]
};

// A grid stored as CSV rows of numbers without a header (row r of the file is
// grid row r), in the unit `to_pa` Pa (1e3 for kPa); pixel [m]. Throws
// palpa::Error (Input) naming the file, line and column: an unreadable or
// empty file, a field that is not a finite number ≥ 0, rows of unequal
// length, a grid with no pressure; and for pixel or to_pa not > 0.
PressureGrid read_pressure_grid(const std::filesystem::path& path, double pixel, double to_pa);

struct TemplateComparison {
  PressureGrid simulated;    // the simulated map on the template's grid, aligned
  double correlation = 0.0;  // Pearson r over `pixels`
  Eigen::Index pixels = 0;   // pixels where either map has a pressure
  double template_peak = 0.0, simulated_peak = 0.0;  // [Pa], on the grid
  bool length_reversed = false;  // the simulated major axis runs against the template's
  bool width_reversed = false;   // ... and the minor axis
  // Template spread over simulated spread along the major and minor axes.
  double length_scale = 1.0, width_scale = 1.0;
};

// skin: the deformed surface [m] with per-vertex pressure [Pa] (≥ 0);
// normal: the plate's normal (the direction the footprint is seen along).
// Throws palpa::Error (Input) when either map has no pressure, or a footprint
// has no area seen along the normal.
TemplateComparison compare_with_template(const SurfaceMesh& skin, const Eigen::VectorXd& pressure,
                                         const Eigen::Vector3d& normal,
                                         const PressureGrid& reference);

// The two grids side by side as an SVG picture, each coloured on its own
// scale (viridis from 0 to its peak; grey where there is no pressure), with
// the peaks, the correlation and the alignment in the caption.
void write_template_comparison_svg(const std::filesystem::path& path, const TemplateComparison& c,
                                   const PressureGrid& reference,
                                   const std::string& simulated_title,
                                   const std::string& reference_title);

}  // namespace palpa::report
