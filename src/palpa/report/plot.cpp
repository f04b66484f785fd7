// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/report/plot.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string_view>
#include <utility>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/report/svg_text.hpp"
#include "palpa/report/ticks.hpp"

namespace palpa::report {
namespace {

// Okabe–Ito colours in hand-out order (see plot.hpp).
constexpr std::array<const char*, kPaletteSize> kPalette = {
    "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000", "#F0E442"};

// Sizes in px.
constexpr double kMinCellWidth = 160;
constexpr double kMinCellHeight = 120;
constexpr double kFigureTitleHeight = 30;
constexpr double kFigureTitleSize = 15;
constexpr double kTitleSize = 13;
constexpr double kLabelSize = 12;
constexpr double kTickSize = 11;
constexpr double kLegendSize = 11;
constexpr double kTickLength = 4;
constexpr double kMinorTickLength = 2.5;
constexpr double kGap = 6;   // between tick marks, tick labels and axis labels
constexpr double kEdge = 8;  // cell edge to outermost text
constexpr double kMinYTickSpacing = 28;
constexpr double kMinXLabelGap = 10;  // between neighbouring x tick labels
constexpr double kLineWidth = 1.6;
constexpr double kDotRadius = 2.6;
constexpr double kIsolatedDotRadius = 1.6;
constexpr double kLegendRow = 16;
constexpr double kLegendPad = 6;
constexpr double kLegendGlyph = 22;
constexpr double kLegendInset = 6;  // legend box to plot frame
constexpr double kLegendSample = 3;
constexpr double kOnFrame = 0.05;  // px: a point this close to the frame is inside    // px between
                                   // samples along a line when counting hidden data
constexpr int kMaxLabels = 8;
constexpr const char* kDash = "6 4";
constexpr const char* kGridColor = "#e6e6e6";
constexpr const char* kFrameColor = "#777";
constexpr const char* kTextColor = "#222";

std::string where(std::size_t plot_index, const Plot& plot) {
  std::string s = "plot " + std::to_string(plot_index + 1);
  if (!plot.title.empty()) s += " ('" + plot.title + "')";
  return s;
}

std::string where(std::size_t plot_index, const Plot& plot, std::size_t series_index,
                  const Series& series) {
  std::string s = where(plot_index, plot) + ", series " + std::to_string(series_index + 1);
  if (!series.label.empty()) s += " ('" + series.label + "')";
  return s;
}

struct Point {
  double x, y;
};
using Run = std::vector<Point>;  // consecutive drawable points (data units)

struct PreparedSeries {
  const Series* series = nullptr;
  const char* color = "";
  std::vector<Run> runs;
};

struct Range {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool empty() const { return lo > hi; }
};

struct PreparedPlot {
  const Plot* plot = nullptr;
  std::vector<PreparedSeries> series;  // only those with drawable points
  Range x, y;
};

void check_axis(const Axis& axis, const char* name, const std::string& context) {
  const auto field = ErrorContext{}.with_field(context + ", " + name + " axis");
  for (const auto& b : {axis.min, axis.max})
    if (b && !std::isfinite(*b))
      throw_input_error("axis bound is not finite", field, "a finite number");
  if (axis.log)
    for (const auto& b : {axis.min, axis.max})
      if (b && *b <= 0) throw_input_error("log axis bound is <= 0", field, "a positive bound");
  if (axis.min && axis.max && !(*axis.min < *axis.max))
    throw_input_error("axis min is not below max", field, "min < max");
}

PreparedPlot prepare(const Plot& plot, std::size_t plot_index) {
  const std::string context = where(plot_index, plot);
  check_axis(plot.x, "x", context);
  check_axis(plot.y, "y", context);
  PreparedPlot out;
  out.plot = &plot;
  int previous_color = -1;
  bool any_finite = false;
  bool x_positive = false, y_positive = false;
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const Series& s = plot.series[i];
    if (s.x.size() != s.y.size())
      throw_input_error(
          "x has " + std::to_string(s.x.size()) + " values but y has " + std::to_string(s.y.size()),
          ErrorContext{}.with_field(where(plot_index, plot, i, s)), "x and y of the same length");
    if (s.color < -1)
      throw_input_error("colour index " + std::to_string(s.color) + " is negative",
                        ErrorContext{}.with_field(where(plot_index, plot, i, s)),
                        "a palette index >= 0, or -1 for the next colour");
    const int color = s.color >= 0 ? s.color : previous_color + 1;
    previous_color = color;
    PreparedSeries p;
    p.series = &s;
    p.color = palette_color(color);
    Run run;
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      const double x = s.x[k], y = s.y[k];
      bool ok = std::isfinite(x) && std::isfinite(y);
      if (ok) {
        any_finite = true;
        x_positive |= x > 0;
        y_positive |= y > 0;
        ok = (!plot.x.log || x > 0) && (!plot.y.log || y > 0);
      }
      if (ok) {
        run.push_back({x, y});
        out.x.add(x);
        out.y.add(y);
      } else if (!run.empty()) {
        p.runs.push_back(std::move(run));
        run.clear();
      }
    }
    if (!run.empty()) p.runs.push_back(std::move(run));
    if (!p.runs.empty()) out.series.push_back(std::move(p));
  }
  if (any_finite) {
    if (plot.x.log && !x_positive)
      throw_input_error("log x axis has no positive value",
                        ErrorContext{}.with_field(context + ", x axis"), "some x > 0");
    if (plot.y.log && !y_positive)
      throw_input_error("log y axis has no positive value",
                        ErrorContext{}.with_field(context + ", y axis"), "some y > 0");
    if (out.series.empty())  // every positive x pairs with a non-positive y or vice versa
      throw_input_error("no point has positive values on both log axes",
                        ErrorContext{}.with_field(context), "some points with x > 0 and y > 0");
  }
  return out;
}

struct Box {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // x0 < x1, y0 < y1 (y down)
  bool contains(double x, double y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};

struct Layout {
  Box area;  // the data area (plot frame)
  AxisTicks xt, yt;
  bool legend = false;
  Box legend_box;
  std::size_t hidden = 0;  // data samples under the legend

  double map(double v, const AxisTicks& t, double a, double b) const {
    const double f = t.log ? std::log10(v) : v;
    const double f0 = t.log ? std::log10(t.min) : t.min;
    const double f1 = t.log ? std::log10(t.max) : t.max;
    return a + (f - f0) / (f1 - f0) * (b - a);
  }
  double px(double x) const { return map(x, xt, area.x0, area.x1); }
  double py(double y) const { return map(y, yt, area.y1, area.y0); }
};

struct LegendSize {
  double width = 0, height = 0;
  std::size_t entries = 0;
};

LegendSize legend_size(const PreparedPlot& p) {
  LegendSize s;
  double text = 0;
  for (const auto& ps : p.series)
    if (!ps.series->label.empty()) {
      ++s.entries;
      text = std::max(text, estimated_text_width(ps.series->label, kLegendSize));
    }
  if (s.entries == 0) return s;
  s.width = 3 * kLegendPad + kLegendGlyph + text;
  s.height =
      2 * kLegendPad + kLegendRow * static_cast<double>(s.entries) - (kLegendRow - kLegendSize);
  return s;
}

// Number of data samples (points, and points every few px along lines) inside `box`.
std::size_t samples_inside(const PreparedPlot& p, const Layout& l, const Box& box) {
  std::size_t n = 0;
  for (const auto& ps : p.series) {
    const bool line = ps.series->mark != Mark::Dots;
    for (const auto& run : ps.runs) {
      double qx = 0, qy = 0;
      for (std::size_t i = 0; i < run.size(); ++i) {
        const double x = l.px(run[i].x), y = l.py(run[i].y);
        if (box.contains(x, y)) ++n;
        if (line && i > 0) {
          const double len = std::hypot(x - qx, y - qy);
          const auto steps = static_cast<int>(std::min(len / kLegendSample, 1000.0));
          for (int k = 1; k < steps; ++k) {
            const double t = static_cast<double>(k) / steps;
            if (box.contains(qx + t * (x - qx), qy + t * (y - qy))) ++n;
          }
        }
        qx = x;
        qy = y;
      }
    }
  }
  return n;
}

Layout make_layout(const PreparedPlot& p, double cx, double cy, double w, double h,
                   bool legend_outside) {
  const Plot& plot = *p.plot;
  Layout l;
  const double top = kEdge + (plot.title.empty() ? 4 : kTitleSize + kGap);
  const double bottom =
      kTickLength + kGap + kTickSize + kEdge + (plot.x.label.empty() ? 0 : kLabelSize + kGap);
  l.area.y0 = cy + top;
  l.area.y1 = cy + h - bottom;
  if (p.series.empty()) {
    l.area.x0 = cx + kEdge + (plot.y.label.empty() ? 0 : kLabelSize + kGap) + 2 * kGap;
    l.area.x1 = cx + w - 2 * kEdge;
    return l;
  }
  const int y_labels =
      std::clamp(static_cast<int>((l.area.y1 - l.area.y0) / kMinYTickSpacing) + 1, 2, kMaxLabels);
  l.yt = choose_ticks(p.y.lo, p.y.hi, plot.y.log, plot.y.min, plot.y.max, y_labels);
  double y_text = 0;
  for (const auto& t : l.yt.major)
    y_text = std::max(y_text, estimated_text_width(t.label, kTickSize));
  l.area.x0 =
      cx + kEdge + (plot.y.label.empty() ? 0 : kLabelSize + kGap) + y_text + kGap + kTickLength;
  const LegendSize legend = legend_size(p);
  double right = 2 * kEdge;
  if (legend_outside) right += legend.width + kLegendInset;
  l.area.x1 = cx + w - right;
  // x ticks: as many as fit without labels touching.
  for (int n = kMaxLabels; n >= 2; --n) {
    l.xt = choose_ticks(p.x.lo, p.x.hi, plot.x.log, plot.x.min, plot.x.max, n);
    bool fits = true;
    for (std::size_t i = 1; i < l.xt.major.size(); ++i) {
      const auto& a = l.xt.major[i - 1];
      const auto& b = l.xt.major[i];
      const double room = l.px(b.value) - l.px(a.value);
      const double need = 0.5 * (estimated_text_width(a.label, kTickSize) +
                                 estimated_text_width(b.label, kTickSize)) +
                          kMinXLabelGap;
      if (room < need) fits = false;
    }
    if (fits) break;
  }
  // Room for the last x label's right half.
  if (!l.xt.major.empty()) {
    const Tick& last = l.xt.major.back();
    const double overflow =
        l.px(last.value) + 0.5 * estimated_text_width(last.label, kTickSize) - (cx + w - kEdge);
    if (overflow > 0) l.area.x1 -= overflow;
  }
  if (legend.entries > 0) {
    l.legend = true;
    if (legend_outside) {
      const double x0 = l.area.x1 + kLegendInset;
      l.legend_box = {x0, l.area.y0, x0 + legend.width, l.area.y0 + legend.height};
    } else {
      // Corners in order of preference: top right, top left, bottom right, bottom left.
      const double lw = legend.width, lh = legend.height;
      const Box& a = l.area;
      const std::array<Box, 4> corners = {Box{a.x1 - kLegendInset - lw, a.y0 + kLegendInset,
                                              a.x1 - kLegendInset, a.y0 + kLegendInset + lh},
                                          Box{a.x0 + kLegendInset, a.y0 + kLegendInset,
                                              a.x0 + kLegendInset + lw, a.y0 + kLegendInset + lh},
                                          Box{a.x1 - kLegendInset - lw, a.y1 - kLegendInset - lh,
                                              a.x1 - kLegendInset, a.y1 - kLegendInset},
                                          Box{a.x0 + kLegendInset, a.y1 - kLegendInset - lh,
                                              a.x0 + kLegendInset + lw, a.y1 - kLegendInset}};
      l.hidden = std::numeric_limits<std::size_t>::max();
      for (const Box& b : corners) {
        // Count points whose dots would touch the box too.
        const Box near{b.x0 - kDotRadius, b.y0 - kDotRadius, b.x1 + kDotRadius, b.y1 + kDotRadius};
        const std::size_t n = samples_inside(p, l, near);
        if (n < l.hidden) {
          l.hidden = n;
          l.legend_box = b;
        }
      }
    }
  }
  return l;
}

// ---- SVG output ----

void draw_axes(SvgWriter& svg, const Layout& l) {
  const Box& a = l.area;
  // Grid lines.
  svg << "<path stroke=\"" << kGridColor << "\" shape-rendering=\"crispEdges\" d=\"";
  for (const auto& t : l.xt.major) {
    const double x = l.px(t.value);
    if (x > a.x0 + 0.5 && x < a.x1 - 0.5) svg << "M" << x << " " << a.y0 << "V" << a.y1;
  }
  for (const auto& t : l.yt.major) {
    const double y = l.py(t.value);
    if (y > a.y0 + 0.5 && y < a.y1 - 0.5) svg << "M" << a.x0 << " " << y << "H" << a.x1;
  }
  svg << "\"/>\n";
  // Frame and tick marks.
  svg << "<rect class=\"frame\" x=\"" << a.x0 << "\" y=\"" << a.y0 << "\" width=\"" << (a.x1 - a.x0)
      << "\" height=\"" << (a.y1 - a.y0) << "\" fill=\"none\" stroke=\"" << kFrameColor << "\"/>\n";
  svg << "<path stroke=\"" << kFrameColor << "\" d=\"";
  for (const auto& t : l.xt.major) svg << "M" << l.px(t.value) << " " << a.y1 << "v" << kTickLength;
  for (double v : l.xt.minor) svg << "M" << l.px(v) << " " << a.y1 << "v" << kMinorTickLength;
  for (const auto& t : l.yt.major)
    svg << "M" << a.x0 << " " << l.py(t.value) << "h" << -kTickLength;
  for (double v : l.yt.minor) svg << "M" << a.x0 << " " << l.py(v) << "h" << -kMinorTickLength;
  svg << "\"/>\n";
  // Tick labels.
  svg << "<g class=\"xticks\" fill=\"" << kTextColor << "\" font-size=\"" << kTickSize
      << "\" text-anchor=\"middle\">\n";
  const double xl_y = a.y1 + kTickLength + kGap + 0.8 * kTickSize;
  for (const auto& t : l.xt.major) svg.text(l.px(t.value), xl_y, t.label, 0, "");
  svg << "</g>\n<g class=\"yticks\" fill=\"" << kTextColor << "\" font-size=\"" << kTickSize
      << "\" text-anchor=\"end\">\n";
  for (const auto& t : l.yt.major)
    svg.text(a.x0 - kTickLength - kGap / 2, l.py(t.value) + 0.35 * kTickSize, t.label, 0, "");
  svg << "</g>\n";
}

void draw_series(SvgWriter& svg, const PreparedSeries& ps, const Layout& l,
                 const std::string& clip_lines, const std::string& clip_dots) {
  const Series& s = *ps.series;
  const bool line = s.mark != Mark::Dots;
  const bool dots = s.mark != Mark::Line;
  // Pixel runs, with repeated (rounded) points dropped.
  std::vector<std::vector<std::pair<std::string, std::string>>> runs;
  for (const auto& run : ps.runs) {
    auto& r = runs.emplace_back();
    for (const auto& pt : run) {
      std::pair<std::string, std::string> q{svg_number(l.px(pt.x)), svg_number(l.py(pt.y))};
      if (r.empty() || r.back() != q) r.push_back(std::move(q));
    }
  }
  if (line) {
    svg << "<g class=\"line\" clip-path=\"url(#" << clip_lines << ")\" fill=\"none\" stroke=\""
        << ps.color << "\" stroke-width=\"" << kLineWidth
        << "\" stroke-linejoin=\"round\" stroke-linecap=\"round\"";
    if (s.dashed) svg << " stroke-dasharray=\"" << kDash << "\"";
    svg << ">\n";
    for (const auto& r : runs) {
      if (r.size() < 2) continue;
      svg << "<polyline points=\"";
      for (std::size_t i = 0; i < r.size(); ++i)
        svg << (i ? " " : "") << r[i].first << "," << r[i].second;
      svg << "\"/>\n";
    }
    svg << "</g>\n";
  }
  // Dots: every point for Dots/LineDots, isolated points of lines.
  bool any_dot = false;
  for (const auto& r : runs) any_dot |= dots || r.size() == 1;
  if (!any_dot) return;
  svg << "<g class=\"dots\" clip-path=\"url(#" << clip_dots << ")\" fill=\"" << ps.color << "\">\n";
  const std::string radius = svg_number(dots ? kDotRadius : kIsolatedDotRadius);
  // Points outside fixed axis bounds get no dot (a dot half inside the frame
  // would suggest a value on the bound).
  const Box& a = l.area;
  const Box inside{a.x0 - kOnFrame, a.y0 - kOnFrame, a.x1 + kOnFrame, a.y1 + kOnFrame};
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (!dots && runs[i].size() != 1) continue;  // lines: only isolated points
    std::pair<std::string, std::string> previous;
    for (const auto& pt : ps.runs[i]) {
      const double x = l.px(pt.x), y = l.py(pt.y);
      if (!inside.contains(x, y)) continue;
      std::pair<std::string, std::string> q{svg_number(x), svg_number(y)};
      if (q == previous) continue;
      svg << "<circle cx=\"" << q.first << "\" cy=\"" << q.second << "\" r=\"" << radius
          << "\"/>\n";
      previous = std::move(q);
    }
  }
  svg << "</g>\n";
}

void draw_legend(SvgWriter& svg, const PreparedPlot& p, const Layout& l) {
  const Box& b = l.legend_box;
  svg << "<g class=\"legend\" font-size=\"" << kLegendSize << "\" fill=\"" << kTextColor
      << "\">\n<rect x=\"" << b.x0 << "\" y=\"" << b.y0 << "\" width=\"" << (b.x1 - b.x0)
      << "\" height=\"" << (b.y1 - b.y0)
      << "\" rx=\"3\" fill=\"#fff\" fill-opacity=\"0.85\" stroke=\"#bbb\"/>\n";
  double y = b.y0 + kLegendPad + kLegendSize / 2;
  for (const auto& ps : p.series) {
    const Series& s = *ps.series;
    if (s.label.empty()) continue;
    const double gx = b.x0 + kLegendPad;
    if (s.mark != Mark::Dots) {
      svg << "<path d=\"M" << gx << " " << y << "h" << kLegendGlyph << "\" stroke=\"" << ps.color
          << "\" stroke-width=\"" << kLineWidth << "\"";
      if (s.dashed) svg << " stroke-dasharray=\"" << kDash << "\"";
      svg << "/>\n";
    }
    if (s.mark != Mark::Line)
      svg << "<circle cx=\"" << (gx + kLegendGlyph / 2) << "\" cy=\"" << y << "\" r=\""
          << kDotRadius << "\" fill=\"" << ps.color << "\"/>\n";
    svg.text(gx + kLegendGlyph + kLegendPad, y + 0.35 * kLegendSize, s.label, 0, "");
    y += kLegendRow;
  }
  svg << "</g>\n";
}

void draw_plot(SvgWriter& svg, const PreparedPlot& p, std::size_t index, double cx, double cy,
               double w, double h) {
  const Plot& plot = *p.plot;
  Layout l = make_layout(p, cx, cy, w, h, false);
  if (l.legend && l.hidden > 0) {
    // Every corner covers data: put the legend beside the plot if that leaves
    // the data area at least half the cell.
    Layout outside = make_layout(p, cx, cy, w, h, true);
    if (outside.area.x1 - outside.area.x0 >= 0.5 * w) l = std::move(outside);
  }
  const Box& a = l.area;
  svg << "<g class=\"plot\">\n";
  if (!plot.title.empty())
    svg.text(0.5 * (a.x0 + a.x1), cy + kEdge + kTitleSize * 0.8, plot.title, kTitleSize, "middle",
             std::string("font-weight=\"bold\" fill=\"") + kTextColor + "\"");
  if (!plot.x.label.empty())
    svg.text(0.5 * (a.x0 + a.x1), cy + h - kEdge, plot.x.label, kLabelSize, "middle",
             std::string("fill=\"") + kTextColor + "\"");
  if (!plot.y.label.empty()) {
    const double x = cx + kEdge + kLabelSize * 0.8;
    const double y = 0.5 * (a.y0 + a.y1);
    svg.text(x, y, plot.y.label, kLabelSize, "middle",
             "transform=\"rotate(-90 " + svg_number(x) + " " + svg_number(y) + ")\" fill=\"" +
                 kTextColor + "\"");
  }
  if (p.series.empty()) {
    svg << "<rect class=\"frame\" x=\"" << a.x0 << "\" y=\"" << a.y0 << "\" width=\""
        << (a.x1 - a.x0) << "\" height=\"" << (a.y1 - a.y0) << "\" fill=\"none\" stroke=\""
        << kFrameColor << "\"/>\n";
    svg.text(0.5 * (a.x0 + a.x1), 0.5 * (a.y0 + a.y1) + 0.35 * kLabelSize, "no data", kLabelSize,
             "middle", "fill=\"#888\"");
    svg << "</g>\n";
    return;
  }
  const std::string clip_lines = "clip" + std::to_string(index);
  const std::string clip_dots = clip_lines + "d";
  const double m = kDotRadius + 1;
  svg << "<defs><clipPath id=\"" << clip_lines << "\"><rect x=\"" << a.x0 << "\" y=\"" << a.y0
      << "\" width=\"" << (a.x1 - a.x0) << "\" height=\"" << (a.y1 - a.y0)
      << "\"/></clipPath><clipPath id=\"" << clip_dots << "\"><rect x=\"" << (a.x0 - m) << "\" y=\""
      << (a.y0 - m) << "\" width=\"" << (a.x1 - a.x0 + 2 * m) << "\" height=\""
      << (a.y1 - a.y0 + 2 * m) << "\"/></clipPath></defs>\n";
  draw_axes(svg, l);
  for (const auto& ps : p.series) draw_series(svg, ps, l, clip_lines, clip_dots);
  if (l.legend) draw_legend(svg, p, l);
  svg << "</g>\n";
}

}  // namespace

const char* palette_color(int index) noexcept {
  return kPalette[static_cast<std::size_t>(std::max(index, 0) % kPaletteSize)];
}

std::string render_svg(const Figure& figure) {
  const auto field = ErrorContext{}.with_field("figure");
  if (figure.columns < 1)
    throw_input_error("columns is " + std::to_string(figure.columns), field, "columns >= 1");
  if (!(figure.plot_width >= kMinCellWidth) || !(figure.plot_height >= kMinCellHeight) ||
      !std::isfinite(figure.plot_width) || !std::isfinite(figure.plot_height))
    throw_input_error("plot size " + svg_number(figure.plot_width) + " x " +
                          svg_number(figure.plot_height) + " px is too small",
                      field,
                      "plot_width >= " + svg_number(kMinCellWidth) +
                          " and plot_height >= " + svg_number(kMinCellHeight));

  const Plot empty_plot;
  std::vector<const Plot*> plots;
  for (const auto& p : figure.plots) plots.push_back(&p);
  if (plots.empty()) plots.push_back(&empty_plot);
  std::vector<PreparedPlot> prepared;
  for (std::size_t i = 0; i < plots.size(); ++i) prepared.push_back(prepare(*plots[i], i));

  const auto n = static_cast<int>(plots.size());
  const int columns = std::min(figure.columns, n);
  const int rows = (n + columns - 1) / columns;
  const double top = figure.title.empty() ? 0 : kFigureTitleHeight;
  const double width = figure.plot_width * columns;
  const double height = top + figure.plot_height * rows;

  SvgWriter svg;
  svg.begin(width, height);
  if (!figure.title.empty())
    svg.text(0.5 * width, 0.7 * kFigureTitleHeight, figure.title, kFigureTitleSize, "middle",
             std::string("font-weight=\"bold\" fill=\"") + kTextColor + "\"");
  for (int i = 0; i < n; ++i) {
    const double cx = figure.plot_width * (i % columns);
    const double cy = top + figure.plot_height * (i / columns);
    draw_plot(svg, prepared[static_cast<std::size_t>(i)], static_cast<std::size_t>(i), cx, cy,
              figure.plot_width, figure.plot_height);
  }
  svg.end();
  return std::move(svg.str());
}

void write_svg(const std::filesystem::path& path, const Figure& figure) {
  const std::string text = render_svg(figure);
  write_file_atomic(path, [&](std::ostream& os) { os << text; });
}

}  // namespace palpa::report
