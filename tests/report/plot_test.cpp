// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/report/plot.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <regex>

#include "common/test_support.hpp"
#include "report/xml_check.hpp"

namespace palpa::report {
namespace {

using palpa::test::XmlDocument;
using palpa::test::XmlElement;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Coordinates are written rounded to 0.1 px.
constexpr double kPixelTol = 0.051;

struct Frame {
  double x0, y0, x1, y1;
};

// Parses `svg`, failing the test if it is not well-formed XML.
XmlDocument parse(const std::string& svg) {
  XmlDocument doc = test::parse_xml(svg);
  EXPECT_TRUE(doc.ok()) << doc.error;
  return doc;
}

std::vector<Frame> frames(const XmlDocument& doc) {
  std::vector<Frame> out;
  for (const auto* r : doc.all("rect")) {
    const auto it = r->attributes.find("class");
    if (it == r->attributes.end() || it->second != "frame") continue;
    const double x = XmlDocument::number(*r, "x"), y = XmlDocument::number(*r, "y");
    out.push_back(
        {x, y, x + XmlDocument::number(*r, "width"), y + XmlDocument::number(*r, "height")});
  }
  return out;
}

struct Px {
  double x, y;
};
std::vector<Px> circles(const XmlDocument& doc, std::string_view group = "dots") {
  std::vector<Px> out;
  for (const auto* c : doc.all("circle", group))
    out.push_back({XmlDocument::number(*c, "cx"), XmlDocument::number(*c, "cy")});
  return out;
}
std::vector<std::vector<Px>> polylines(const XmlDocument& doc) {
  std::vector<std::vector<Px>> out;
  for (const auto* p : doc.all("polyline")) {
    auto& line = out.emplace_back();
    std::istringstream in(p->attributes.at("points"));
    std::string pair;
    while (in >> pair) {
      const auto comma = pair.find(',');
      line.push_back({std::stod(pair.substr(0, comma)), std::stod(pair.substr(comma + 1))});
    }
  }
  return out;
}
std::vector<std::string> texts(const XmlDocument& doc, std::string_view group = {}) {
  std::vector<std::string> out;
  for (const auto* t : doc.all("text", group)) out.push_back(t->text);
  return out;
}

Figure one_plot(Series s, Axis x = {}, Axis y = {}) {
  Figure f;
  Plot& p = f.plots.emplace_back();
  p.x = std::move(x);
  p.y = std::move(y);
  p.series.push_back(std::move(s));
  return f;
}

TEST(ReportPlot, MapsDataToPixels) {
  // Data fill [0, 1] × [0, 1] exactly, so the axes are [0, 1] (ticks 0, 0.2, …, 1).
  const Figure f = one_plot({"", {0, 0.25, 1, 0.5}, {0, 0.75, 1, 0.1}, Mark::Dots});
  const XmlDocument doc = parse(render_svg(f));
  const auto fr = frames(doc);
  ASSERT_EQ(fr.size(), 1u);
  const Frame a = fr[0];
  EXPECT_GT(a.x1 - a.x0, 300);  // most of the 480 px cell
  EXPECT_GT(a.y1 - a.y0, 200);
  const auto c = circles(doc);
  ASSERT_EQ(c.size(), 4u);
  const double xs[] = {0, 0.25, 1, 0.5}, ys[] = {0, 0.75, 1, 0.1};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(c[i].x, a.x0 + xs[i] * (a.x1 - a.x0), kPixelTol) << i;
    EXPECT_NEAR(c[i].y, a.y1 - ys[i] * (a.y1 - a.y0), kPixelTol) << i;  // y points up
  }
  EXPECT_EQ(texts(doc, "xticks"), (std::vector<std::string>{"0", "0.2", "0.4", "0.6", "0.8", "1"}));
  EXPECT_EQ(texts(doc, "yticks"), (std::vector<std::string>{"0", "0.2", "0.4", "0.6", "0.8", "1"}));
}

TEST(ReportPlot, MapsLogAxesAndFixedBounds) {
  Axis x{"time [s]", false, -1.0, 3.0};
  Axis y{"objective", true, std::nullopt, std::nullopt};
  // The last point lies outside the fixed x range: clipped, no dot.
  const Figure f = one_plot({"", {1, -1, 3, 5}, {1e-2, 1e-3, 1e-1, 1e-2}, Mark::Dots}, x, y);
  const XmlDocument doc = parse(render_svg(f));
  const Frame a = frames(doc).at(0);
  const auto c = circles(doc);
  ASSERT_EQ(c.size(), 3u);
  // x: fixed [-1, 3]; y: decades [1e-3, 1e-1], 1e-2 halfway.
  EXPECT_NEAR(c[0].x, 0.5 * (a.x0 + a.x1), kPixelTol);
  EXPECT_NEAR(c[0].y, 0.5 * (a.y0 + a.y1), kPixelTol);
  EXPECT_NEAR(c[1].x, a.x0, kPixelTol);
  EXPECT_NEAR(c[1].y, a.y1, kPixelTol);
  EXPECT_NEAR(c[2].x, a.x1, kPixelTol);
  EXPECT_NEAR(c[2].y, a.y0, kPixelTol);
  // Two decades: 1–2–5 labels.
  EXPECT_EQ(texts(doc, "yticks"),
            (std::vector<std::string>{"0.001", "0.002", "0.005", "0.01", "0.02", "0.05", "0.1"}));
}

TEST(ReportPlot, NonFiniteValuesBreakLines) {
  const Figure f = one_plot({"", {0, 1, 2, 3, 4, 5, 6}, {0, 1, kNaN, 3, 4, kNaN, 6}, Mark::Line});
  const XmlDocument doc = parse(render_svg(f));
  const auto lines = polylines(doc);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].size(), 2u);
  EXPECT_EQ(lines[1].size(), 2u);
  // The isolated last point is drawn as a dot.
  const auto dots = circles(doc);
  ASSERT_EQ(dots.size(), 1u);
  const Frame a = frames(doc).at(0);
  EXPECT_NEAR(dots[0].x, a.x1, kPixelTol);
  EXPECT_NEAR(dots[0].y, a.y0, kPixelTol);
  // Infinite x breaks too.
  const Figure g = one_plot({"", {0, 1, INFINITY, 3, 4}, {0, 1, 2, 3, 4}, Mark::Line});
  EXPECT_EQ(polylines(parse(render_svg(g))).size(), 2u);
}

TEST(ReportPlot, LogAxisDropsNonPositiveValues) {
  Axis y{"", true, std::nullopt, std::nullopt};
  const Figure f = one_plot({"", {0, 1, 2, 3, 4}, {1, 0, -1, 10, 100}, Mark::Line}, {}, y);
  const XmlDocument doc = parse(render_svg(f));
  const auto lines = polylines(doc);
  ASSERT_EQ(lines.size(), 1u);  // 10 → 100
  EXPECT_EQ(lines[0].size(), 2u);
  EXPECT_EQ(circles(doc).size(), 1u);  // the lone point y = 1
  EXPECT_EQ(texts(doc, "yticks"),
            (std::vector<std::string>{"1", "2", "5", "10", "20", "50", "100"}));
}

TEST(ReportPlot, AllNonPositiveLogAxisIsAnError) {
  Axis y{"", true, std::nullopt, std::nullopt};
  Figure f = one_plot({"validation", {0, 1}, {0, -1}, Mark::Line}, {}, y);
  f.plots[0].title = "Objective";
  EXPECT_TRUE(test::throws_error([&] { render_svg(f); }, ErrorKind::Input,
                                 {"plot 1 ('Objective')", "y axis", "no positive value"}));
  Axis bad{"", true, 0.0, 10.0};
  const Figure g = one_plot({"", {1, 2}, {1, 2}}, bad);
  EXPECT_TRUE(test::throws_error([&] { render_svg(g); }, ErrorKind::Input, {"x axis", "<= 0"}));
}

TEST(ReportPlot, SinglePointAndEqualValuesArePadded) {
  const Figure f = one_plot({"", {3}, {5}, Mark::Dots});
  const XmlDocument doc = parse(render_svg(f));
  const Frame a = frames(doc).at(0);
  const auto c = circles(doc);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].x, 0.5 * (a.x0 + a.x1), kPixelTol);
  EXPECT_NEAR(c[0].y, 0.5 * (a.y0 + a.y1), kPixelTol);
  // A flat line: y range padded, the line in the middle.
  const Figure g = one_plot({"", {0, 1, 2}, {0, 0, 0}, Mark::Line});
  const XmlDocument dg = parse(render_svg(g));
  const Frame b = frames(dg).at(0);
  const auto lines = polylines(dg);
  ASSERT_EQ(lines.size(), 1u);
  for (const auto& p : lines[0]) EXPECT_NEAR(p.y, 0.5 * (b.y0 + b.y1), kPixelTol);
}

TEST(ReportPlot, EmptySeriesAreSkippedAndEmptyPlotsSayNoData) {
  Figure f = one_plot({"empty", {}, {}, Mark::Line});
  f.plots[0].series.push_back({"all NaN", {kNaN}, {1.0}, Mark::Dots});
  const XmlDocument doc = parse(render_svg(f));
  EXPECT_TRUE(polylines(doc).empty());
  EXPECT_TRUE(circles(doc).empty());
  const auto t = texts(doc);
  EXPECT_NE(std::find(t.begin(), t.end(), "no data"), t.end());
  EXPECT_TRUE(doc.all("g", "legend").empty());
  // A figure without plots, and an empty series beside a real one.
  EXPECT_TRUE(parse(render_svg(Figure{})).ok());
  Figure g = one_plot({"empty", {}, {}});
  g.plots[0].series.push_back({"data", {0, 1}, {0, 1}});
  const XmlDocument dg = parse(render_svg(g));
  EXPECT_EQ(polylines(dg).size(), 1u);
  const auto legend = texts(dg, "legend");
  EXPECT_EQ(legend, (std::vector<std::string>{"data"}));
}

TEST(ReportPlot, EscapesText) {
  const std::string nasty = "a<b & \"c\" 'd' >";
  Figure f = one_plot({nasty, {0, 1}, {0, 1}}, {nasty + " x"}, {nasty + " y"});
  f.title = nasty;
  f.plots[0].title = nasty;
  const std::string svg = render_svg(f);
  EXPECT_EQ(svg.find("a<b"), std::string::npos);
  EXPECT_NE(svg.find("a&lt;b &amp; &quot;c&quot; &apos;d&apos; &gt;"), std::string::npos);
  const XmlDocument doc = parse(svg);
  const auto t = texts(doc);
  EXPECT_EQ(std::count(t.begin(), t.end(), nasty), 3);  // figure title, plot title, legend
  EXPECT_EQ(std::count(t.begin(), t.end(), nasty + " x"), 1);
  EXPECT_EQ(std::count(t.begin(), t.end(), nasty + " y"), 1);
}

TEST(ReportPlot, OutputIsDeterministicAndCompact) {
  Figure f;
  f.title = "fit";
  f.columns = 2;
  for (int k = 0; k < 3; ++k) {
    Plot& p = f.plots.emplace_back();
    p.title = "plot " + std::to_string(k);
    std::vector<double> x, y;
    for (int i = 0; i < 50; ++i) {
      x.push_back(i / 49.0 * 3.7e-3);
      y.push_back(std::sin(i * 0.1 + k) * 1.3 + 2);
    }
    p.series.push_back({"measured", x, y, Mark::Dots});
    p.series.push_back({"simulated", x, y, Mark::Line, 0, true});
  }
  const std::string a = render_svg(f);
  const Figure copy = f;
  EXPECT_EQ(render_svg(copy), a);
  EXPECT_TRUE(parse(a).ok());
  // No coordinate or size carries more than one decimal.
  const std::regex long_number(R"(\d\.\d\d)");
  for (const auto& e : parse(a).elements)
    for (const char* key : {"x", "y", "cx", "cy", "r", "width", "height", "points", "d"}) {
      const auto it = e.attributes.find(key);
      if (it != e.attributes.end()) {
        EXPECT_FALSE(std::regex_search(it->second, long_number)) << key << "=" << it->second;
      }
    }
  // Size of the grid: 2 columns, 2 rows, plus the title strip; a viewBox.
  const XmlDocument doc = parse(a);
  const XmlElement& root = doc.elements.at(0);
  EXPECT_EQ(root.name, "svg");
  EXPECT_EQ(root.attributes.at("xmlns"), "http://www.w3.org/2000/svg");
  EXPECT_EQ(root.attributes.at("width"), "960");
  EXPECT_EQ(root.attributes.at("height"), "670");
  EXPECT_EQ(root.attributes.at("viewBox"), "0 0 960 670");
  EXPECT_EQ(frames(doc).size(), 3u);
}

TEST(ReportPlot, ColoursDashesAndMarks) {
  Figure f = one_plot({"a", {0, 1}, {0, 1}, Mark::Line});
  auto& s = f.plots[0].series;
  s.push_back({"b", {0, 1}, {1, 0}, Mark::LineDots});
  s.push_back({"c", {0, 1}, {0.5, 0.5}, Mark::Line, 0, true});
  s.push_back({"d", {0, 1}, {0.2, 0.3}, Mark::Dots, 9});
  const XmlDocument doc = parse(render_svg(f));
  std::vector<std::string> strokes, dashes;
  for (const auto* g : doc.all("g")) {
    const auto cls = g->attributes.find("class");
    if (cls == g->attributes.end() || cls->second != "line") continue;
    strokes.push_back(g->attributes.at("stroke"));
    const auto d = g->attributes.find("stroke-dasharray");
    dashes.push_back(d == g->attributes.end() ? "" : d->second);
  }
  EXPECT_EQ(strokes, (std::vector<std::string>{"#0072B2", "#D55E00", "#0072B2"}));
  EXPECT_EQ(dashes, (std::vector<std::string>{"", "", "6 4"}));
  std::vector<std::string> fills;
  for (const auto* g : doc.all("g"))
    if (g->attributes.count("class") && g->attributes.at("class") == "dots")
      fills.push_back(g->attributes.at("fill"));
  EXPECT_EQ(fills, (std::vector<std::string>{"#D55E00", std::string(palette_color(1))}));
  EXPECT_EQ(circles(doc).size(), 4u);  // b's two and d's two
  EXPECT_EQ(texts(doc, "legend"), (std::vector<std::string>{"a", "b", "c", "d"}));
}

// The legend rectangle (first rect in the legend group).
Frame legend_box(const XmlDocument& doc) {
  const auto rects = doc.all("rect", "legend");
  EXPECT_EQ(rects.size(), 1u);
  const auto& r = *rects.at(0);
  const double x = XmlDocument::number(r, "x"), y = XmlDocument::number(r, "y");
  return {x, y, x + XmlDocument::number(r, "width"), y + XmlDocument::number(r, "height")};
}

TEST(ReportPlot, LegendAvoidsData) {
  // Dots fill the top half and the bottom-left corner; the bottom-right corner
  // is free (its only point sits on the frame corner, below the legend's inset).
  std::vector<double> x, y;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) {
      const double u = i / 20.0, v = j / 20.0;
      if (v >= 0.5 || (u <= 0.4 && v <= 0.4)) {
        x.push_back(u);
        y.push_back(v);
      }
    }
  x.push_back(1);
  y.push_back(0);
  const Figure f = one_plot({"measured", x, y, Mark::Dots});
  const XmlDocument doc = parse(render_svg(f));
  const Frame a = frames(doc).at(0);
  const Frame l = legend_box(doc);
  EXPECT_GT(l.x0, a.x0 + 0.5 * (a.x1 - a.x0));  // right half
  EXPECT_GT(l.y0, a.y0 + 0.5 * (a.y1 - a.y0));  // bottom half
  for (const auto& c : circles(doc))
    EXPECT_FALSE(c.x >= l.x0 && c.x <= l.x1 && c.y >= l.y0 && c.y <= l.y1);
}

TEST(ReportPlot, LegendMovesBesideThePlotWhenDataFillsIt) {
  std::vector<double> x, y;
  for (int i = 0; i <= 30; ++i)
    for (int j = 0; j <= 30; ++j) {
      x.push_back(i);
      y.push_back(j);
    }
  const Figure f = one_plot({"grid", x, y, Mark::Dots});
  const XmlDocument doc = parse(render_svg(f));
  const Frame a = frames(doc).at(0);
  const Frame l = legend_box(doc);
  EXPECT_GT(l.x0, a.x1);
  EXPECT_LE(l.x1, 480);
}

TEST(ReportPlot, RejectsBadInput) {
  Figure f = one_plot({"validation", {0, 1, 2}, {0, 1}, Mark::Line});
  f.plots[0].title = "Fit";
  EXPECT_TRUE(test::throws_error(
      [&] { render_svg(f); }, ErrorKind::Input,
      {"plot 1 ('Fit'), series 1 ('validation')", "x has 3 values but y has 2"}));
  Figure g = one_plot({"", {0}, {0}});
  g.columns = 0;
  EXPECT_TRUE(test::throws_error([&] { render_svg(g); }, ErrorKind::Input, {"columns"}));
  g.columns = 1;
  g.plot_width = 10;
  EXPECT_TRUE(test::throws_error([&] { render_svg(g); }, ErrorKind::Input, {"too small"}));
  Figure h = one_plot({"x", {0}, {0}, Mark::Dots, -2});
  EXPECT_TRUE(
      test::throws_error([&] { render_svg(h); }, ErrorKind::Input, {"series 1 ('x')", "colour"}));
  Figure k = one_plot({"", {0}, {0}}, Axis{"", false, 2.0, 1.0});
  EXPECT_TRUE(test::throws_error([&] { render_svg(k); }, ErrorKind::Input, {"x axis", "min"}));
}

TEST(ReportPlot, WritesAtomically) {
  test::ScratchDir dir;
  const Figure f = one_plot({"a", {0, 1}, {0, 1}});
  write_svg(dir / "plot.svg", f);
  EXPECT_EQ(test::read_text(dir / "plot.svg"), render_svg(f));
  EXPECT_EQ(dir.entry_count(), 1u);
  EXPECT_TRUE(test::throws_error([&] { write_svg(dir / "missing" / "plot.svg", f); },
                                 ErrorKind::Input, {"missing"}));
  EXPECT_EQ(dir.entry_count(), 1u);
}

}  // namespace
}  // namespace palpa::report
