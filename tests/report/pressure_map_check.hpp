// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Reads a pressure-map picture (report/pressure_map_svg.hpp) back for the
// tests: the polygons of its maps in painting order with their fills, the map
// frames, the colour bar's labels and the caption lines.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "report/xml_check.hpp"

namespace palpa::test {

struct MapPolygon {
  std::string fill;                     // "#rrggbb"
  std::vector<Eigen::Vector2d> points;  // page coordinates [px]
  double area() const;                  // [px²]
  Eigen::Vector2d centroid() const;     // of the corners
};

struct MapFrame {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [px], y down
  double area() const { return (x1 - x0) * (y1 - y0); }
};

struct PressureMapPicture {
  XmlDocument doc;
  std::vector<MapPolygon> polygons;     // every subpath of the "map" groups' paths
  std::vector<MapFrame> frames;         // one per panel
  std::vector<std::string> bar_labels;  // bottom to top
  std::vector<std::string> caption;     // every caption line, panel after panel
  std::string caption_text() const;     // the lines joined with newlines
};

// Parses `svg`; check doc.ok() before anything else.
PressureMapPicture read_pressure_map_picture(const std::string& svg);

// The light greys in which the pictures draw zero pressure.
bool is_no_contact_grey(const std::string& fill);

// The number after `key` in `text` ("map force 39.6 N", key "map force " →
// 39.6); NaN if `key` is not there.
double number_after(const std::string& text, const std::string& key);

}  // namespace palpa::test
