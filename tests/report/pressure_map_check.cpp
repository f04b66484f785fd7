// SPDX-License-Identifier: AGPL-3.0-or-later
#include "report/pressure_map_check.hpp"

#include <cmath>
#include <set>
#include <sstream>

namespace palpa::test {

double MapPolygon::area() const {
  double a = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    const auto& q = points[(i + 1) % points.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * std::abs(a);
}

Eigen::Vector2d MapPolygon::centroid() const {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& p : points) c += p;
  return points.empty() ? c : Eigen::Vector2d(c / static_cast<double>(points.size()));
}

std::string PressureMapPicture::caption_text() const {
  std::string s;
  for (const auto& line : caption) s += line + "\n";
  return s;
}

PressureMapPicture read_pressure_map_picture(const std::string& svg) {
  PressureMapPicture pic;
  pic.doc = parse_xml(svg);
  if (!pic.doc.ok()) return pic;
  for (const XmlElement* e : pic.doc.all("path", "map")) {
    const std::string fill = e->attributes.at("fill");
    std::string d = e->attributes.at("d");
    for (char& c : d) {
      if (c == 'Z')
        c = ';';
      else if (c == 'M' || c == 'L')
        c = ' ';
    }
    std::istringstream subpaths(d);
    std::string sub;
    while (std::getline(subpaths, sub, ';')) {
      std::istringstream in(sub);
      MapPolygon p{fill, {}};
      double x = 0, y = 0;
      while (in >> x >> y) p.points.emplace_back(x, y);
      if (!p.points.empty()) pic.polygons.push_back(std::move(p));
    }
  }
  for (const XmlElement* r : pic.doc.all("rect")) {
    const auto c = r->attributes.find("class");
    if (c == r->attributes.end() || c->second != "map-frame") continue;
    const double x = XmlDocument::number(*r, "x"), y = XmlDocument::number(*r, "y");
    pic.frames.push_back(
        {x, y, x + XmlDocument::number(*r, "width"), y + XmlDocument::number(*r, "height")});
  }
  for (const XmlElement* t : pic.doc.all("text", "colorbar-ticks"))
    pic.bar_labels.push_back(t->text);
  for (const XmlElement* t : pic.doc.all("text", "caption")) pic.caption.push_back(t->text);
  return pic;
}

bool is_no_contact_grey(const std::string& fill) {
  static const std::set<std::string> kGreys = {"#d0d0d0", "#d9d9d9", "#e2e2e2", "#ebebeb"};
  return kGreys.count(fill) > 0;
}

double number_after(const std::string& text, const std::string& key) {
  const auto at = text.find(key);
  if (at == std::string::npos) return std::nan("");
  return std::stod(text.substr(at + key.size()));
}

}  // namespace palpa::test
