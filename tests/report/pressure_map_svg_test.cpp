// SPDX-License-Identifier: AGPL-3.0-or-later
// Pressure-map pictures read back as XML: a Hertz map on a flat grid (coloured
// polygons with the top colour, the colour bar's labelled range [0, max], the
// caption's force and peak), each vertex's colour painted over exactly its
// barycentric area, cropping to the contact patch, the view's handedness and
// painter's order, back faces left out, a colour scale shared by two panels,
// an all-grey zero map, and bad input.

#include "palpa/report/pressure_map_svg.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "common/square_grid.hpp"
#include "common/test_support.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/report/colormap.hpp"
#include "report/pressure_map_check.hpp"

namespace palpa::report {
namespace {

using test::is_no_contact_grey;
using test::MapPolygon;
using test::number_after;

constexpr int kMapCells = 40;
constexpr double kMapSide = 0.1;   // [m]
constexpr double kMapA = 0.02;     // contact radius [m]
constexpr double kMapP0 = 47.3e3;  // peak [Pa]: not a nice tick, so the top label is the peak's own

SurfaceMesh map_flat_grid(double z = 0.0) {
  return test::square_grid(kMapCells, kMapSide, {0.0, 0.0, z});
}

Eigen::VectorXd map_hertz(const SurfaceMesh& m, double a = kMapA, double p0 = kMapP0) {
  Eigen::VectorXd p(m.V.rows());
  for (Eigen::Index v = 0; v < p.size(); ++v) {
    const double r2 = m.V.row(v).head<2>().squaredNorm();
    p[v] = r2 < a * a ? p0 * std::sqrt(1.0 - r2 / (a * a)) : 0.0;
  }
  return p;
}

// Parses `svg`, failing the test if it is not well-formed XML.
test::PressureMapPicture map_read(const std::string& svg) {
  test::PressureMapPicture pic = test::read_pressure_map_picture(svg);
  EXPECT_TRUE(pic.doc.ok()) << pic.doc.error;
  return pic;
}

PressureMapOptions map_whole_view() {
  PressureMapOptions o;
  o.crop = PressureMapCrop::Whole;
  return o;
}

TEST(ReportPressureMapSvg, DrawsAHertzMapWithItsColourBarAndCaption) {
  const SurfaceMesh m = map_flat_grid();
  const Eigen::VectorXd p = map_hertz(m);
  const std::string svg = render_pressure_map_svg({{m, p, "body side", std::nullopt, 42.0}});
  EXPECT_LT(svg.size(), 1u << 20);
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("href"), std::string::npos);  // self-contained
  const auto pic = map_read(svg);
  ASSERT_EQ(pic.frames.size(), 1u);
  ASSERT_FALSE(pic.polygons.empty());

  // Coloured polygons cover about the contact disc's share of the plot area
  // (Auto keeps the whole grid here: the patch with its margin is more than a
  // third of it); one of them, at the peak, has the top colour.
  double coloured = 0.0, all = 0.0;
  bool top = false;
  const std::string top_colour = hex_color(viridis(1.0));
  for (const MapPolygon& q : pic.polygons) {
    all += q.area();
    if (!is_no_contact_grey(q.fill)) coloured += q.area();
    top |= q.fill == top_colour;
  }
  EXPECT_TRUE(top);
  const double disc_share = std::numbers::pi * kMapA * kMapA / (kMapSide * kMapSide);
  EXPECT_NEAR(coloured / pic.frames[0].area(), disc_share, 0.15 * disc_share);
  EXPECT_NEAR(all / pic.frames[0].area(), 1.0, 0.01);

  // The colour bar: labelled from 0 to the peak in kPa (the top label is the
  // peak to 3 significant digits), labels increasing.
  ASSERT_GE(pic.bar_labels.size(), 3u);
  std::vector<double> values;
  for (const auto& l : pic.bar_labels) values.push_back(std::stod(l));
  EXPECT_EQ(values.front(), 0.0);
  EXPECT_NEAR(values.back(), kMapP0 * 1e-3, 5e-3 * kMapP0 * 1e-3);
  EXPECT_EQ(pic.bar_labels.back(), "47.3");
  for (std::size_t i = 1; i < values.size(); ++i) EXPECT_LT(values[i - 1], values[i]);
  EXPECT_EQ(pic.doc.all("stop").size(), static_cast<std::size_t>(kViridisStops));

  // The caption: side, load, the map's force (⅔πa²p0 for Hertz) and peak.
  const std::string caption = pic.caption_text();
  const PressureMetrics metrics = pressure_metrics(m, p);
  EXPECT_NE(svg.find("body side"), std::string::npos);
  EXPECT_NE(caption.find("load 42 N"), std::string::npos) << caption;
  EXPECT_NEAR(number_after(caption, "map force "), metrics.force, 5e-3 * metrics.force) << caption;
  EXPECT_NEAR(metrics.force, 2.0 / 3.0 * std::numbers::pi * kMapA * kMapA * kMapP0,
              0.03 * metrics.force);
  EXPECT_EQ(number_after(caption, "peak "), 47.3) << caption;
  EXPECT_NEAR(number_after(caption, "PPI "), metrics.peak_pressure_index * 1e-3,
              5e-3 * metrics.peak_pressure_index * 1e-3)
      << caption;
}

TEST(ReportPressureMapSvg, PaintsEachPressureOverItsVertexArea) {
  // A uniform disc: the coloured area, back in m², is the barycentric area of
  // the vertices with a pressure, all in the top colour.
  const SurfaceMesh m = map_flat_grid();
  Eigen::VectorXd p = map_hertz(m);
  for (Eigen::Index v = 0; v < p.size(); ++v) p[v] = p[v] > 0.0 ? 20e3 : 0.0;
  const auto pic = map_read(render_pressure_map_svg({{m, p, "disc"}}, map_whole_view()));
  const test::MapFrame f = pic.frames.at(0);
  const double px_per_m = (f.x1 - f.x0) / kMapSide;
  double coloured = 0.0;
  for (const MapPolygon& q : pic.polygons) {
    if (is_no_contact_grey(q.fill)) continue;
    EXPECT_EQ(q.fill, hex_color(viridis(1.0)));
    coloured += q.area();
  }
  const Eigen::VectorXd area = geometry::vertex_areas(m);
  const double expected = (p.array() > 0.0).select(area, 0.0).sum();
  EXPECT_NEAR(coloured / (px_per_m * px_per_m), expected, 0.01 * expected);
}

// The share of the map frame that coloured polygons cover.
double coloured_share(const test::PressureMapPicture& pic) {
  double coloured = 0.0;
  for (const MapPolygon& q : pic.polygons)
    if (!is_no_contact_grey(q.fill)) coloured += q.area();
  return coloured / pic.frames.at(0).area();
}

TEST(ReportPressureMapSvg, CropsToASmallContactPatch) {
  const SurfaceMesh m = map_flat_grid();
  const Eigen::VectorXd p = map_hertz(m, 0.006);
  const auto share = [&](PressureMapCrop crop) {
    PressureMapOptions o;
    o.crop = crop;
    return coloured_share(map_read(render_pressure_map_svg({{m, p, "small"}}, o)));
  };
  const double whole = share(PressureMapCrop::Whole);
  EXPECT_GT(whole, 0.0);
  EXPECT_GT(share(PressureMapCrop::Auto), 4.0 * whole);
  EXPECT_EQ(share(PressureMapCrop::Auto), share(PressureMapCrop::Contact));
}

TEST(ReportPressureMapSvg, SeenFromBelowIsTheMirrorImageAndNearerTrianglesComeLast) {
  // Pressure on the +x half only: right of centre seen from above, left seen
  // from below (y up the page both times).
  const SurfaceMesh m = map_flat_grid();
  Eigen::VectorXd p = map_hertz(m, 0.04);
  for (Eigen::Index v = 0; v < p.size(); ++v)
    if (m.V(v, 0) <= 0.0) p[v] = 0.0;
  const auto coloured_x = [&](double dz) {
    PressureMapOptions o = map_whole_view();
    o.view_direction = {0.0, 0.0, dz};
    const auto pic = map_read(render_pressure_map_svg({{m, p, "half"}}, o));
    const test::MapFrame f = pic.frames.at(0);
    double x = 0.0, w = 0.0;
    for (const MapPolygon& q : pic.polygons)
      if (!is_no_contact_grey(q.fill)) {
        x += q.area() * q.centroid().x();
        w += q.area();
      }
    return (x / w - f.x0) / (f.x1 - f.x0);
  };
  EXPECT_GT(coloured_x(-1.0), 0.6);
  EXPECT_LT(coloured_x(+1.0), 0.4);

  // A grey sheet 10 mm above one pressed all over: from below every polygon
  // of the pressed sheet (nearer) is painted after the grey ones; from above
  // the other way round.
  SurfaceMesh two = m;
  const SurfaceMesh lid = map_flat_grid(0.01);
  two.V.conservativeResize(2 * m.V.rows(), 3);
  two.V.bottomRows(m.V.rows()) = lid.V;
  two.F.conservativeResize(2 * m.F.rows(), 3);
  two.F.bottomRows(m.F.rows()) = lid.F.array() + static_cast<int>(m.V.rows());
  Eigen::VectorXd p2 = Eigen::VectorXd::Zero(two.V.rows());
  p2.head(m.V.rows()).setConstant(kMapP0);
  for (const double dz : {-1.0, 1.0}) {
    PressureMapOptions o = map_whole_view();
    o.view_direction = {0.0, 0.0, dz};
    const auto polys =
        map_read(render_pressure_map_svg({{two, p2, "two sheets", PressureMetrics{}}}, o)).polygons;
    std::size_t first_grey = polys.size(), last_grey = 0, first_colour = polys.size(),
                last_colour = 0;
    for (std::size_t i = 0; i < polys.size(); ++i) {
      if (is_no_contact_grey(polys[i].fill)) {
        first_grey = std::min(first_grey, i);
        last_grey = i;
      } else {
        first_colour = std::min(first_colour, i);
        last_colour = i;
      }
    }
    ASSERT_LT(first_grey, polys.size());
    ASSERT_LT(first_colour, polys.size());
    if (dz > 0.0)
      EXPECT_LT(last_grey, first_colour);
    else
      EXPECT_LT(last_colour, first_grey);
  }
}

TEST(ReportPressureMapSvg, LeavesOutBackFacesWhenAsked) {
  // The grid faces +z: seen from above all of it is drawn, from below none.
  const SurfaceMesh m = map_flat_grid();
  const Eigen::VectorXd p = map_hertz(m);
  const auto count = [&](double dz, bool hide) {
    PressureMapOptions o = map_whole_view();
    o.view_direction = {0.0, 0.0, dz};
    o.hide_back_faces = hide;
    return map_read(render_pressure_map_svg({{m, p, "grid"}}, o)).polygons.size();
  };
  EXPECT_EQ(count(-1.0, true), count(-1.0, false));
  EXPECT_GT(count(+1.0, false), static_cast<std::size_t>(m.F.rows()));
  EXPECT_EQ(count(+1.0, true), 0u);
}

TEST(ReportPressureMapSvg, LeavesOutFarGreyTrianglesBeyondItsBudget) {
  // 84 050 triangles, more than the 80 000 polygons a picture may hold: the
  // grey ones farthest from the contact go, and the caption says how many.
  constexpr int kCells = 205;
  const SurfaceMesh m = test::square_grid(kCells, kMapSide, Eigen::Vector3d::Zero());
  const Eigen::VectorXd p = map_hertz(m, 0.005);
  const std::string svg =
      render_pressure_map_svg({{m, p, "fine", PressureMetrics{}}}, map_whole_view());
  const auto subpaths = static_cast<std::size_t>(std::count(svg.begin(), svg.end(), 'Z'));
  EXPECT_LE(subpaths, 80000u);
  EXPECT_GT(subpaths, 79000u);
  EXPECT_LT(svg.size(), 4u << 20);
  const auto at = svg.find(" triangles far from the contact not drawn");
  ASSERT_NE(at, std::string::npos);
  const auto start = svg.rfind('>', at) + 1;
  const int left_out = std::stoi(svg.substr(start, at - start));
  // At least the 4 050 triangles over the budget, and two more for each
  // triangle of the contact (painted as three corner shares).
  EXPECT_GE(left_out, 4050);
  EXPECT_LT(left_out, 8000);
}

TEST(ReportPressureMapSvg, PanelsShareOneColourScale) {
  // Before and after: the softer map never reaches the top colour, and the
  // bar's top is the larger peak.
  const SurfaceMesh m = map_flat_grid();
  const Eigen::VectorXd p = map_hertz(m);
  const Eigen::VectorXd half = 0.5 * p;
  PressureMapOptions o;
  o.title = "body side";
  const auto pic = map_read(render_pressure_map_svg({{m, half, "after"}, {m, p, "before"}}, o));
  ASSERT_EQ(pic.frames.size(), 2u);
  ASSERT_FALSE(pic.bar_labels.empty());
  EXPECT_EQ(pic.bar_labels.back(), "47.3");
  std::size_t top_in_first = 0, top_in_second = 0;
  for (const MapPolygon& q : pic.polygons) {
    if (q.fill != hex_color(viridis(1.0))) continue;
    (q.centroid().x() < pic.frames[0].x1 ? top_in_first : top_in_second) += 1;
  }
  EXPECT_EQ(top_in_first, 0u);
  EXPECT_GT(top_in_second, 0u);
  // The first caption is the softer map's: its own peak (to 3 digits).
  EXPECT_NEAR(number_after(pic.caption_text(), "peak "), 0.5 * kMapP0 * 1e-3, 0.051)
      << pic.caption_text();
}

TEST(ReportPressureMapSvg, AZeroMapIsAllGrey) {
  const SurfaceMesh m = map_flat_grid();
  const std::string svg =
      render_pressure_map_svg({{m, Eigen::VectorXd::Zero(m.V.rows()), "support side"}});
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("inf"), std::string::npos);
  const auto pic = map_read(svg);
  ASSERT_FALSE(pic.polygons.empty());
  double all = 0.0;
  for (const MapPolygon& q : pic.polygons) {
    EXPECT_TRUE(is_no_contact_grey(q.fill)) << q.fill;
    all += q.area();
  }
  EXPECT_NEAR(all / pic.frames.at(0).area(), 1.0, 0.01);
  EXPECT_TRUE(pic.bar_labels.empty());
  EXPECT_NE(pic.caption_text().find("no contact"), std::string::npos);
}

TEST(ReportPressureMapSvg, RefusesBadInputByName) {
  const SurfaceMesh m = map_flat_grid();
  const Eigen::VectorXd p = map_hertz(m);
  const auto refuses = [](const PressureMapPanel& panel, const PressureMapOptions& o,
                          const std::vector<std::string>& says) {
    return test::throws_error([&] { render_pressure_map_svg({panel}, o); }, ErrorKind::Input, says);
  };
  EXPECT_TRUE(refuses(
      {m, p.head(10), "short"}, {},
      {"pressure map 1 ('short')", "10 pressures for 1681 vertices", "one pressure per vertex"}));
  Eigen::VectorXd bad = p;
  bad[3] = std::nan("");
  EXPECT_TRUE(refuses({m, bad, "nan"}, {}, {"pressure", "vertex 3", "finite pressures >= 0"}));
  bad[3] = -1.0;
  EXPECT_TRUE(refuses({m, bad, "negative"}, {}, {"vertex 3", "finite pressures >= 0"}));
  SurfaceMesh broken = m;
  broken.F(5, 1) = 99999;
  EXPECT_TRUE(refuses({broken, p, "index"}, {}, {"surface.F", "triangle 5", "vertex 99999"}));
  EXPECT_TRUE(refuses({SurfaceMesh{m.V, {}}, p, "empty"}, {}, {"no triangles"}));
  PressureMapOptions o;
  o.view_direction = Eigen::Vector3d::Zero();
  EXPECT_TRUE(refuses({m, p, "view"}, o, {"view_direction", "non-zero"}));
  o.view_direction = {0.0, 0.0, 1.0};
  o.up = Eigen::Vector3d(0.0, 0.0, -2.0);
  EXPECT_TRUE(refuses({m, p, "up"}, o, {"up", "across the view direction"}));
  SurfaceMesh point = m;  // every vertex in one place
  point.V.setZero();
  EXPECT_TRUE(refuses({point, p, "point"}, {}, {"no extent"}));
  o = {};
  o.map_size = 50;
  EXPECT_TRUE(refuses({m, p, "tiny"}, o, {"map_size", ">= 160"}));
  EXPECT_TRUE(test::throws_error([] { render_pressure_map_svg({}); }, ErrorKind::Input,
                                 {"no pressure map"}));
}

}  // namespace
}  // namespace palpa::report
