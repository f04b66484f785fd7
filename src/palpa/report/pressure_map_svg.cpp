// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/report/pressure_map_svg.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string_view>
#include <utility>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/report/colormap.hpp"
#include "palpa/report/svg_text.hpp"
#include "palpa/report/ticks.hpp"

namespace palpa::report {
namespace {

// Sizes in px. (Names carry "Map": the module is compiled as a unity build.)
constexpr double kMapEdge = 12;  // page edge to content
constexpr double kMapFigureTitleSize = 15;
constexpr double kMapFigureTitleHeight = 28;
constexpr double kMapPanelTitleSize = 13;
constexpr double kMapTextSize = 11;
constexpr double kMapTitleRow = 19;  // panel title line
constexpr double kMapViewRow = 17;   // view line, above the map
constexpr double kMapScaleRow = 34;  // scale bar and axis glyph, under the map
constexpr double kMapCaptionRow = 15;
constexpr double kMapPanelGap = 28;
constexpr double kMapMinPanelWidth = 280;
constexpr double kMapMinSize = 160;
constexpr double kMapBarGap = 26;
constexpr double kMapBarWidth = 14;
constexpr double kMapMinBarHeight = 120;
constexpr double kMapTickLength = 4;
constexpr double kMapLabelGap = 3;
constexpr double kMapTopClearance = 14;  // between the top label and the next tick label
constexpr double kMapSwatchHeight = 10;
constexpr double kMapGlyphLength = 14;
// Axes whose projection is shorter than this share of the glyph are left out.
constexpr double kMapGlyphMinShare = 0.25;
// A stroke of the fill's colour closes the antialiasing seams between polygons.
constexpr double kMapSeam = 0.3;
// About this many px per labelled tick on the colour bar.
constexpr double kMapMaxTickSpacing = 30;
// The window.
constexpr double kMapAutoCropShare = 1.0 / 3.0;
constexpr double kMapCropMargin = 0.25;     // of the contact window's longer side
constexpr double kMapMinCropMargin = 0.02;  // of the whole surface's longer side
constexpr double kMapMinAspect = 0.4;
// Polygons beyond which zero-pressure triangles far from the contact are left out.
constexpr std::size_t kMapMaxPolygons = 80000;
constexpr int kMapSignificantDigits = 3;
constexpr double kMapUnitTolerance = 1e-9;  // a direction this close to an axis is named by it
constexpr const char* kMapTextColor = "#222";
constexpr const char* kMapMutedColor = "#666";
constexpr const char* kMapFrameColor = "#bbb";
constexpr const char* kMapBarFrameColor = "#777";
// Zero pressure: light greys, lighter the more squarely a triangle faces the viewer.
constexpr std::array<const char*, 4> kMapGreys = {"#d0d0d0", "#d9d9d9", "#e2e2e2", "#ebebeb"};
constexpr const char* kMapSwatchGrey = "#e2e2e2";

std::string map_panel_name(std::size_t index, const PressureMapPanel& panel) {
  std::string s = "pressure map " + std::to_string(index + 1);
  if (!panel.title.empty()) s += " ('" + panel.title + "')";
  return s;
}

void check_map_panel(const PressureMapPanel& panel, std::size_t index) {
  const auto field = [&](const std::string& part) {
    return ErrorContext{}.with_field(map_panel_name(index, panel) + ", " + part);
  };
  const SurfaceMesh& m = panel.surface;
  if (m.F.rows() == 0)
    throw_input_error("the surface has no triangles", field("surface.F"), "at least one triangle");
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      if (m.F(f, c) < 0 || m.F(f, c) >= m.V.rows())
        throw_input_error(
            fmt::format("triangle {} refers to vertex {} but the surface has {} vertices", f,
                        m.F(f, c), m.V.rows()),
            field("surface.F"), "vertex indices in [0, #V)");
  for (Eigen::Index v = 0; v < m.V.rows(); ++v)
    if (!m.V.row(v).allFinite())
      throw_input_error(fmt::format("vertex {} is not finite", v), field("surface.V"),
                        "finite positions [m]");
  if (panel.pressure.size() != m.V.rows())
    throw_input_error(
        fmt::format("{} pressures for {} vertices", panel.pressure.size(), m.V.rows()),
        field("pressure"), "one pressure per vertex");
  for (Eigen::Index v = 0; v < panel.pressure.size(); ++v)
    if (!std::isfinite(panel.pressure[v]) || panel.pressure[v] < 0.0)
      throw_input_error(fmt::format("the pressure at vertex {} is {}", v, panel.pressure[v]),
                        field("pressure"), "finite pressures >= 0 [Pa]");
}

// An axis-aligned box in the view plane [m].
struct MapBox {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0;
  double x1 = -std::numeric_limits<double>::infinity(), y1 = x1;
  bool empty() const { return x0 > x1; }
  double width() const { return x1 - x0; }
  double height() const { return y1 - y0; }
  void add(double x, double y) {
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
  void add(const MapBox& b) {
    if (b.empty()) return;
    add(b.x0, b.y0);
    add(b.x1, b.y1);
  }
  bool overlaps(const MapBox& b) const {
    return !(b.x1 < x0 || b.x0 > x1 || b.y1 < y0 || b.y0 > y1);
  }
};

// The view: eye looking along d; r to the right of the page, u up it.
struct MapView {
  Eigen::Vector3d d, r, u;
};

MapView map_view(const PressureMapOptions& o) {
  const auto field = [](const char* name) { return ErrorContext{}.with_field(name); };
  if (!o.view_direction.allFinite() || o.view_direction.norm() == 0.0)
    throw_input_error("the view direction is zero or not finite", field("view_direction"),
                      "a finite, non-zero direction");
  MapView v;
  v.d = o.view_direction.normalized();
  Eigen::Vector3d up;
  if (o.up) {
    if (!o.up->allFinite())
      throw_input_error("up is not finite", field("up"), "a finite direction");
    up = *o.up;
  } else {
    // The axis most across the view: y before z before x on ties.
    int best = 1;
    for (const int k : {2, 0})
      if (std::abs(v.d[k]) < std::abs(v.d[best]) - kMapUnitTolerance) best = k;
    up = Eigen::Vector3d::Unit(best);
  }
  v.u = up - up.dot(v.d) * v.d;
  constexpr double kAcross = 1e-6;
  if (!(v.u.norm() > kAcross * std::max(up.norm(), 1e-300)))
    throw_input_error("up is zero or along the view direction", field("up"),
                      "a direction across the view direction");
  v.u.normalize();
  v.r = v.d.cross(v.u);
  return v;
}

// "+z", "−x", or "(0.71, 0.00, −0.71)".
std::string map_direction_text(const Eigen::Vector3d& d) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(d[k]) > 1.0 - kMapUnitTolerance)
      return std::string(d[k] > 0 ? "+" : "\u2212") + "xyz"[k];
  std::string s = fmt::format("({:.2f}, {:.2f}, {:.2f})", d[0], d[1], d[2]);
  std::string out;
  for (char c : s) {
    if (c == '-')
      out += "\u2212";
    else
      out += c;
  }
  return out;
}

// v to 3 significant digits, plain decimals where they are readable.
std::string map_sig3(double v) {
  if (v == 0.0 || !std::isfinite(v)) return "0";
  int e = static_cast<int>(std::floor(std::log10(std::abs(v)))) - (kMapSignificantDigits - 1);
  long long n = std::llround(v / std::pow(10.0, e));
  if (std::llabs(n) >= 1000) {
    n = std::llround(static_cast<double>(n) / 10.0);
    ++e;
  }
  return format_decimal(n, e);
}

// One panel, prepared.
struct MapPanelData {
  const PressureMapPanel* panel = nullptr;
  PressureMetrics metrics;
  std::vector<double> x, y, depth;  // per vertex, in the view [m]
  MapBox whole, contact;
  double top = 0.0;            // largest pressure drawn [Pa]
  double bottom = 0.0;         // smallest value (a field's; 0 for pressures)
  std::vector<int> triangles;  // drawn, farthest first
  std::size_t left_out = 0;    // zero-pressure triangles left out for size
};

MapPanelData prepare_map_panel(const PressureMapPanel& panel, const MapView& view, bool field) {
  MapPanelData p;
  p.panel = &panel;
  if (!field) p.metrics = panel.metrics ? *panel.metrics : pressure_metrics(panel.surface, panel.pressure);
  if (field) p.bottom = std::numeric_limits<double>::infinity();
  const SurfaceMesh& m = panel.surface;
  const auto n = static_cast<std::size_t>(m.V.rows());
  p.x.resize(n);
  p.y.resize(n);
  p.depth.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d q = m.V.row(static_cast<Eigen::Index>(i)).transpose();
    p.x[i] = view.r.dot(q);
    p.y[i] = view.u.dot(q);
    p.depth[i] = view.d.dot(q);
  }
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    bool touched = false;
    for (int c = 0; c < 3; ++c) {
      const double pc = panel.pressure[m.F(f, c)];
      touched |= pc > 0.0 || field;
      p.top = std::max(p.top, pc);
      if (field) p.bottom = std::min(p.bottom, pc);
    }
    for (int c = 0; c < 3; ++c) {
      const auto v = static_cast<std::size_t>(m.F(f, c));
      p.whole.add(p.x[v], p.y[v]);
      if (touched) p.contact.add(p.x[v], p.y[v]);
    }
  }
  return p;
}

MapBox grown(const MapBox& b, double margin) {
  return {b.x0 - margin, b.y0 - margin, b.x1 + margin, b.y1 + margin};
}

MapBox choose_map_window(const std::vector<MapPanelData>& panels, PressureMapCrop crop) {
  MapBox whole, contact;
  for (const auto& p : panels) {
    whole.add(p.whole);
    contact.add(p.contact);
  }
  const double extent = std::max(whole.width(), whole.height());
  if (!(extent > 0.0))
    throw_input_error("the surface has no extent seen along the view direction",
                      ErrorContext{}.with_field("view_direction"),
                      "a surface that covers an area in the view");
  MapBox w = whole;
  if (crop != PressureMapCrop::Whole && !contact.empty()) {
    const double margin = std::max(kMapCropMargin * std::max(contact.width(), contact.height()),
                                   kMapMinCropMargin * extent);
    MapBox c = grown(contact, margin);
    c = {std::max(c.x0, whole.x0), std::max(c.y0, whole.y0), std::min(c.x1, whole.x1),
         std::min(c.y1, whole.y1)};
    const double area = std::max(c.width(), 0.0) * std::max(c.height(), 0.0);
    const double whole_area = std::max(whole.width(), kMapMinAspect * extent) *
                              std::max(whole.height(), kMapMinAspect * extent);
    if (crop == PressureMapCrop::Contact || area < kMapAutoCropShare * whole_area) w = c;
  }
  // Keep the aspect within kMapMinAspect: widen the thinner side about the centre.
  const double side = std::max(w.width(), w.height());
  if (w.width() < kMapMinAspect * side) {
    const double grow = 0.5 * (kMapMinAspect * side - w.width());
    w.x0 -= grow;
    w.x1 += grow;
  }
  if (w.height() < kMapMinAspect * side) {
    const double grow = 0.5 * (kMapMinAspect * side - w.height());
    w.y0 -= grow;
    w.y1 += grow;
  }
  return w;
}

// The triangles of each panel inside the window, farthest first; within the
// polygon budget.
void select_map_triangles(std::vector<MapPanelData>& panels, const MapBox& window,
                          const MapView& view, bool hide_back_faces) {
  std::size_t polygons = 0;
  struct Zero {
    double distance;
    std::size_t panel;
    int triangle;
  };
  std::vector<Zero> zeros;
  for (std::size_t k = 0; k < panels.size(); ++k) {
    MapPanelData& p = panels[k];
    const SurfaceMesh& m = p.panel->surface;
    const Eigen::VectorXd& pr = p.panel->pressure;
    std::vector<std::pair<double, int>> order;
    const double cx =
        p.contact.empty() ? 0.5 * (window.x0 + window.x1) : 0.5 * (p.contact.x0 + p.contact.x1);
    const double cy =
        p.contact.empty() ? 0.5 * (window.y0 + window.y1) : 0.5 * (p.contact.y0 + p.contact.y1);
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      MapBox b;
      double depth = 0.0, gx = 0.0, gy = 0.0;
      bool touched = false, uniform = true;
      for (int c = 0; c < 3; ++c) {
        const auto v = static_cast<std::size_t>(m.F(f, c));
        b.add(p.x[v], p.y[v]);
        depth += p.depth[v];
        gx += p.x[v];
        gy += p.y[v];
        touched |= pr[m.F(f, c)] > 0.0;
        uniform &= pr[m.F(f, c)] == pr[m.F(f, 0)];
      }
      if (!b.overlaps(window)) continue;
      if (hide_back_faces) {
        const Eigen::Vector3d a = m.V.row(m.F(f, 0)).transpose();
        const Eigen::Vector3d n =
            (m.V.row(m.F(f, 1)).transpose() - a).cross(m.V.row(m.F(f, 2)).transpose() - a);
        if (n.dot(view.d) >= 0.0) continue;
      }
      order.emplace_back(-depth, static_cast<int>(f));
      polygons += uniform ? 1 : 3;
      if (!touched) zeros.push_back({std::hypot(gx / 3 - cx, gy / 3 - cy), k, static_cast<int>(f)});
    }
    std::stable_sort(order.begin(), order.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    p.triangles.clear();
    for (const auto& [key, f] : order) p.triangles.push_back(f);
  }
  if (polygons <= kMapMaxPolygons) return;
  std::sort(zeros.begin(), zeros.end(), [](const Zero& a, const Zero& b) {
    if (a.distance != b.distance) return a.distance > b.distance;
    return a.panel != b.panel ? a.panel < b.panel : a.triangle < b.triangle;
  });
  std::vector<std::vector<char>> drop(panels.size());
  for (std::size_t k = 0; k < panels.size(); ++k)
    drop[k].assign(static_cast<std::size_t>(panels[k].panel->surface.F.rows()), 0);
  for (const Zero& z : zeros) {
    if (polygons <= kMapMaxPolygons) break;
    drop[z.panel][static_cast<std::size_t>(z.triangle)] = 1;
    ++panels[z.panel].left_out;
    --polygons;
  }
  for (std::size_t k = 0; k < panels.size(); ++k) {
    auto& t = panels[k].triangles;
    t.erase(std::remove_if(t.begin(), t.end(),
                           [&](int f) { return drop[k][static_cast<std::size_t>(f)] != 0; }),
            t.end());
  }
}

// Page placement of the window: X = x0 + (x − window.x0)·scale, Y = y0 + (window.y1 − y)·scale.
struct MapPlacement {
  MapBox window;
  double scale = 1.0;  // px per m
  double x0 = 0.0, y0 = 0.0;
  double px(double x) const { return x0 + (x - window.x0) * scale; }
  double py(double y) const { return y0 + (window.y1 - y) * scale; }
};

// Polygons written as <path>s, those of one fill that follow each other merged.
class MapPathWriter {
 public:
  explicit MapPathWriter(SvgWriter& svg) : svg_(svg) {}
  ~MapPathWriter() = default;
  MapPathWriter(const MapPathWriter&) = delete;
  MapPathWriter& operator=(const MapPathWriter&) = delete;

  void polygon(const std::string& fill, const Eigen::Vector2d* points, int count) {
    if (fill != fill_) flush();
    fill_ = fill;
    for (int i = 0; i < count; ++i) {
      d_ += i == 0 ? "M" : "L";
      d_ += svg_number(points[i].x());
      d_ += ' ';
      d_ += svg_number(points[i].y());
    }
    d_ += 'Z';
  }
  void flush() {
    if (!d_.empty())
      svg_ << "<path fill=\"" << fill_ << "\" stroke=\"" << fill_ << "\" d=\"" << d_ << "\"/>\n";
    d_.clear();
  }

 private:
  SvgWriter& svg_;
  std::string fill_;
  std::string d_;
};

// Colours: a pressure from 0 to top (0: the surface's grey shade); a field
// from bottom to top (field true).
void draw_map_triangles(SvgWriter& svg, const MapPanelData& p, const MapView& view,
                        const MapPlacement& at, double bottom, double top, bool field) {
  const SurfaceMesh& m = p.panel->surface;
  const Eigen::VectorXd& pr = p.panel->pressure;
  MapPathWriter out(svg);
  for (const int f : p.triangles) {
    std::array<Eigen::Vector2d, 3> q;
    std::array<std::string, 3> fill;
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)).transpose();
    const Eigen::Vector3d n =
        (m.V.row(m.F(f, 1)).transpose() - a).cross(m.V.row(m.F(f, 2)).transpose() - a);
    const double facing = n.norm() > 0.0 ? std::abs(n.dot(view.d)) / n.norm() : 0.0;
    const auto level =
        std::min(static_cast<std::size_t>(facing * kMapGreys.size()), kMapGreys.size() - 1);
    for (int c = 0; c < 3; ++c) {
      const int v = m.F(f, c);
      q[static_cast<std::size_t>(c)] = {at.px(p.x[static_cast<std::size_t>(v)]),
                                        at.py(p.y[static_cast<std::size_t>(v)])};
      fill[static_cast<std::size_t>(c)] =
          field  ? hex_color(viridis(top > bottom ? std::min(1.0, (pr[v] - bottom) / (top - bottom)) : 0.5))
          : pr[v] > 0.0 ? hex_color(viridis(pr[v] / top))
                        : kMapGreys[level];
    }
    if (fill[0] == fill[1] && fill[1] == fill[2]) {
      out.polygon(fill[0], q.data(), 3);
      continue;
    }
    // Each corner's share: the corner, the midpoints of its edges, the centroid.
    const Eigen::Vector2d g = (q[0] + q[1] + q[2]) / 3.0;
    for (std::size_t c = 0; c < 3; ++c) {
      const Eigen::Vector2d& qi = q[c];
      const Eigen::Vector2d& qj = q[(c + 1) % 3];
      const Eigen::Vector2d& qk = q[(c + 2) % 3];
      const std::array<Eigen::Vector2d, 4> share = {qi, 0.5 * (qi + qj), g, 0.5 * (qi + qk)};
      out.polygon(fill[c], share.data(), 4);
    }
  }
  out.flush();
}

// Caption items packed into lines no wider than `width`.
std::vector<std::string> pack_map_caption(const std::vector<std::string>& items, double width) {
  static constexpr std::string_view kSeparator = " \u00b7 ";
  std::vector<std::string> lines;
  for (const auto& item : items) {
    if (!lines.empty()) {
      std::string joined = lines.back();
      joined.append(kSeparator).append(item);
      if (estimated_text_width(joined, kMapTextSize) <= width) {
        lines.back() = std::move(joined);
        continue;
      }
    }
    lines.push_back(item);
  }
  return lines;
}

std::vector<std::string> map_caption(const MapPanelData& p, double width, const std::optional<MapField>& field) {
  if (field) {
    std::vector<std::string> items{fmt::format("{} {} to {} {}", field->name, map_sig3(p.bottom * field->scale),
                                               map_sig3(p.top * field->scale), field->unit)};
    if (field->cap && p.top > *field->cap) {
      const Eigen::VectorXd& v = p.panel->pressure;
      items.push_back(fmt::format("{} of {} vertices above {} {} in the top colour", (v.array() > *field->cap).count(),
                                  v.size(), map_sig3(*field->cap * field->scale), field->unit));
    }
    return pack_map_caption(items, width);
  }
  const PressureMetrics& m = p.metrics;
  std::vector<std::string> items;
  if (p.panel->load) items.push_back("load " + map_sig3(*p.panel->load) + " N");
  if (m.force > 0.0 || m.peak > 0.0) {
    items.push_back("map force " + map_sig3(m.force) + " N");
    items.push_back("peak " + map_sig3(m.peak * 1e-3) + " kPa");
    items.push_back("PPI " + map_sig3(m.peak_pressure_index * 1e-3) + " kPa");
    items.push_back("contact " + map_sig3(m.contact_area * 1e4) + " cm\u00b2");
    items.push_back("mean " + map_sig3(m.mean * 1e-3) + " kPa");
  } else {
    items.push_back("no contact: every pressure is 0");
  }
  std::vector<std::string> lines = pack_map_caption(items, width);
  if (p.left_out > 0)
    lines.push_back(fmt::format("{} triangles far from the contact not drawn", p.left_out));
  return lines;
}

// A scale bar of a nice length (1, 2 or 5 × 10^k mm) at most a quarter of the map's width.
void draw_map_scale_bar(SvgWriter& svg, const MapPlacement& at, double x, double y) {
  const double target_mm = 0.25 * at.window.width() * 1e3;
  int e = static_cast<int>(std::floor(std::log10(target_mm)));
  int mantissa = 1;
  for (const int m : {5, 2, 1}) {
    if (m * std::pow(10.0, e) <= target_mm) {
      mantissa = m;
      break;
    }
  }
  const double length_mm = mantissa * std::pow(10.0, e);
  const double length_px = length_mm * 1e-3 * at.scale;
  constexpr double kEnd = 3;
  svg << "<g class=\"scalebar\" stroke=\"" << kMapTextColor << "\" fill=\"none\">\n<path d=\"M" << x
      << " " << (y - kEnd) << "v" << 2 * kEnd << "M" << x << " " << y << "h" << length_px << "M"
      << (x + length_px) << " " << (y - kEnd) << "v" << 2 * kEnd << "\"/>\n";
  svg.text(x + length_px + 2 * kMapLabelGap, y + 0.35 * kMapTextSize,
           format_decimal(mantissa, e) + " mm", kMapTextSize, "start",
           std::string("stroke=\"none\" fill=\"") + kMapTextColor + "\"");
  svg << "</g>\n";
}

// Where the world axes point on the page, from (x, y).
void draw_map_axes_glyph(SvgWriter& svg, const MapView& view, double x, double y) {
  svg << "<g class=\"axes\" stroke=\"" << kMapMutedColor << "\" fill=\"" << kMapMutedColor
      << "\" font-size=\"" << kMapTextSize << "\" text-anchor=\"middle\">\n";
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
    const double dx = view.r.dot(e), dy = -view.u.dot(e);
    const double length = std::hypot(dx, dy);
    if (length < kMapGlyphMinShare) continue;
    const double tx = x + kMapGlyphLength * dx, ty = y + kMapGlyphLength * dy;
    svg << "<path d=\"M" << x << " " << y << "L" << tx << " " << ty << "\"/>\n";
    const double lx = tx + 0.6 * kMapTextSize * dx / length;
    const double ly = ty + 0.6 * kMapTextSize * dy / length + 0.35 * kMapTextSize;
    svg.text(lx, ly, std::string(1, "xyz"[k]), 0, "", "stroke=\"none\"");
  }
  svg << "</g>\n";
}

struct MapBarTick {
  double value;  // [kPa]
  std::string label;
};

// The colour bar's labels: nice ticks inside [low, top] (shown units), the
// top labelled by its value (and a field's bottom by its own).
std::vector<MapBarTick> map_bar_ticks(double low, double top, double height, bool label_low) {
  const int labels = std::clamp(static_cast<int>(height / kMapMaxTickSpacing) + 1, 2, 8);
  const AxisTicks t = choose_ticks(low, top, false, low, top, labels);
  std::vector<MapBarTick> out;
  const double clearance = kMapTopClearance / height * (top - low);
  if (label_low) out.push_back({low, map_sig3(low)});
  for (const Tick& tick : t.major)
    if (tick.value >= low + (label_low ? clearance : 0.0) && tick.value < top - clearance)
      out.push_back({tick.value, tick.label});
  out.push_back({top, map_sig3(top)});
  return out;
}

}  // namespace

std::string render_pressure_map_svg(const std::vector<PressureMapPanel>& panels,
                                    const PressureMapOptions& options) {
  if (panels.empty())
    throw_input_error("no pressure map to draw", ErrorContext{}.with_field("panels"),
                      "at least one panel");
  if (!std::isfinite(options.map_size) || options.map_size < kMapMinSize)
    throw_input_error("map_size " + svg_number(options.map_size) + " px is too small",
                      ErrorContext{}.with_field("map_size"),
                      "map_size >= " + svg_number(kMapMinSize) + " px");
  for (std::size_t i = 0; i < panels.size(); ++i) check_map_panel(panels[i], i);
  const MapView view = map_view(options);
  std::vector<MapPanelData> data;
  data.reserve(panels.size());
  const bool field = options.field.has_value();
  for (const auto& p : panels) data.push_back(prepare_map_panel(p, view, field));
  const MapBox window = choose_map_window(data, field ? PressureMapCrop::Whole : options.crop);
  select_map_triangles(data, window, view, options.hide_back_faces);
  double top = 0.0;
  double bottom = field ? std::numeric_limits<double>::infinity() : 0.0;
  for (const auto& p : data) {
    top = std::max(top, p.top);
    bottom = std::min(bottom, p.bottom);
  }
  if (field && options.field->cap && *options.field->cap < top) top = std::max(*options.field->cap, bottom);
  // Shown units: kPa for pressures, the field's own.
  const double shown = field ? options.field->scale : 1e-3;
  const std::string unit = field ? options.field->unit : "kPa";

  // Layout.
  const double scale = options.map_size / std::max(window.width(), window.height());
  const double map_w = window.width() * scale, map_h = window.height() * scale;
  const double panel_w = std::max(map_w, kMapMinPanelWidth);
  std::vector<std::vector<std::string>> captions;
  std::size_t caption_lines = 0;
  for (const auto& p : data) {
    captions.push_back(map_caption(p, panel_w, options.field));
    caption_lines = std::max(caption_lines, captions.back().size());
  }
  const auto n = static_cast<double>(panels.size());
  const double title_h = options.title.empty() ? 0.0 : kMapFigureTitleHeight;
  const double map_top = kMapEdge + title_h + kMapTitleRow + kMapViewRow;
  const double bar_h = std::max(map_h, kMapMinBarHeight);
  const double bar_x = kMapEdge + n * panel_w + (n - 1) * kMapPanelGap + kMapBarGap;
  std::vector<MapBarTick> ticks;
  double label_w = field ? 0.0 : estimated_text_width("no contact", kMapTextSize);
  const double top_shown = top * shown, low_shown = bottom * shown;
  const bool bar = field ? top > bottom : top > 0.0;
  if (bar) {
    ticks = map_bar_ticks(low_shown, top_shown, bar_h, field);
    for (const auto& t : ticks)
      label_w = std::max(label_w, estimated_text_width(t.label, kMapTextSize));
  } else {
    label_w = estimated_text_width(field ? "one value: " + map_sig3(top_shown) + " " + unit
                                         : std::string("no contact: every pressure is 0"),
                                   kMapTextSize);
  }
  const double width = bar_x + kMapBarWidth + kMapTickLength + kMapLabelGap + label_w + kMapEdge;
  const double below_map =
      std::max(kMapScaleRow + kMapCaptionRow * static_cast<double>(caption_lines),
               bar_h - map_h + kMapSwatchHeight + 2 * kMapCaptionRow);
  const double height = map_top + map_h + below_map + kMapEdge;

  SvgWriter svg;
  svg.begin(width, height);
  const std::string text_fill = std::string("fill=\"") + kMapTextColor + "\"";
  const double panels_right = bar_x - kMapBarGap;
  if (!options.title.empty())
    svg.text(0.5 * (kMapEdge + panels_right), kMapEdge + 0.7 * kMapFigureTitleHeight, options.title,
             kMapFigureTitleSize, "middle", "font-weight=\"bold\" " + text_fill);
  const std::string view_text =
      (options.view_label.empty() ? std::string() : options.view_label + ", ") + "looking along " +
      map_direction_text(view.d);
  for (std::size_t k = 0; k < data.size(); ++k) {
    const MapPanelData& p = data[k];
    const double px = kMapEdge + static_cast<double>(k) * (panel_w + kMapPanelGap);
    MapPlacement at;
    at.window = window;
    at.scale = scale;
    at.x0 = px + 0.5 * (panel_w - map_w);
    at.y0 = map_top;
    svg << "<g class=\"panel\">\n";
    const double title_y = kMapEdge + title_h + 0.8 * kMapPanelTitleSize;
    svg.text(px, title_y, p.panel->title, kMapPanelTitleSize, "start",
             "font-weight=\"bold\" " + text_fill);
    svg.text(px, title_y + kMapViewRow, view_text, kMapTextSize, "start",
             std::string("fill=\"") + kMapMutedColor + "\"");
    const std::string clip = "map-clip" + std::to_string(k);
    svg << "<defs><clipPath id=\"" << clip << "\"><rect x=\"" << at.x0 << "\" y=\"" << at.y0
        << "\" width=\"" << map_w << "\" height=\"" << map_h << "\"/></clipPath></defs>\n";
    svg << "<g class=\"map\" clip-path=\"url(#" << clip << ")\" stroke-width=\"" << kMapSeam
        << "\" stroke-linejoin=\"round\">\n";
    draw_map_triangles(svg, p, view, at, bottom, top, field);
    svg << "</g>\n<rect class=\"map-frame\" x=\"" << at.x0 << "\" y=\"" << at.y0 << "\" width=\""
        << map_w << "\" height=\"" << map_h << "\" fill=\"none\" stroke=\"" << kMapFrameColor
        << "\"/>\n";
    const double row_y = at.y0 + map_h + 0.5 * kMapScaleRow;
    draw_map_scale_bar(svg, at, at.x0, row_y);
    draw_map_axes_glyph(svg, view, at.x0 + map_w - 2 * kMapGlyphLength, row_y);
    svg << "<g class=\"caption\" font-size=\"" << kMapTextSize << "\" " << text_fill << ">\n";
    double y = at.y0 + map_h + kMapScaleRow + 0.8 * kMapTextSize;
    for (const auto& line : captions[k]) {
      svg.text(px, y, line, 0, "");
      y += kMapCaptionRow;
    }
    svg << "</g>\n</g>\n";
  }

  // The colour bar, bottom 0, top the largest pressure.
  const double bar_y0 = map_top, bar_y1 = map_top + bar_h;
  const double label_x = bar_x + kMapBarWidth + kMapTickLength + kMapLabelGap;
  double swatch_y = bar_y0;
  if (bar) {
    svg << "<defs><linearGradient id=\"map-scale\" x1=\"0\" y1=\"1\" x2=\"0\" y2=\"0\">";
    for (int i = 0; i < kViridisStops; ++i)
      svg << "<stop offset=\"" << fmt::format("{:g}", i / double(kViridisStops - 1))
          << "\" stop-color=\"" << hex_color(viridis_stop(i)) << "\"/>";
    svg << "</linearGradient></defs>\n";
    svg.text(bar_x, bar_y0 - 0.6 * kMapTextSize, unit, kMapTextSize, "start", text_fill);
    svg << "<rect class=\"colorbar\" x=\"" << bar_x << "\" y=\"" << bar_y0 << "\" width=\""
        << kMapBarWidth << "\" height=\"" << bar_h << "\" fill=\"url(#map-scale)\" stroke=\""
        << kMapBarFrameColor << "\"/>\n";
    svg << "<path stroke=\"" << kMapBarFrameColor << "\" d=\"";
    for (const auto& t : ticks)
      svg << "M" << (bar_x + kMapBarWidth) << " " << (bar_y1 - (t.value - low_shown) / (top_shown - low_shown) * bar_h) << "h"
          << kMapTickLength;
    svg << "\"/>\n<g class=\"colorbar-ticks\" font-size=\"" << kMapTextSize << "\" " << text_fill
        << ">\n";
    for (const auto& t : ticks)
      svg.text(label_x, bar_y1 - (t.value - low_shown) / (top_shown - low_shown) * bar_h + 0.35 * kMapTextSize, t.label,
               0, "");
    svg << "</g>\n";
    swatch_y = bar_y1 + kMapCaptionRow;
  }
  if (field) {
    if (!bar) svg.text(bar_x, bar_y0, "one value: " + map_sig3(top_shown) + " " + unit, kMapTextSize, "start", text_fill);
  } else {
    svg << "<rect class=\"swatch\" x=\"" << bar_x << "\" y=\"" << swatch_y << "\" width=\""
        << kMapBarWidth << "\" height=\"" << kMapSwatchHeight << "\" fill=\"" << kMapSwatchGrey
        << "\" stroke=\"" << kMapBarFrameColor << "\"/>\n";
    svg.text(label_x, swatch_y + 0.5 * kMapSwatchHeight + 0.35 * kMapTextSize,
             top > 0.0 ? "no contact" : "no contact: every pressure is 0", kMapTextSize, "start",
             text_fill);
  }
  svg.end();
  return std::move(svg.str());
}

void write_pressure_map_svg(const std::filesystem::path& path,
                            const std::vector<PressureMapPanel>& panels,
                            const PressureMapOptions& options) {
  const std::string text = render_pressure_map_svg(panels, options);
  write_file_atomic(path, [&](std::ostream& os) { os << text; });
}

}  // namespace palpa::report
