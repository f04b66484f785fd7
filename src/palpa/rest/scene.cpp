// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/rest/scene.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <fmt/format.h>
#include <set>

#include "palpa/core/json.hpp"
#include "palpa/geometry/format.hpp"
#include "palpa/io/mesh.hpp"
#include "palpa/io/vtu.hpp"
#include "palpa/material/material_file.hpp"
#include "palpa/mesh/bodies.hpp"
#include "palpa/mesh/csg.hpp"
#include "palpa/mesh/surface_check.hpp"
#include "palpa/mesh/layer.hpp"
#include "palpa/sim3d/scene_json.hpp"
#include "palpa/sim3d/shapes.hpp"
#include "palpa/tet/material_field.hpp"

namespace palpa::rest {

using sim3d::read_count;
using sim3d::read_line_search;
using sim3d::read_positive;
using sim3d::read_quantity3;
using sim3d::read_rotation;
using sim3d::resolve_scene_path;

namespace {

namespace fs = std::filesystem;

// An inline material object or the path of a material file.
std::shared_ptr<const material::Material> read_scene_material(const JsonView& mv, const fs::path& file) {
  if (mv.is_object()) return std::shared_ptr<material::Material>(material::material_from_json(mv));
  return std::shared_ptr<material::Material>(
      material::read_material_file(resolve_scene_path(file, mv.as_string())).material);
}

double unit_of(const JsonView& parent) {
  if (const auto u = parent.find("unit")) return parse_unit(u->as_string(), Dimension::Length, u->context());
  return 1.0;
}

}  // namespace

SurfaceMesh read_body_surface(const JsonView& b, const fs::path& file, std::string& source,
                              Eigen::Index* repaired_pairs) {
  SurfaceMesh scan;
  if (const auto surf = b.find("surface")) {
    MeshReadOptions o;
    o.unit_to_si = unit_of(b);
    // A scan in normalized units: a dimensionless factor on top of the unit.
    if (const auto sc = b.find("scale")) {
      const double f = sc->as_number();
      if (!(f >= 1e-6 && f <= 1e6)) sc->fail(fmt::format("a factor of {}", f), "a factor from 1e-6 to 1e6");
      o.unit_to_si *= f;
    }
    scan = read_surface_mesh(resolve_scene_path(file, surf->as_string()), o);
    source = resolve_scene_path(file, surf->as_string()).string();
  } else {
    const JsonView gen = b.at("generate");
    gen.expect_only({"shape", "length", "width", "height"});
    for (const char* k : {"scale", "unit"}) {
      if (b.has(k)) {
        b.at(k).fail("applies to a surface file, not to a generated body",
                     "the generated body's sizes: \"length\", \"width\", \"height\" with their units");
      }
    }
    mesh::BodyOptions o;
    {
      const JsonView shape = gen.at("shape");
      const std::string name = shape.as_string();
      try {
        o.shape = mesh::parse_body_shape(name);
      } catch (const Error& e) {
        shape.fail(e.problem(), e.expected());
      }
    }
    if (const auto v = gen.find("length")) o.size.x() = read_positive(*v, Dimension::Length);
    if (const auto v = gen.find("width")) o.size.y() = read_positive(*v, Dimension::Length);
    if (const auto v = gen.find("height")) o.size.z() = read_positive(*v, Dimension::Length);
    o.edge_length = b.has("edge") ? read_positive(b.at("edge"), Dimension::Length) : 10e-3;
    if (const double smallest = mesh::body_smallest_feature(o); !(o.edge_length <= smallest / 4.0)) {
      const JsonView where = b.has("edge") ? b.at("edge") : gen;
      where.fail(fmt::format("an edge of {} for a {} whose smallest feature is {}",
                             format_quantity(o.edge_length, Dimension::Length), mesh::body_shape_name(o.shape),
                             format_quantity(smallest, Dimension::Length)),
                 "at most a quarter of the smallest feature");
    }
    scan = mesh::make_body(o);
    source = fmt::format("generated {}", gen.at("shape").as_string());
  }
  if (const auto fix = b.find("remove_self_intersections"); fix && fix->as_bool()) {
    scan = mesh::remove_self_intersections(mesh::repair_surface(scan), source,
                                           repaired_pairs);
  }
  if (const auto clip = b.find("clip")) {
    clip->expect_only({"min", "max"});
    const Eigen::AlignedBox3d box(read_quantity3(clip->at("min"), Dimension::Length),
                                  read_quantity3(clip->at("max"), Dimension::Length));
    if (!(box.min().array() < box.max().array()).all()) clip->fail("min is not below max in every coordinate");
    scan = mesh::clip_to_box(mesh::repair_surface(scan), box, source);
  }
  // Boxes cut away (CSG difference): folds and webs outside the region
  // of interest, such as the groin between seated thighs.
  if (const auto cuts = b.find("cut")) {
    for (std::size_t i = 0; i < cuts->size(); ++i) {
      const JsonView c = cuts->at(i);
      c.expect_only({"min", "max"});
      const Eigen::Vector3d lo = read_quantity3(c.at("min"), Dimension::Length);
      const Eigen::Vector3d hi = read_quantity3(c.at("max"), Dimension::Length);
      if (!(lo.array() < hi.array()).all()) c.fail("min is not below max in every coordinate");
      const Eigen::Vector3d body_lo = scan.V.colwise().minCoeff().transpose();
      const Eigen::Vector3d body_hi = scan.V.colwise().maxCoeff().transpose();
      if (!(lo.cwiseMax(body_lo).array() < hi.cwiseMin(body_hi).array()).all()) {
        c.fail(fmt::format("the box does not overlap the body, which spans {} – {}",
                           geometry::format_point(body_lo), geometry::format_point(body_hi)),
               "a box that cuts part of the body away (same unit as the scene)");
      }
      SurfaceMesh cutter = sim3d::make_box_surface(hi - lo, 1);
      cutter.V.rowwise() += Eigen::RowVector3d(0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()), lo.z());
      scan = mesh::boolean(mesh::repair_surface(scan), cutter, mesh::BooleanOp::Difference,
                           source + " (" + c.path() + ")");
    }
  }
  return scan;
}

mesh::LayerOptions read_layer_options(const JsonView& b) {
  mesh::LayerOptions lo;
  lo.edge_length = b.has("edge") ? read_positive(b.at("edge"), Dimension::Length) : 10e-3;
  if (const auto rf = b.find("refine")) {
    rf->expect_only({"edge", "within"});
    mesh::Grading g;
    g.edge = read_positive(rf->at("edge"), Dimension::Length);
    if (!(g.edge < lo.edge_length)) {
      rf->at("edge").fail(fmt::format("{} is not below the body's edge {}", format_quantity(g.edge, Dimension::Length),
                                      format_quantity(lo.edge_length, Dimension::Length)),
                          "a shorter edge than \"edge\" near the support");
    }
    g.within = rf->at("within").as_quantity(Dimension::Length);
    if (!(g.within >= 0.0)) rf->at("within").fail("a negative distance", "a distance ≥ 0 such as \"15 mm\"");
    lo.grading = g;
  }
  if (const auto c = b.find("clamp_depth")) lo.clamp_depth = c->as_bool();
  if (const auto c = b.find("core_offset")) {
    try {
      lo.core_offset = mesh::parse_core_offset(c->as_string());
    } catch (const Error&) {
      c->fail(fmt::format("unknown core offset '{}'", c->as_string()), "normals or distance");
    }
  }
  return lo;
}

double read_body_density(const JsonView& b) {
  const double density = b.has("density") ? b.at("density").as_quantity(Dimension::Density) : 1000.0;
  if (!(density >= 0.0)) b.at("density").fail("must be ≥ 0", "a density such as \"1000 kg/m^3\"");
  return density;
}

namespace {

void read_body(const JsonView& b, const fs::path& file, RestScene& s) {
  b.expect_only({"surface", "layer", "generate", "unit", "scale", "remove_self_intersections", "clip", "cut", "depth",
                 "clamp_depth", "core_offset", "stiffness",
                 "edge", "refine", "material", "density", "position", "rotation", "element", "stabilization"});
  const int sources = int(b.has("surface")) + int(b.has("layer")) + int(b.has("generate"));
  Eigen::VectorXd young;  // per tet [Pa]: the material's shape scaled to it
  if (sources != 1) b.fail("give exactly one of \"surface\", \"layer\", \"generate\"");
  // Placement.
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  if (const auto r = b.find("rotation")) R = read_rotation(*r);
  if (const auto p = b.find("position")) t = read_quantity3(*p, Dimension::Length);
  if (const auto layer = b.find("layer")) {
    for (const char* k : {"scale", "remove_self_intersections", "clip", "cut", "depth", "clamp_depth", "core_offset", "edge",
                          "refine"}) {
      if (b.has(k)) b.at(k).fail("applies to a surface that is meshed here, not to a ready layer", "no such key with \"layer\"");
    }
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
    if (const auto st = b.find("stiffness")) {
      if (!st->is_string() || st->as_string() != "layer") {
        st->fail("with a ready layer, the moduli are the layer's own", "\"layer\" (its cell data youngs_modulus_Pa)");
      }
      const DataArray* E = g.find_cell_data("youngs_modulus_Pa");
      if (E == nullptr || E->values.rows() != m.T.rows()) {
        st->fail(fmt::format("{} has no cell data youngs_modulus_Pa for its tets", p.string()),
                 "a layer written by palpa mesh layer with --stiffness-samples");
      }
      young = E->values.col(0);
      for (Eigen::Index e = 0; e < young.size(); ++e) {
        if (!(std::isfinite(young[e]) && young[e] > 0.0)) {
          st->fail(fmt::format("tet {} of {} has a youngs_modulus_Pa of {}", e, p.string(), young[e]),
                   "a finite modulus > 0 in every tet");
        }
      }
    }
    for (Eigen::Index v = 0; v < att->values.rows(); ++v) {
      if (att->values(v, 0) > 0.5) s.body.attached.push_back(static_cast<int>(v));
    }
    s.body_source = p.string();
  } else {
    SurfaceMesh scan = read_body_surface(b, file, s.body_source, &s.body_repaired_pairs);
    mesh::DepthSpec depth;
    if (const JsonView dv = b.at("depth"); dv.is_object()) {
      dv.expect_only({"samples", "column"});
      const std::string column = dv.has("column") ? dv.at("column").as_string() : "depth";
      depth.samples = mesh::read_samples(resolve_scene_path(file, dv.at("samples").as_string()), column,
                                         Dimension::Length);
    } else {
      depth.uniform = read_positive(dv, Dimension::Length);
    }
    mesh::LayerOptions lo = read_layer_options(b);
    lo.source = s.body_source;
    if (const auto rf = b.find("refine")) {
      // The skin finer toward the support where the body is placed (read
      // before the body: read_rest_scene).
      const mesh::Grading g = *lo.grading;
      lo.contact_distance = [&s, R, t](const Eigen::MatrixX3d& points) {
        const Eigen::MatrixX3d world = ((points * R.transpose()).rowwise() + t.transpose()).eval();
        return mesh::distance_to_surface(s.support, world);
      };
      if (const double nearest = lo.contact_distance(scan.V).minCoeff(); !(nearest < g.within)) {
        rf->at("within").fail(fmt::format("no part of the body is within {} of the support (the nearest is {} away)",
                                          format_quantity(g.within, Dimension::Length),
                                          format_quantity(nearest, Dimension::Length)),
                              "a distance that reaches the support where the body will touch it");
      }
    }
    std::optional<mesh::Samples> stiffness;
    if (const auto st = b.find("stiffness")) {
      if (!st->is_object()) st->fail("not an object", "{\"samples\": \"moduli.csv\", \"column\": \"youngs_modulus\"}");
      st->expect_only({"samples", "column"});
      const std::string column = st->has("column") ? st->at("column").as_string() : "youngs_modulus";
      stiffness = mesh::read_samples(resolve_scene_path(file, st->at("samples").as_string()), column,
                                     Dimension::Pressure);
    }
    const mesh::LayerMesh made = mesh::make_layer(scan, depth, stiffness, lo);
    s.body.mesh = made.tets;
    young = made.youngs_modulus;
    for (Eigen::Index v : made.attached) s.body.attached.push_back(static_cast<int>(v));
    s.body_depth_clamped = made.depth_clamped;
  }
  s.body.mesh.region.resize(0);
  s.body.mesh.V = ((s.body.mesh.V * R.transpose()).rowwise() + t.transpose()).eval();

  tet::BodyMaterial bm;
  bm.material = read_scene_material(b.at("material"), file);
  bm.density = read_body_density(b);
  if (young.size() > 0) {
    tet::MaterialField field = tet::scaled_per_element(bm, young);
    s.body.materials = std::move(field.materials);
    s.body.element_material = std::move(field.element_material);
  } else {
    s.body.materials = {bm};
  }
  s.body.element = sim3d::read_element(b);
}

// A box support with its top face centred at the origin; "bevel" rounds the
// top edge on one side (the knee edge of a block chair, §7.3.2) into a
// quarter cylinder of the given radius.
SurfaceMesh read_box(const JsonView& box) {
  box.expect_only({"size", "divisions", "bevel"});
  const Eigen::Vector3d size = read_quantity3(box.at("size"), Dimension::Length);
  // One count for every axis, or one per axis ([nx, ny, nz]).
  Eigen::Vector3i n = Eigen::Vector3i::Constant(40);
  if (const auto d = box.find("divisions")) {
    if (d->is_array()) {
      if (d->size() != 3) d->fail(fmt::format("{} counts", d->size()), "one count, or three [nx, ny, nz]");
      for (int k = 0; k < 3; ++k) n[k] = static_cast<int>(d->at(static_cast<std::size_t>(k)).as_integer());
    } else {
      n.setConstant(static_cast<int>(d->as_integer()));
    }
    if (n.minCoeff() < 1 || n.maxCoeff() > 1000) d->fail(fmt::format("{} {} {}", n[0], n[1], n[2]), "1 to 1000");
    // Two triangles per face cell; a support beyond that is no support a
    // contact solve gets through.
    constexpr double kMaxBoxTriangles = 2e6;
    const double triangles = 4.0 * (double(n[0]) * n[1] + double(n[1]) * n[2] + double(n[2]) * n[0]);
    if (triangles > kMaxBoxTriangles) {
      d->fail(fmt::format("{} × {} × {} divisions, {:.3g} triangles", n[0], n[1], n[2], triangles),
              fmt::format("at most {:.0f} triangles (about 400 divisions a side)", kMaxBoxTriangles));
    }
  }
  SurfaceMesh m = sim3d::make_box_surface(size, n);
  m.V.col(2).array() -= size.z();  // the top face at the origin
  if (const auto bevel = box.find("bevel")) {
    bevel->expect_only({"radius", "side"});
    const double r = read_positive(bevel->at("radius"), Dimension::Length);
    const std::string side = bevel->has("side") ? bevel->at("side").as_string() : "+x";
    int axis = 0;
    double sign = 1.0;
    if (side == "+x" || side == "-x" || side == "+y" || side == "-y") {
      axis = side[1] == 'x' ? 0 : 1;
      sign = side[0] == '+' ? 1.0 : -1.0;
    } else {
      bevel->at("side").fail(fmt::format("unknown side '{}'", side), "+x, -x, +y or -y");
    }
    const double half = 0.5 * size(axis);
    if (r > half || r > size.z()) {
      bevel->at("radius").fail("larger than the box", "a radius below half the box's length and its height");
    }
    // Points of the square beyond the arc's centre move along the direction
    // from the centre so that the square's outer sides (the top and front
    // faces) land on the arc and the end faces' points inside the quarter
    // disc: a monotone map, so the mesh stays valid.
    const double cu = half - r;  // along sign·axis
    const double cz = -r;
    for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
      const double u = sign * m.V(i, axis) - cu;
      const double w = m.V(i, 2) - cz;
      if (u <= 0.0 || w <= 0.0) continue;
      const double f = std::max(u, w) / std::hypot(u, w);
      m.V(i, axis) = sign * (cu + f * u);
      m.V(i, 2) = cz + f * w;
    }
  }
  return m;
}

}  // namespace

void read_scene_support(const JsonView& sp, const fs::path& file, RestScene& s) {
  sp.expect_only(
      {"box", "spheres", "level", "smoothing", "negative_image", "file", "unit", "position", "rotation", "deformable"});
  SurfaceMesh m;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  if (const auto r = sp.find("rotation")) R = read_rotation(*r);
  if (const auto p = sp.find("position")) t = read_quantity3(*p, Dimension::Length);
  const auto place = [&](SurfaceMesh& mesh) { mesh.V = ((mesh.V * R.transpose()).rowwise() + t.transpose()).eval(); };
  const std::string name = file.filename().string();
  if (const auto box = sp.find("box")) {
    m = read_box(*box);
    s.support_source = box->has("bevel") ? "bevelled box" : "box";
    place(m);
  } else if (const auto spheres = sp.find("spheres")) {
    const int level = sp.has("level") ? read_count(sp.at("level"), 1, 7) : 3;
    double first_edge = 0.0;
    for (std::size_t i = 0; i < spheres->size(); ++i) {
      const JsonView si = spheres->at(i);
      si.expect_only({"centre", "radius"});
      const double r = read_positive(si.at("radius"), Dimension::Length);
      SurfaceMesh ball = sim3d::make_sphere(r, level);
      if (i == 0) first_edge = mesh::mean_edge_length(ball);
      ball.V.col(2).array() -= r;
      ball.V.rowwise() += read_quantity3(si.at("centre"), Dimension::Length).transpose();
      // Overlapping spheres are joined into one solid (CSG union).
      m = i == 0 ? ball : mesh::boolean(m, ball, mesh::BooleanOp::Union, name + ": support.spheres");
    }
    if (m.V.rows() == 0) spheres->fail("no sphere given", "at least one {\"centre\", \"radius\"}");
    // The union's seam is cut into slivers: remesh at the spheres' own edge
    // length before smoothing it (§7.3.2: CSG union, then Taubin smoothing).
    if (spheres->size() > 1) m = mesh::remesh_surface(m, first_edge);
    if (const auto sm = sp.find("smoothing")) mesh::taubin_smooth(m, read_count(*sm, 0, 1000));
    s.support_source = fmt::format("{} sphere(s)", spheres->size());
    place(m);
  } else if (const auto neg = sp.find("negative_image")) {
    // The block with the body, as placed, pressed into it (§7.5.1); the
    // body then starts in the hollow, `clearance` clear of it.
    neg->expect_only({"box", "support", "press", "edge", "smoothing", "band", "clearance"});
    if (neg->has("box") == neg->has("support")) {
      neg->fail("give either box or support", "a box, or any closed support (spheres, a file) to hollow");
    }
    SurfaceMesh block;
    std::string of = "a box";
    if (const auto b = neg->find("box")) {
      block = read_box(*b);
    } else {
      // Any other support shape is hollowed the same way (a mouse's spheres).
      const JsonView inner = neg->at("support");
      for (const char* key : {"negative_image", "deformable"}) {
        if (const auto k = inner.find(key)) {
          k->fail(fmt::format("\"{}\" inside a negative image", key),
                  "a box, spheres or a file (\"deformable\" goes beside \"negative_image\")");
        }
      }
      RestScene shape;
      read_scene_support(inner, file, shape);
      block = std::move(shape.support);
      of = shape.support_source;
    }
    place(block);
    mesh::NegativeImageOptions o;
    const double g = s.options.gravity.norm();
    if (g > 0.0) o.down = s.options.gravity / g;
    if (const auto v = neg->find("press")) o.press = read_positive(*v, Dimension::Length);
    if (const auto v = neg->find("edge")) o.edge_length = read_positive(*v, Dimension::Length);
    if (const auto v = neg->find("smoothing")) o.smoothing_rounds = read_count(*v, 0, 1000);
    if (const auto v = neg->find("band")) o.smoothing_band = read_positive(*v, Dimension::Length);
    if (const auto v = neg->find("clearance")) o.clearance = read_positive(*v, Dimension::Length);
    const SurfaceMesh skin = body_skin(s.body);
    const mesh::NegativeImage made = mesh::negative_image(block, skin, o, name + ": support.negative_image");
    m = made.support;
    s.body.mesh.V.rowwise() += made.body_shift.transpose();
    s.body_shift += made.body_shift;
    s.support_source = fmt::format("negative image of the body pressed {} into {}",
                                   format_quantity(o.press, Dimension::Length), of);
  } else if (const auto f = sp.find("file")) {
    MeshReadOptions o;
    o.unit_to_si = unit_of(sp);
    m = read_surface_mesh(resolve_scene_path(file, f->as_string()), o);
    s.support_source = resolve_scene_path(file, f->as_string()).string();
    place(m);
  } else {
    sp.fail("no support shape", "\"box\", \"spheres\", \"negative_image\" or \"file\"");
  }
  s.support = m;
  if (const auto d = sp.find("deformable")) {
    // A foam or gel support (§7.4.3): its inside meshed with tets, its base held.
    d->expect_only({"material", "edge", "base_tolerance"});
    DeformableSupport ds;
    ds.material = read_scene_material(d->at("material"), file);
    if (const auto v = d->find("edge")) ds.edge = read_positive(*v, Dimension::Length);
    if (const auto v = d->find("base_tolerance")) {
      ds.base_tolerance = v->as_quantity(Dimension::Length);
      if (!(ds.base_tolerance >= 0.0)) v->fail("a negative height", "a height ≥ 0 such as \"1 mm\"");
    }
    s.options.deformable_support = ds;
    s.support_source += ", deformable";
  } else {
    s.options.deformable_support.reset();
  }
}

RestScene read_rest_scene(const fs::path& path, const std::string& version_key,
                          const std::vector<std::string>& extra_keys) {
  return read_rest_scene(read_json_file(path), path, version_key, extra_keys);
}

RestScene read_rest_scene(const Json& doc, const fs::path& path, const std::string& version_key,
                          const std::vector<std::string>& extra_keys) {
  const JsonView root(doc, path.string());
  if (!doc.is_object()) root.fail("is not a JSON object", "a scene object");
  std::vector<std::string> keys{version_key, "body", "core", "support", "gravity", "contact", "solver", "template"};
  keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
  root.expect_only(keys);
  if (root.at(version_key).as_integer() != 1) root.at(version_key).fail("unsupported version", "1");
  RestScene s;
  s.file = path;
  RestOptions& o = s.options;
  if (const auto g = root.find("gravity")) o.gravity = read_quantity3(*g, Dimension::Acceleration);
  // A body refined toward its support is meshed after it; a negative image is
  // made from the body, after it.
  const JsonView body_json = root.at("body"), support_json = root.at("support");
  if (const auto rf = body_json.find("refine")) {
    if (support_json.has("negative_image")) {
      rf->fail("a negative image is made from the body, so the body cannot be refined toward it",
               "a box, spheres or a file support (or no \"refine\")");
    }
    read_scene_support(support_json, path, s);
    read_body(body_json, path, s);
  } else {
    read_body(body_json, path, s);
    read_scene_support(support_json, path, s);
  }
  if (const auto t = root.find("template")) {
    t->expect_only({"grid", "unit", "pixel", "title"});
    TemplateSpec spec;
    spec.file = resolve_scene_path(path, t->at("grid").as_string());
    const std::string unit = t->has("unit") ? t->at("unit").as_string() : "Pa";
    const double to_pa = parse_unit(unit, Dimension::Pressure, t->has("unit") ? t->at("unit").context() : t->context());
    spec.grid = report::read_pressure_grid(spec.file, read_positive(t->at("pixel"), Dimension::Length), to_pa);
    spec.title = t->has("title") ? t->at("title").as_string() : spec.file.filename().string();
    s.reference_map = std::move(spec);
  }
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
  if (const auto c = root.find("contact")) {
    c->expect_only({"stiffness", "max_penetration", "sampling", "subdivisions"});
    if (const auto sm = c->find("sampling")) o.sampling = sim3d::read_contact_sampling(*sm);
    if (const auto n = c->find("subdivisions")) o.subdivisions = sim3d::read_count(*n, 1, 8);
    if (const auto k = c->find("stiffness")) {
      o.stiffness = read_positive(*k, o.sampling == body::ContactSampling::Surface ? Dimension::PressurePerLength
                                                                                    : Dimension::Stiffness);
    }
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
