// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/sim3d/scene.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <map>
#include <numbers>
#include <set>

#include "palpa/axisym/mesh.hpp"
#include "palpa/core/json.hpp"
#include "palpa/geometry/boundary.hpp"
#include "palpa/io/mesh.hpp"
#include "palpa/material/material_file.hpp"
#include "palpa/sim3d/scene_json.hpp"
#include "palpa/sim3d/shapes.hpp"
#include "palpa/tet/mesh.hpp"

namespace palpa::sim3d {

namespace {

namespace fs = std::filesystem;

int axis_of(const JsonView& v) {
  const std::string a = v.as_string();
  if (a == "x") return 0;
  if (a == "y") return 1;
  if (a == "z") return 2;
  v.fail(fmt::format("unknown axis '{}'", a), "\"x\", \"y\" or \"z\"");
}

std::array<bool, 3> components_of(const JsonView& v) {
  const std::string s = v.as_string();
  std::array<bool, 3> c{false, false, false};
  for (char ch : s) {
    if (ch < 'x' || ch > 'z') v.fail(fmt::format("'{}' is not a set of components", s), "letters from \"xyz\"");
    c[static_cast<std::size_t>(ch - 'x')] = true;
  }
  if (!(c[0] || c[1] || c[2])) v.fail("no component given", "letters from \"xyz\"");
  return c;
}

SurfaceMesh read_shape(const JsonView& shape, const fs::path& scene_file) {
  shape.expect_only({"cylinder", "box", "sphere", "file", "unit"});
  if (const auto c = shape.find("cylinder")) {
    c->expect_only({"radius", "height", "segments"});
    const int seg = c->has("segments") ? read_count(c->at("segments"), 3, 4096) : 64;
    return make_cylinder(read_positive(c->at("radius"), Dimension::Length), read_positive(c->at("height"), Dimension::Length), seg);
  }
  if (const auto b = shape.find("box")) {
    b->expect_only({"size", "divisions"});
    const int n = b->has("divisions") ? read_count(b->at("divisions"), 1, 500) : 4;
    const Eigen::Vector3d size = read_quantity3(b->at("size"), Dimension::Length);
    if (!(size.minCoeff() > 0.0)) b->at("size").fail("sizes must be > 0", "three positive lengths");
    return make_box_surface(size, n);
  }
  if (const auto s = shape.find("sphere")) {
    s->expect_only({"radius", "level"});
    const int level = s->has("level") ? read_count(s->at("level"), 0, 7) : 3;
    return make_sphere(read_positive(s->at("radius"), Dimension::Length), level);
  }
  if (const auto f = shape.find("file")) {
    MeshReadOptions opt;
    if (const auto u = shape.find("unit")) opt.unit_to_si = parse_unit(u->as_string(), Dimension::Length, u->context());
    return read_surface_mesh(resolve_scene_path(scene_file, f->as_string()), opt);
  }
  shape.fail("no shape given", "one of \"cylinder\", \"box\", \"sphere\", \"file\"");
}

// "cylinder": {"radius", "height", "rim", "level", "segments", "sector"}: the
// (r, z) grid of `palpa poke`'s layer under a punch of radius "rim" at that
// mesh level, swept around the axis.
tet::StructuredMesh read_cylinder_body(const JsonView& c) {
  c.expect_only({"radius", "height", "rim", "level", "segments", "sector"});
  axisym::LayerGeometry g;
  g.outer_radius = read_positive(c.at("radius"), Dimension::Length);
  g.thickness = read_positive(c.at("height"), Dimension::Length);
  g.punch_radius = read_positive(c.at("rim"), Dimension::Length);
  if (!(g.outer_radius > 1.5 * g.punch_radius)) {
    c.at("rim").fail(fmt::format("a rim at {:g} mm is not well inside the radius {:g} mm", g.punch_radius * 1e3,
                                 g.outer_radius * 1e3),
                     "a rim of at most 2/3 of the radius");
  }
  const int level = c.has("level") ? static_cast<int>(c.at("level").as_integer()) : 1;
  if (level < 0 || level > 4) c.at("level").fail(fmt::format("level {} is out of range", level), "0 to 4");
  const int segments = c.has("segments") ? static_cast<int>(c.at("segments").as_integer()) : 96;
  if (segments < 8 || segments > 1024) {
    c.at("segments").fail(fmt::format("{} segments", segments), "8 to 1024 segments around the full circle");
  }
  const double angle = c.has("sector") ? c.at("sector").as_quantity(Dimension::Angle) : 2.0 * std::numbers::pi;
  const double share = segments * angle / (2.0 * std::numbers::pi);
  if (!(angle > 0.0 && angle <= 2.0 * std::numbers::pi * (1.0 + 1e-12)) ||
      std::abs(share - std::round(share)) > 1e-9 * segments || std::round(share) < 1.0) {
    c.at("sector").fail("not a whole number of segments", "an angle up to \"360 deg\" that the segments divide");
  }
  const axisym::AxisymMesh grid = axisym::make_layer_mesh(g, level);
  std::vector<double> radii, depths;
  for (const int n : grid.top_nodes) radii.push_back(grid.nodes(n, 0));
  for (int j = grid.rows - 1; j >= 0; --j) depths.push_back(-grid.nodes(grid.node(0, j), 1));
  radii.front() = 0.0;
  depths.front() = 0.0;
  return tet::make_cylinder_mesh(radii, depths, segments, angle);
}

}  // namespace

Scene read_scene(const fs::path& path) {
  const Json doc = read_json_file(path);
  const JsonView root(doc, path.string());
  root.expect_only({"palpa_scene", "body", "gravity", "obstacles", "steps", "contact", "solver", "dynamics",
                    "local", "output"});
  if (root.at("palpa_scene").as_integer() != 1) root.at("palpa_scene").fail("unsupported version", "1");
  Scene s;
  s.file = path;

  // ---- body
  const JsonView body = root.at("body");
  body.expect_only({"box", "cylinder", "mesh", "unit", "materials", "element", "stabilization", "fixed"});
  s.element = read_element(body);
  std::map<std::string, std::vector<int>> sets;
  if (int(body.has("box")) + int(body.has("cylinder")) + int(body.has("mesh")) > 1) {
    body.fail("more than one of \"box\", \"cylinder\" and \"mesh\" given", "one of them");
  }
  if (const auto cyl = body.find("cylinder")) {
    tet::StructuredMesh c = read_cylinder_body(*cyl);
    s.mesh = std::move(c.mesh);
    sets = std::move(c.vertex_sets);
    s.mesh_name = fmt::format("{}: body.cylinder", path.string());
  } else if (const auto box = body.find("box")) {
    box->expect_only({"size", "cells"});
    const Eigen::Vector3d size = read_quantity3(box->at("size"), Dimension::Length);
    if (!(size.minCoeff() > 0.0)) box->at("size").fail("sizes must be > 0", "three positive lengths");
    const std::vector<double> cells = box->at("cells").as_number_array();
    if (cells.size() != 3 || std::any_of(cells.begin(), cells.end(), [](double c) { return c < 1 || c != std::floor(c) || c > 1000; })) {
      box->at("cells").fail("expected 3 whole numbers from 1 to 1000", "[nx, ny, nz]");
    }
    // Six tets per cell; beyond kMaxBoxTets the run would not fit in memory.
    constexpr double kMaxBoxTets = 5e6;
    if (const double tets = 6.0 * cells[0] * cells[1] * cells[2]; tets > kMaxBoxTets) {
      box->at("cells").fail(fmt::format("{:.0f} × {:.0f} × {:.0f} cells, {:.3g} tetrahedra", cells[0], cells[1],
                                        cells[2], tets),
                            fmt::format("at most {:.0f} tetrahedra (6 per cell)", kMaxBoxTets));
    }
    const Eigen::Vector3d lo(-size[0] / 2, -size[1] / 2, -size[2]);
    const Eigen::Vector3d hi(size[0] / 2, size[1] / 2, 0.0);
    tet::BoxMesh b = tet::make_box_mesh(lo, hi, Eigen::Vector3i(int(cells[0]), int(cells[1]), int(cells[2])));
    s.mesh = std::move(b.mesh);
    sets = std::move(b.vertex_sets);
    s.mesh_name = fmt::format("{}: body.box", path.string());
    s.is_box = true;
  } else {
    const JsonView m = body.at("mesh");
    MeshReadOptions opt;
    if (const auto u = body.find("unit")) opt.unit_to_si = parse_unit(u->as_string(), Dimension::Length, u->context());
    const fs::path mesh_path = resolve_scene_path(path, m.as_string());
    s.mesh = read_tet_mesh(mesh_path, opt);
    s.mesh_name = mesh_path.string();
  }
  tet::prepare_tet_mesh(s.mesh, s.mesh_name);

  // Materials per region.
  const JsonView mats = body.at("materials");
  if (mats.size() == 0) mats.fail("no material given", "at least one {\"material\": ..., \"density\": ...}");
  const Eigen::Index nt = s.mesh.T.rows();
  const Eigen::VectorXi region = s.mesh.region.size() == nt ? s.mesh.region : Eigen::VectorXi::Zero(nt);
  std::set<int> regions(region.data(), region.data() + region.size());
  s.element_material = Eigen::VectorXi::Constant(nt, -1);
  for (std::size_t k = 0; k < mats.size(); ++k) {
    const JsonView mk = mats.at(k);
    mk.expect_only({"material", "density", "regions"});
    tet::BodyMaterial bm;
    const JsonView mv = mk.at("material");
    if (mv.is_object()) {
      bm.material = material::material_from_json(mv);
    } else {
      bm.material = material::read_material_file(resolve_scene_path(path, mv.as_string())).material;
    }
    bm.density = mk.has("density") ? mk.at("density").as_quantity(Dimension::Density) : 1000.0;
    if (!(bm.density >= 0.0)) mk.at("density").fail("must be ≥ 0", "a density such as \"1000 kg/m^3\"");
    std::set<int> mine;
    if (const auto r = mk.find("regions")) {
      for (double v : r->as_number_array()) {
        if (!regions.count(static_cast<int>(v)) || v != std::floor(v)) {
          r->fail(fmt::format("region {} is not in the mesh", v), "region ids of the mesh's tets");
        }
        mine.insert(static_cast<int>(v));
      }
    } else {
      mine = regions;
    }
    for (Eigen::Index e = 0; e < nt; ++e) {
      if (!mine.count(region[e])) continue;
      if (s.element_material[e] >= 0) {
        mk.fail(fmt::format("region {} already has material {}", region[e], s.element_material[e]),
                "each region in one material's \"regions\"");
      }
      s.element_material[e] = static_cast<int>(k);
    }
    s.materials.push_back(std::move(bm));
  }
  for (Eigen::Index e = 0; e < nt; ++e) {
    if (s.element_material[e] < 0) {
      mats.fail(fmt::format("region {} (tetrahedron {}) has no material", region[e], e), "a material for every region");
    }
  }

  // Fixed vertex sets.
  const geometry::Boundary boundary = geometry::boundary_of(s.mesh);
  sets["boundary"] = boundary.vertices;
  for (Eigen::Index f = 0; f < s.mesh.boundary_marker.size() && f < s.mesh.boundary.rows(); ++f) {
    auto& v = sets[fmt::format("marker:{}", s.mesh.boundary_marker[f])];
    for (int c = 0; c < 3; ++c) v.push_back(s.mesh.boundary(f, c));
  }
  if (const auto fixed = body.find("fixed")) {
    for (std::size_t i = 0; i < fixed->size(); ++i) {
      const JsonView fi = fixed->at(i);
      fi.expect_only({"set", "below", "above", "axis", "components"});
      FixedSpec spec;
      if (const auto c = fi.find("components")) spec.components = components_of(*c);
      const std::string comps = std::string(spec.components[0] ? "x" : "") + (spec.components[1] ? "y" : "") +
                                (spec.components[2] ? "z" : "");
      if (const auto name = fi.find("set")) {
        const std::string n = name->as_string();
        const auto it = sets.find(n);
        if (it == sets.end()) {
          std::string known;
          for (const auto& [k, v] : sets) known += (known.empty() ? "" : ", ") + k;
          name->fail(fmt::format("unknown vertex set '{}'", n), "one of: " + known);
        }
        spec.vertices = it->second;
        spec.description = fmt::format("{} ({})", n, comps);
      } else {
        const bool below = fi.has("below");
        if (below == fi.has("above")) fi.fail("need exactly one of \"set\", \"below\", \"above\"");
        const JsonView lim = fi.at(below ? "below" : "above");
        const double value = lim.as_quantity(Dimension::Length);
        const int axis = axis_of(fi.at("axis"));
        for (Eigen::Index v = 0; v < s.mesh.V.rows(); ++v) {
          const double x = s.mesh.V(v, axis);
          if (below ? x <= value : x >= value) spec.vertices.push_back(static_cast<int>(v));
        }
        spec.description = fmt::format("{} {} {} mm ({})", "xyz"[axis], below ? "≤" : "≥", value * 1e3, comps);
      }
      std::sort(spec.vertices.begin(), spec.vertices.end());
      spec.vertices.erase(std::unique(spec.vertices.begin(), spec.vertices.end()), spec.vertices.end());
      if (spec.vertices.empty()) fi.fail("selects no vertex", "a set with at least one vertex");
      s.fixed.push_back(std::move(spec));
    }
  }

  if (const auto g = root.find("gravity")) s.gravity = read_quantity3(*g, Dimension::Acceleration);

  // ---- obstacles
  bool any_path = false;
  if (const auto obs = root.find("obstacles")) {
    std::set<std::string> names;
    for (std::size_t i = 0; i < obs->size(); ++i) {
      const JsonView oi = obs->at(i);
      oi.expect_only({"name", "shape", "position", "rotation", "path"});
      ObstacleSpec o;
      o.name = oi.has("name") ? oi.at("name").as_string() : fmt::format("obstacle{}", i);
      if (o.name.empty() || o.name.find_first_of("/\\ ") != std::string::npos || !names.insert(o.name).second) {
        oi.at("name").fail(fmt::format("'{}' is empty, repeated or has a space or slash", o.name),
                           "a unique name usable in file names");
      }
      o.mesh = read_shape(oi.at("shape"), path);
      if (const auto p = oi.find("position")) o.position = read_quantity3(*p, Dimension::Length);
      if (const auto r = oi.find("rotation")) {
        o.rotation = read_rotation(*r);
      }
      if (const auto p = oi.find("path")) {
        p->expect_only({"direction", "depth"});
        const Eigen::Vector3d dir = read_number3(p->at("direction"));
        if (!(dir.norm() > 0.0)) p->at("direction").fail("zero direction", "a non-zero direction");
        o.direction = dir.normalized();
        o.depth = p->at("depth").as_quantity(Dimension::Length);
        if (!(o.depth > 0.0)) p->at("depth").fail("must be > 0", "a positive length");
        o.has_path = true;
        any_path = true;
      }
      s.obstacles.push_back(std::move(o));
    }
  }
  if (const auto st = root.find("steps")) {
    const long long n = st->as_integer();
    if (n < 1 || n > 100000) st->fail(fmt::format("{} steps", n), "1 to 100000");
    s.steps = static_cast<int>(n);
  } else if (any_path) {
    s.steps = 10;
  }
  // A step longer than half the thinner of the obstacle and the body along
  // the path could carry the obstacle through the body between two
  // equilibria (the contact sees only the poses): refused with the steps
  // that would do.
  for (std::size_t i = 0; i < s.obstacles.size(); ++i) {
    const ObstacleSpec& o = s.obstacles[i];
    if (!o.has_path || o.mesh.V.rows() == 0 || s.mesh.V.rows() == 0) continue;
    const auto extent = [&](const Eigen::VectorXd& along) { return along.maxCoeff() - along.minCoeff(); };
    const double own = extent(o.mesh.V * (o.rotation.transpose() * o.direction));
    const double thickness = extent(s.mesh.V * o.direction);
    const double limit = 0.5 * std::min(own, thickness);
    const double travel = o.depth / s.steps;
    if (travel > limit) {
      const double needed = std::ceil(o.depth / limit);
      const JsonView where = root.has("steps") ? root.at("steps") : root.at("obstacles").at(i).at("path").at("depth");
      where.fail(fmt::format("obstacle '{}' moves {} per step, more than half the thinner of itself ({}) and the "
                             "body ({}) along its path: it could pass through the body between two steps",
                             o.name, format_quantity(travel, Dimension::Length),
                             format_quantity(own, Dimension::Length), format_quantity(thickness, Dimension::Length)),
                 needed <= 100000 ? fmt::format("at least {:.0f} steps for this depth", needed)
                                  : "a shallower path, or a thicker obstacle or body");
    }
  }

  if (const auto c = root.find("contact")) {
    c->expect_only({"stiffness", "max_penetration", "sampling", "subdivisions", "friction"});
    if (const auto fr = c->find("friction")) {
      const std::string f = fr->as_string();
      if (f == "stick") {
        s.contact.friction = contact::Friction::Stick;
      } else if (f != "frictionless") {
        fr->fail(fmt::format("unknown friction '{}'", f), "\"frictionless\" or \"stick\"");
      }
    }
    if (const auto sm = c->find("sampling")) s.contact.sampling = read_contact_sampling(*sm);
    if (const auto n = c->find("subdivisions")) s.contact.subdivisions = read_count(*n, 1, 8);
    if (const auto k = c->find("stiffness")) {
      s.contact.stiffness = read_positive(*k, s.contact.sampling == body::ContactSampling::Surface
                                                  ? Dimension::PressurePerLength
                                                  : Dimension::Stiffness);
    }
    if (const auto p = c->find("max_penetration")) s.contact.max_penetration = read_positive(*p, Dimension::Length);
    if (s.contact.stiffness > 0.0 && s.contact.max_penetration > 0.0) {
      c->fail("both \"stiffness\" and \"max_penetration\" given", "one of them");
    }
  }
  if (const auto sv = root.find("solver")) {
    sv->expect_only({"line_search", "max_iterations", "force_tolerance"});
    if (const auto ls = sv->find("line_search")) s.solver.line_search = read_line_search(*ls);
    if (const auto m = sv->find("max_iterations")) s.solver.max_iterations = read_count(*m, 1, 100000);
    if (const auto t = sv->find("force_tolerance")) s.solver.force_tolerance = read_positive(*t, Dimension::Force);
  }
  if (const auto d = root.find("dynamics")) {
    d->expect_only({"time_step", "mass_damping", "stiffness_damping", "max_steps", "settle"});
    s.dynamics.enabled = true;
    if (const auto v = d->find("time_step")) s.dynamics.time_step = read_positive(*v, Dimension::Time);
    if (const auto v = d->find("mass_damping")) s.dynamics.mass_damping = v->as_quantity(Dimension::Frequency);
    if (const auto v = d->find("stiffness_damping")) s.dynamics.stiffness_damping = v->as_quantity(Dimension::Time);
    if (s.dynamics.mass_damping < 0.0 || s.dynamics.stiffness_damping < 0.0) d->fail("damping must be ≥ 0");
    if (const auto v = d->find("max_steps")) {
      const long long n = v->as_integer();
      if (n < 1 || n > 1000000) v->fail(fmt::format("{}", n), "1 to 1000000");
      s.dynamics.max_steps = static_cast<int>(n);
    }
    if (const auto v = d->find("settle")) s.dynamics.settle = read_positive(*v, Dimension::Length);
  }
  if (const auto l = root.find("local")) {
    l->expect_only({"margin"});
    s.local.enabled = true;
    if (const auto m = l->find("margin")) s.local.margin = read_positive(*m, Dimension::Length);
    if (s.obstacles.empty()) l->fail("a local simulation needs an obstacle to be local to");
  }
  if (const auto o = root.find("output")) {
    o->expect_only({"frames_every"});
    if (const auto f = o->find("frames_every")) {
      const long long n = f->as_integer();
      if (n < 0) f->fail(fmt::format("{}", n), "0 (no frames) or a positive number of steps");
      s.frames_every = static_cast<int>(n);
    }
  }
  if (s.fixed.empty() && s.obstacles.empty()) {
    body.fail("the body is neither fixed nor touched by an obstacle: it has no equilibrium",
              "a \"fixed\" set or an obstacle");
  }
  return s;
}

}  // namespace palpa::sim3d
