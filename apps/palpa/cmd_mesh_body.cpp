// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa mesh body: analytic closed test bodies (sphere, rounded block, thigh, foot).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <memory>
#include <string>

#include "cli_common.hpp"
#include "mesh_options.hpp"
#include "palpa/core/error.hpp"
#include "palpa/io/mesh.hpp"
#include "palpa/mesh/bodies.hpp"
#include "palpa/mesh/layer.hpp"
#include "palpa/mesh/surface_check.hpp"

namespace palpa::cli {

namespace {

struct BodyArgs {
  std::string shape;
  double length = 0.0, width = 0.0, height = 0.0, radius = 0.0;
  double edge = 5e-3;
  std::string output;
};

void run_body(const BodyArgs& a) {
  mesh::BodyOptions o;
  o.shape = mesh::parse_body_shape(a.shape, ErrorContext{"", 0, 0, "SHAPE"});
  o.size = Eigen::Vector3d(a.length, a.width, a.height);
  if (o.shape == mesh::BodyShape::Sphere || o.shape == mesh::BodyShape::Foot) {
    o.size = Eigen::Vector3d(a.length, a.length, a.length);
  } else if (!o.size.isZero() && !(o.size.minCoeff() > 0.0)) {
    throw_input_error("give --length, --width and --height together", option_context("--length"),
                      "all three sizes, or none for the default");
  }
  o.radius = a.radius;
  o.edge_length = a.edge;
  if (const double smallest = mesh::body_smallest_feature(o); !(a.edge <= smallest / 4.0)) {
    throw_input_error(fmt::format("an edge of {} for a {} whose smallest feature is {}",
                                  format_quantity(a.edge, Dimension::Length), mesh::body_shape_name(o.shape),
                                  format_quantity(smallest, Dimension::Length)),
                      option_context("--edge"), "at most a quarter of the smallest feature");
  }
  // The body's area is at most its bounding box's.
  check_edge_for(2.0 * (o.size.x() * o.size.y() + o.size.y() * o.size.z() + o.size.z() * o.size.x()), a.edge,
                 fmt::format("a {}", mesh::body_shape_name(o.shape)));
  const SurfaceMesh m = mesh::make_body(o);
  write_surface_mesh(a.output, m);
  spdlog::info("wrote {}: {} {} with {} vertices, {} triangles, volume {:.4g} cm3",
               a.output, mesh::body_shape_name(o.shape), "surface", m.V.rows(), m.F.rows(),
               mesh::enclosed_volume(m) * 1e6);
}

}  // namespace

void add_mesh_body(CLI::App& mesh) {
  auto ba = std::make_shared<BodyArgs>();
  auto* body = mesh.add_subcommand("body", "An analytic closed test body surface.");
  body->add_option("SHAPE", ba->shape, "sphere, rounded-block, thigh or foot")->required();
  add_quantity_option(*body, "--length", ba->length, Dimension::Length,
                      "Size along x (sphere: diameter; foot: heel to toe); default per shape", Sign::Positive);
  add_quantity_option(*body, "--width", ba->width, Dimension::Length, "Size along y (block, thigh)", Sign::Positive);
  add_quantity_option(*body, "--height", ba->height, Dimension::Length,
                      "Size along z (block, thigh)", Sign::Positive);
  add_quantity_option(*body, "--radius", ba->radius, Dimension::Length,
                      "Block edge rounding radius (default 10mm)", Sign::NonNegative);
  add_quantity_option(*body, "--edge", ba->edge, Dimension::Length,
                      "Target triangle edge length (default 5mm)", Sign::Positive);
  body->add_option("-o,--output", ba->output, "Output surface (.obj .ply .stl .off .vtu), in m")
      ->required();
  body->callback([ba] { run_body(*ba); });
}

}  // namespace palpa::cli
