#include "palpa/rest/scene.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <fmt/format.h>
#include <set>

#include "palpa/core/json.hpp"
#include "palpa/io/vtu.hpp"
#include "palpa/material/material_file.hpp"
#include "palpa/mesh/bodies.hpp"
#include "palpa/mesh/layer.hpp"
#include "palpa/sim3d/scene_json.hpp"
#include "palpa/sim3d/shapes.hpp"

namespace palpa::rest {

using sim3d::read_count;
using sim3d::read_line_search;
using sim3d::read_positive;
using sim3d::read_quantity3;
using sim3d::read_rotation;
using sim3d::resolve_scene_path;

namespace {

namespace fs = std::filesystem;

double unit_of(const JsonView& parent) {
  if (const auto u = parent.find("unit")) return parse_quantity("1 " + u->as_string(), Dimension::Length, u->context());
  return 1.0;
}

SurfaceMesh append(const SurfaceMesh& a, const SurfaceMesh& b) {
  SurfaceMesh m;
  m.V.resize(a.V.rows() + b.V.rows(), 3);
  m.V << a.V, b.V;
  m.F.resize(a.F.rows() + b.F.rows(), 3);
  m.F << a.F, (b.F.array() + static_cast<int>(a.V.rows())).matrix();
  return m;
}

void read_body(const JsonView& b, const fs::path& file, RestScene& s) {
  b.expect_only({"surface", "layer", "generate", "unit", "depth", "edge", "material", "density", "position", "rotation"});
  const int sources = int(b.has("surface")) + int(b.has("layer")) + int(b.has("generate"));
  if (sources != 1) b.fail("give exactly one of \"surface\", \"layer\", \"generate\"");
  if (const auto layer = b.find("layer")) {
    const fs::path p = resolve_scene_path(file, layer->as_string());
    const UnstructuredGrid g = read_vtu(p);
    const double unit = unit_of(b);
    const DataArray* att = g.find_point_data("attached");
    if (att == nullptr) layer->fail("the mesh has no point data \"attached\"", "a layer written by palpa mesh layer");
    TetMesh m;
    m.V = g.points * unit;
    for (const CellBlock& c : g.cells) {
      if (c.type == VtkCellType::Tetra) m.T = c.nodes;
    }
    if (m.T.rows() == 0) layer->fail("the mesh has no tetrahedra", "a tet layer");
    s.body.mesh = m;
    for (Eigen::Index v = 0; v < att->values.rows(); ++v) {
      if (att->values(v, 0) > 0.5) s.body.attached.push_back(static_cast<int>(v));
    }
    s.body_source = p.string();
  } else {
    SurfaceMesh scan;
    if (const auto surf = b.find("surface")) {
      MeshReadOptions o;
      o.unit_to_si = unit_of(b);
      scan = read_surface_mesh(resolve_scene_path(file, surf->as_string()), o);
      s.body_source = resolve_scene_path(file, surf->as_string()).string();
    } else {
      const JsonView gen = b.at("generate");
      gen.expect_only({"shape", "length", "width", "height"});
      mesh::BodyOptions o;
      o.shape = mesh::parse_body_shape(gen.at("shape").as_string());
      if (const auto v = gen.find("length")) o.size.x() = read_positive(*v, Dimension::Length);
      if (const auto v = gen.find("width")) o.size.y() = read_positive(*v, Dimension::Length);
      if (const auto v = gen.find("height")) o.size.z() = read_positive(*v, Dimension::Length);
      o.edge_length = b.has("edge") ? read_positive(b.at("edge"), Dimension::Length) : 10e-3;
      scan = mesh::make_body(o);
      s.body_source = fmt::format("generated {}", gen.at("shape").as_string());
    }
    mesh::DepthSpec depth;
    depth.uniform = read_positive(b.at("depth"), Dimension::Length);
    mesh::LayerOptions lo;
    lo.edge_length = b.has("edge") ? read_positive(b.at("edge"), Dimension::Length) : 10e-3;
    lo.source = s.body_source;
    const mesh::LayerMesh made = mesh::make_layer(scan, depth, std::nullopt, lo);
    s.body.mesh = made.tets;
    for (Eigen::Index v : made.attached) s.body.attached.push_back(static_cast<int>(v));
  }
  s.body.mesh.region.resize(0);
  // Placement.
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  if (const auto r = b.find("rotation")) R = read_rotation(*r);
  if (const auto p = b.find("position")) t = read_quantity3(*p, Dimension::Length);
  s.body.mesh.V = ((s.body.mesh.V * R.transpose()).rowwise() + t.transpose()).eval();

  tet::BodyMaterial bm;
  const JsonView mv = b.at("material");
  bm.material = mv.is_object() ? std::shared_ptr<material::Material>(material::material_from_json(mv))
                               : std::shared_ptr<material::Material>(material::read_material_file(resolve_scene_path(file, mv.as_string())).material);
  bm.density = b.has("density") ? b.at("density").as_quantity(Dimension::Density) : 1000.0;
  if (!(bm.density >= 0.0)) b.at("density").fail("must be ≥ 0", "a density such as \"1000 kg/m^3\"");
  s.body.materials = {bm};
}

void read_support(const JsonView& sp, const fs::path& file, RestScene& s) {
  sp.expect_only({"box", "spheres", "level", "file", "unit", "position", "rotation"});
  SurfaceMesh m;
  if (const auto box = sp.find("box")) {
    box->expect_only({"size", "divisions"});
    const Eigen::Vector3d size = read_quantity3(box->at("size"), Dimension::Length);
    const int n = box->has("divisions") ? static_cast<int>(box->at("divisions").as_integer()) : 40;
    if (n < 1 || n > 1000) box->at("divisions").fail(fmt::format("{}", n), "1 to 1000");
    m = sim3d::make_box_surface(size, n);
    m.V.col(2).array() -= size.z();  // the top face at the origin
    s.support_source = "box";
  } else if (const auto spheres = sp.find("spheres")) {
    const int level = sp.has("level") ? static_cast<int>(sp.at("level").as_integer()) : 3;
    for (std::size_t i = 0; i < spheres->size(); ++i) {
      const JsonView si = spheres->at(i);
      si.expect_only({"centre", "radius"});
      const double r = read_positive(si.at("radius"), Dimension::Length);
      SurfaceMesh ball = sim3d::make_sphere(r, level);
      ball.V.col(2).array() -= r;
      ball.V.rowwise() += read_quantity3(si.at("centre"), Dimension::Length).transpose();
      m = i == 0 ? ball : append(m, ball);
    }
    if (m.V.rows() == 0) spheres->fail("no sphere given", "at least one {\"centre\", \"radius\"}");
    s.support_source = fmt::format("{} sphere(s)", spheres->size());
  } else if (const auto f = sp.find("file")) {
    MeshReadOptions o;
    o.unit_to_si = unit_of(sp);
    m = read_surface_mesh(resolve_scene_path(file, f->as_string()), o);
    s.support_source = resolve_scene_path(file, f->as_string()).string();
  } else {
    sp.fail("no support shape", "\"box\", \"spheres\" or \"file\"");
  }
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  if (const auto r = sp.find("rotation")) R = read_rotation(*r);
  if (const auto p = sp.find("position")) t = read_quantity3(*p, Dimension::Length);
  m.V = ((m.V * R.transpose()).rowwise() + t.transpose()).eval();
  s.support = m;
}

}  // namespace

RestScene read_rest_scene(const fs::path& path) {
  const Json doc = read_json_file(path);
  const JsonView root(doc, path.string());
  root.expect_only({"palpa_rest", "body", "core", "support", "gravity", "contact", "solver"});
  if (root.at("palpa_rest").as_integer() != 1) root.at("palpa_rest").fail("unsupported version", "1");
  RestScene s;
  s.file = path;
  read_body(root.at("body"), path, s);
  read_support(root.at("support"), path, s);
  RestOptions& o = s.options;
  o.support_name = fmt::format("{}: support", path.filename().string());
  if (const auto core = root.find("core")) {
    core->expect_only({"mass", "free", "force", "torque", "centre"});
    if (const auto m = core->find("mass")) o.core.mass = m->as_quantity(Dimension::Mass);
    if (o.core.mass < 0.0) core->at("mass").fail("must be ≥ 0");
    o.core.locked = {true, true, true, true, true, true};
    if (const auto free = core->find("free")) {
      static const char* kNames[6] = {"x", "y", "z", "rx", "ry", "rz"};
      for (std::size_t i = 0; i < free->size(); ++i) {
        const std::string n = free->at(i).as_string();
        bool known = false;
        for (int k = 0; k < 6; ++k) {
          if (n == kNames[k]) {
            o.core.locked[static_cast<std::size_t>(k)] = false;
            known = true;
          }
        }
        if (!known) free->at(i).fail(fmt::format("unknown DOF '{}'", n), "x, y, z, rx, ry or rz");
      }
    } else {
      o.core.locked[2] = false;  // vertical only
    }
    if (const auto f = core->find("force")) o.core.force = read_quantity3(*f, Dimension::Force);
    if (const auto t = core->find("torque")) o.core.torque = read_quantity3(*t, Dimension::Torque);
    if (const auto c = core->find("centre")) {
      o.core.centre = read_quantity3(*c, Dimension::Length);
      o.core_centre_given = true;
    }
  } else {
    o.core.locked = {true, true, false, true, true, true};
  }
  if (std::all_of(o.core.locked.begin(), o.core.locked.end(), [](bool b) { return b; })) {
    root.at("core").at("free").fail("every core DOF is locked: the body cannot come to rest on anything",
                                    "at least one of x, y, z, rx, ry, rz");
  }
  if (const auto g = root.find("gravity")) o.gravity = read_quantity3(*g, Dimension::Acceleration);
  if (const auto c = root.find("contact")) {
    c->expect_only({"stiffness", "max_penetration"});
    if (const auto k = c->find("stiffness")) o.stiffness = read_positive(*k, Dimension::Stiffness);
    if (const auto p = c->find("max_penetration")) o.target_penetration = read_positive(*p, Dimension::Length);
  }
  if (const auto sv = root.find("solver")) {
    sv->expect_only({"line_search", "max_iterations"});
    if (const auto ls = sv->find("line_search")) o.line_search = read_line_search(*ls);
    if (const auto m = sv->find("max_iterations")) o.max_iterations = read_count(*m, 1, 100000);
  }
  return s;
}

}  // namespace palpa::rest
