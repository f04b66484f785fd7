// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Pressure maps as pictures: the contact pressure on a triangle surface seen
// in an orthographic view, as a self-contained SVG 1.1 document, so that
// where a body is pressed can be seen without a plotting script.
//
//   report::PressureMapPanel p{skin, pressure, "body side", metrics, load};
//   report::PressureMapOptions o;
//   o.view_direction = {0, 0, 1};  // from below, looking up at the body
//   o.view_label = "seen from the support";
//   report::write_pressure_map_svg("body_pressure.svg", {p}, o);
//
// A figure holds one or more panels side by side (e.g. before and after a
// design) sharing one view window, one scale in mm and one colour scale, so
// that they compare directly:
//  - Projection: orthographic along `view_direction`; the projected `up`
//    points up the page and (view × up) to the right, so the picture is what
//    an eye looking along the direction sees (a view from below is the mirror
//    image of the view from above). A small glyph shows where the world axes
//    point. Triangles are painted from the farthest to the nearest (painter's
//    algorithm on their centroids' depth).
//  - Colour: each vertex's pressure paints its share of every triangle around
//    it (the corner up to the edge midpoints and the centroid: the barycentric
//    areas over which pressure_metrics integrates the force); a triangle
//    whose corners get one colour is painted whole. Pressures p > 0 take the
//    viridis colour of p / p_max (report/colormap.hpp), p_max the largest
//    pressure on the triangles of all panels; zero pressure is light grey (shaded a little by
//    how squarely the triangle faces the viewer, so the shape stays legible).
//    Colours are exactly the per-vertex values: nothing is smoothed.
//  - Colour bar in kPa beside the panels: the gradient spans exactly
//    [0, p_max]; its labels are "nice" ticks (report/ticks.hpp) inside the
//    range, with the top labelled by p_max itself to 3 significant digits,
//    and a grey swatch for "0 (no contact)". Without any contact there is no
//    bar, only the swatch and "no contact: every pressure is 0".
//  - Window: `crop` (Auto: the contact patch with a margin of a quarter of its
//    size when that is under a third of the surface's projected extent, else
//    the whole surface); the aspect ratio is kept (a window thinner than
//    2:5 is widened to 2:5) and a scale bar gives the length in mm.
//  - Caption under each panel: its title (e.g. the side), the view, the load,
//    the map's integrated force, peak, peak pressure index, contact area and
//    mean pressure (report/pressure_metrics.hpp).
//  - Size: polygons of one fill that follow each other are one <path>; when
//    a figure would need more than about 80 000 polygons (several MB), the
//    zero-pressure triangles farthest from the contact are left out and the
//    caption says how many.
// Classes for readers of the document: the polygons are <path> elements in
// groups of class "map"; the bar is a <rect class="colorbar">, its labels
// <text> in a group of class "colorbar-ticks"; caption lines are <text> in
// groups of class "caption". Output is deterministic; coordinates are rounded
// to 0.1 px.

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "palpa/geometry/mesh.hpp"
#include "palpa/report/pressure_metrics.hpp"

namespace palpa::report {

struct PressureMapPanel {
  // V: #V×3 positions [m]; F: #F×3 triangles, rows of V (vertices in no
  // triangle are not drawn and do not count for the window).
  SurfaceMesh surface;
  Eigen::VectorXd pressure;  // #V pressures [Pa], finite, >= 0
  std::string title;         // first caption line, e.g. "body side"
  // The caption's figures; unset: pressure_metrics(surface, pressure).
  std::optional<PressureMetrics> metrics = std::nullopt;
  std::optional<double> load = std::nullopt;  // the load's magnitude [N], for the caption
};

enum class PressureMapCrop {
  Auto,     // Contact when the contact window is under a third of the whole surface's, else Whole
  Contact,  // the triangles with a pressure, plus a margin (Whole without contact)
  Whole,    // every triangle
};

// A field over the surface other than a contact pressure (a layer's depth,
// its Young's modulus): every vertex coloured from the smallest value to the
// largest (none is "no contact"), the caption giving the range.
struct MapField {
  std::string name;   // "depth"
  std::string unit;   // as shown, "mm"
  double scale = 1.0;  // SI value × scale = the value shown (1e3 for mm)
  // Set: values above it (SI) take the top colour, and the caption says how
  // many (a few outliers, such as a layer's depth at a clipped body's cut,
  // would otherwise flatten the colours of the rest).
  std::optional<double> cap = std::nullopt;
};

struct PressureMapOptions {
  // The direction the viewer looks along (eye into the scene); any finite,
  // non-zero length.
  Eigen::Vector3d view_direction{0.0, 0.0, -1.0};
  // The world direction drawn pointing up the page (its part across the view
  // direction); unset: the world axis most across the view, y before z before x.
  std::optional<Eigen::Vector3d> up = std::nullopt;
  // Where the viewer is, e.g. "seen from the support"; the direction is added.
  std::string view_label;
  PressureMapCrop crop = PressureMapCrop::Auto;
  // Leave out the triangles that face away from the viewer (normal
  // (V1−V0)×(V2−V0) along the view direction, or edge-on). Exact for closed
  // surfaces wound outward, whose back faces are always hidden behind front
  // ones, and it halves their polygons; an open surface would show holes.
  bool hide_back_faces = false;
  std::string title;      // above the panels; "" for none
  double map_size = 420;  // the longer side of each panel's map [px], >= 160
  // Set: the panels' "pressure" is this field instead (values >= 0, SI), the
  // whole surface drawn.
  std::optional<MapField> field = std::nullopt;
};

// The panels as one SVG document (UTF-8).
// Throws palpa::Error (Input) naming the panel and what was expected for: no
// panel, a surface without triangles or with a triangle's vertex out of range
// or non-finite positions, a pressure count other than the vertex count, a
// negative or non-finite pressure, a zero or non-finite view direction, an
// `up` along it, a map_size below 160 px, a surface with no extent in the view.
std::string render_pressure_map_svg(const std::vector<PressureMapPanel>& panels,
                                    const PressureMapOptions& options = {});

// Renders and writes to `path` atomically (core/atomic_file.hpp).
void write_pressure_map_svg(const std::filesystem::path& path,
                            const std::vector<PressureMapPanel>& panels,
                            const PressureMapOptions& options = {});

}  // namespace palpa::report
