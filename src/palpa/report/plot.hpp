// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Line and scatter plots as self-contained SVG 1.1 documents, for people to look
// at: measured force–indentation curves as dots beside simulated ones as lines,
// an objective per iteration on a log axis, raw against filtered signals.
//
//   report::Figure fig;
//   fig.title = "forearm, punch 4 mm";
//   report::Plot& p = fig.plots.emplace_back();
//   p.x.label = "indentation [mm]";
//   p.y.label = "force [N]";
//   p.series.push_back({"measured", d_mm, f_measured, report::Mark::Dots});
//   p.series.push_back({"simulated", d_mm, f_simulated, report::Mark::Line, 0});
//   report::write_svg("fit.svg", fig);
//
// Layout: one SVG document holds the plots of a figure in a grid of `columns`
// columns, row by row; every cell is plot_width × plot_height pixels, the
// figure title (if any) sits above the grid. Each plot has a title, axis labels,
// nice tick values (report/ticks.hpp) with light grid lines, and a legend of the
// labelled series, placed inside the plot in the corner that covers the fewest
// data points, or beside the plot when every corner would cover some.
//
// Data rules:
//  - A non-finite x or y breaks a series: lines are not drawn across it.
//  - On a log axis, points with a value <= 0 on that axis are dropped from
//    their series (and break lines like a non-finite value). A log axis whose
//    data has no positive value at all is an error.
//  - Series with no drawable point are skipped (no marks, no legend entry); a
//    plot with none at all shows "no data". A figure without plots renders one
//    empty plot.
//  - A line series' isolated points (no neighbour to join) are drawn as small
//    dots so that they stay visible.
//  - Lines are clipped at the plot frame; points outside fixed axis bounds get
//    no dot.
//  - Text (titles, labels) is escaped for XML; control characters and
//    invalid UTF-8 are replaced by U+FFFD.
// Output is deterministic (same figure, same bytes) and compact: coordinates are
// rounded to 0.1 px.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace palpa::report {

// How a series is drawn.
enum class Mark {
  Line,      // polyline through the points
  Dots,      // a small filled circle at each point
  LineDots,  // both
};

// The colour-blind-safe palette (Okabe & Ito 2008), in the order colours are
// handed out: blue, vermillion, bluish green, reddish purple, orange, sky blue,
// black, yellow. Indices wrap around.
inline constexpr int kPaletteSize = 8;
// "#rrggbb" of palette index `index` (>= 0, wraps around).
const char* palette_color(int index) noexcept;

struct Series {
  std::string label;         // legend text; "" keeps the series out of the legend
  std::vector<double> x, y;  // point coordinates in data units; same length
  Mark mark = Mark::Line;
  // Palette index (>= 0), or -1: the index after the previous series' colour in
  // this plot (0 for the first series).
  int color = -1;
  bool dashed = false;  // dashed line (lines only)
};

struct Axis {
  std::string label;                         // e.g. "indentation [mm]"
  bool log = false;                          // base-10 logarithmic axis
  std::optional<double> min = std::nullopt;  // fixed bounds; unset: from the data
  std::optional<double> max = std::nullopt;
};

struct Plot {
  std::string title;
  Axis x, y;
  std::vector<Series> series;
};

struct Figure {
  std::vector<Plot> plots;
  int columns = 1;           // plots per row, >= 1
  double plot_width = 480;   // size of one grid cell [px], >= 160
  double plot_height = 320;  // [px], >= 120
  std::string title;         // above all plots; "" for none
};

// The figure as an SVG document (UTF-8).
// Throws palpa::Error (Input) for bad input, naming the plot and series: x and y
// of different lengths, columns < 1, cell size too small, a colour < -1, fixed
// axis bounds that are not finite, not increasing, or <= 0 on a log axis, a log
// axis without positive data.
std::string render_svg(const Figure& figure);

// Renders `figure` and writes it to `path` atomically (core/atomic_file.hpp).
void write_svg(const std::filesystem::path& path, const Figure& figure);

}  // namespace palpa::report
