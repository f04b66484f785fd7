// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/design/scene.hpp"

#include <Eigen/Geometry>
#include <cctype>
#include <cmath>
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <limits>
#include <map>
#include <optional>

#include "palpa/core/error.hpp"
#include "palpa/core/json.hpp"
#include "palpa/design/cohort.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/sim3d/scene_json.hpp"

namespace palpa::design {

std::vector<int> facing_vertices(const SurfaceMesh& support, const Eigen::Vector3d& up, double angle,
                                 const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::MatrixX3d N = geometry::vertex_normals(support, geometry::NormalWeighting::Area);
  double six_volume = 0.0;
  for (Eigen::Index f = 0; f < support.F.rows(); ++f) {
    const Eigen::Vector3d a = support.V.row(support.F(f, 0)), b = support.V.row(support.F(f, 1)),
                          c = support.V.row(support.F(f, 2));
    six_volume += a.dot(b.cross(c));
  }
  const double sign = six_volume < 0.0 ? -1.0 : 1.0;
  const Eigen::Vector3d u = up.normalized();
  const double cos_max = std::cos(angle);
  std::vector<int> out;
  for (Eigen::Index v = 0; v < support.V.rows(); ++v) {
    if (!(N.row(v).squaredNorm() > 0.0)) continue;
    const Eigen::Vector3d x = support.V.row(v).transpose();
    if ((x.array() < lo.array()).any() || (x.array() > hi.array()).any()) continue;
    if (sign * N.row(v).dot(u) >= cos_max - 1e-12) out.push_back(static_cast<int>(v));
  }
  return out;
}

void begin_on_start(DesignScene& s, const rest::RestBody& body, const SurfaceMesh& support, const std::string& source) {
  s.rest.body = body;
  s.rest.support = support;
  s.rest.support_source = source;
  s.rest.options.support_name =
      fmt::format("{}: the baseline '{}' the design starts from", s.rest.file.filename().string(), s.start);
  // Placed as the baseline's own score places it (ShapeOptimizer::
  // solve_from_scratch): lifted clear where a skin vertex starts inside.
  s.start_lift = rest::place_clear_of(s.rest.body, s.rest.support, -s.rest.options.gravity, 1e-3);
  if (s.start_lift > 0.0) {
    spdlog::info("design: the body starts inside the baseline '{}': lifted {:.3g} mm before it is lowered onto it",
                 s.start, s.start_lift * 1e3);
  }
}

std::string baseline_slug(const std::string& name) {
  std::string slug;
  for (char ch : name) slug += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
  return slug;
}

DesignScene read_design_scene(const std::filesystem::path& path, bool baselines) {
  return read_design_scene(read_json_file(path), path, baselines);
}

namespace {

CohortObjective read_cohort_objective(const JsonView& c) {
  c.expect_only({"objective", "quantile", "sharpness", "single_designs", "baseline", "start"});
  CohortObjective o;
  if (const auto a = c.find("objective")) {
    const std::string name = a->as_string();
    try {
      o.aggregate = parse_cohort_aggregate(name, "cohort.objective");
    } catch (const Error&) {
      a->fail(fmt::format("unknown cohort objective '{}'", name), "\"mean\", \"quantile\" or \"max\"");
    }
  }
  if (const auto q = c.find("quantile")) {
    if (o.aggregate != CohortAggregate::Quantile) q->fail("a quantile for another objective", "\"objective\": \"quantile\"");
    o.quantile = q->as_number();
    if (!(o.quantile >= 0.0 && o.quantile < 1.0)) q->fail("out of range", "a fraction in [0, 1)");
  }
  if (const auto t = c.find("sharpness")) {
    if (o.aggregate != CohortAggregate::SmoothMax) t->fail("a sharpness for another objective", "\"objective\": \"max\"");
    o.sharpness = t->as_number();
    if (!(o.sharpness > 0.0 && o.sharpness <= 10.0)) t->fail("out of range", "τ in (0, 10] (of the scores normalized to 1)");
  }
  return o;
}

// A cohort scene: each body read as a one-body scene of its own (its body and
// core, the cohort's everything else), on one support.
DesignScene read_cohort_scene(const Json& doc, const std::filesystem::path& path) {
  const JsonView root(doc, path.string());
  if (const auto b = root.find("body")) b->fail("a body beside \"bodies\"", "every body of the cohort in \"bodies\"");
  if (const auto b = root.find("baselines")) {
    b->fail("baselines in a cohort scene", "none: a cohort's support is compared body by body with the flat start");
  }
  if (const auto d = root.find("design")) {
    if (const auto st = d->find("start")) st->fail("a start baseline in a cohort scene", "none: a cohort starts from the scene's support");
  }
  const JsonView list = root.at("bodies");
  if (list.size() == 0) list.fail("no body", "at least one body");
  Json base = doc;
  base.erase("bodies");
  base.erase("cohort");
  DesignScene s;
  std::map<std::string, std::string> slugs;  // file-name form -> the first name that has it
  for (std::size_t i = 0; i < list.size(); ++i) {
    const JsonView e = list.at(i);
    e.expect_only({"name", "scene", "body", "core"});
    const JsonView n = e.at("name");
    const std::string name = n.as_string();
    if (name.empty()) n.fail("an empty name", "a name for the body's files and the summary");
    if (const auto [at, fresh] = slugs.emplace(baseline_slug(name), name); !fresh) {
      n.fail(at->second == name ? fmt::format("a second body named '{}'", name)
                                : fmt::format("'{}' and the body '{}' would write the same files (bodies/{}/)", name,
                                              at->second, at->first),
             "body names that differ in a letter or digit");
    }
    if (e.has("scene") == e.has("body")) e.fail("give either scene or body", "one of them");
    Json member = base;
    std::string source = "inline";
    if (const auto sc = e.find("scene")) {
      const std::filesystem::path file = sim3d::resolve_scene_path(path, sc->as_string());
      const Json other = read_json_file(file);
      const JsonView ov(other, file.string());
      if (!ov.is_object()) ov.fail("is not a JSON object", "a scene object with a \"body\"");
      Json body = ov.at("body").json();
      sim3d::absolutize_scene_paths(body, file);
      member["body"] = body;
      if (ov.has("core")) member["core"] = ov.at("core").json();
      source = file.string();
    } else {
      member["body"] = e.at("body").json();
    }
    if (const auto c = e.find("core")) member["core"] = c->json();
    DesignScene m;
    try {
      m = read_design_scene(member, path, false);
    } catch (const Error& err) {
      if (err.kind() != ErrorKind::Input) throw;
      throw Error(ErrorKind::Input, fmt::format("the cohort's body '{}' ({}): {}", name,
                                                source == "inline" ? "bodies[" + std::to_string(i) + "]" : source,
                                                err.what()));
    }
    if (i == 0) {
      s.rest = m.rest;
      s.design_vertices = m.design_vertices;
      s.options = m.options;
      s.region = m.region;
    } else if (m.rest.support.V != s.rest.support.V || m.rest.support.F != s.rest.support.F) {
      e.fail(fmt::format("a support that differs from the first body's ('{}')", s.cohort.front().name),
             "one support for every body (not one made from the body, such as a negative image)");
    }
    s.cohort.push_back(CohortMember{name, std::move(m.rest), source});
  }
  s.options.cohort = root.has("cohort") ? read_cohort_objective(root.at("cohort")) : CohortObjective{};
  if (const auto c = root.find("cohort")) {
    if (const auto sd = c->find("single_designs")) s.single_designs = sd->as_bool();
  }
  s.cohort_baseline = AverageImpressionOptions{};
  if (const auto c = root.find("cohort")) {
    if (const auto b = c->find("baseline")) {
      if (b->json().is_boolean()) {
        if (!b->as_bool()) s.cohort_baseline.reset();
      } else {
        b->expect_only({"press", "smoothing"});
        if (const auto p = b->find("press")) s.cohort_baseline->press = sim3d::read_positive(*p, Dimension::Length);
        if (const auto r = b->find("smoothing")) s.cohort_baseline->smoothing_rounds = sim3d::read_count(*r, 0, 1000);
      }
    }
    if (const auto st = c->find("start")) {
      const std::string where = st->as_string();
      if (where == "baseline") {
        if (!s.cohort_baseline) st->fail("a start on the baseline with \"baseline\": false", "a baseline to start on");
        s.cohort_start_on_baseline = true;
      } else if (where != "scene") {
        st->fail(fmt::format("unknown start '{}'", where), "\"scene\" (its support) or \"baseline\"");
      }
    }
  }
  return s;
}

}  // namespace

DesignScene read_design_scene(const Json& doc, const std::filesystem::path& path, bool baselines) {
  if (doc.is_object() && doc.contains("bodies")) return read_cohort_scene(doc, path);
  if (doc.is_object() && doc.contains("cohort")) {
    JsonView(doc, path.string()).at("cohort").fail("a cohort objective for one body", "\"bodies\": the cohort's bodies");
  }
  DesignScene s;
  s.rest = rest::read_rest_scene(doc, path, "palpa_design", {"design", "baselines"});
  const JsonView root(doc, path.string());
  if (const auto t = root.find("template")) t->fail("a template is compared by palpa rest", "no \"template\" in a design");
  // The baseline the design starts from is built even without the others.
  std::string start;
  std::optional<JsonView> start_field;
  if (const auto d = root.find("design")) {
    if (const auto st = d->find("start")) {
      start = st->as_string();
      start_field = st;
      if (start.empty()) st->fail("an empty start", "the name of one of the scene's baselines (or no \"start\")");
    }
  }
  // An unknown start is refused before any baseline is built (minutes at full size).
  if (start_field) {
    bool named = false;
    if (const auto bl = root.find("baselines")) {
      for (std::size_t i = 0; i < bl->size(); ++i) {
        const Json& b = bl->at(i).json();
        named |= b.is_object() && b.contains("name") && b["name"].is_string() && b["name"] == start;
      }
    }
    if (!named) start_field->fail(fmt::format("no baseline named '{}'", start), "the name of one of the scene's baselines");
  }
  std::optional<Baseline> start_base;
  if (const auto bl = root.find("baselines")) {
    std::map<std::string, std::string> slugs;  // file-name form -> the first name that has it
    for (std::size_t i = 0; i < bl->size(); ++i) {
      const JsonView b = bl->at(i);
      b.expect_only({"name", "support", "sit_and_relax"});
      if (b.has("support") == b.has("sit_and_relax")) b.fail("give either support or sit_and_relax", "one of them");
      {
        const JsonView n = b.at("name");
        const std::string name = n.as_string();
        if (name.empty()) n.fail("an empty name", "a name for the baseline's files and the summary");
        const auto [at, fresh] = slugs.emplace(baseline_slug(name), name);
        if (!fresh) {
          n.fail(at->second == name
                     ? fmt::format("a second baseline named '{}'", name)
                     : fmt::format("'{}' and the baseline '{}' would write the same files (baseline_{}_*)", name,
                                   at->second, at->first),
                 "baseline names that differ in a letter or digit");
        }
      }
      // The body as placed in the scene, before the design's own support
      // moved it.
      rest::RestScene copy = s.rest;
      copy.body.mesh.V.rowwise() -= copy.body_shift.transpose();
      copy.body_shift.setZero();
      Baseline base;
      base.name = b.at("name").as_string();
      const bool is_start = !start.empty() && base.name == start;
      const bool build = baselines || is_start;
      for (const char* key : {"support", "sit_and_relax"}) {
        const auto part = b.find(key);
        if (!part) continue;
        const auto sp = std::string(key) == "support" ? part : part->find("support");
        if (sp && sp->has("deformable")) {
          sp->at("deformable").fail("a material of its own",
                                    "nothing: baselines are made of the scene's support (give \"deformable\" there)");
        }
      }
      if (const auto sr = b.find("sit_and_relax")) {
        sr->expect_only({"support", "smoothness"});
        if (build) rest::read_scene_support(sr->at("support"), path, copy);
        base.sit_and_relax = true;
        if (const auto l = sr->find("smoothness")) {
          base.smoothness = l->as_number();
          if (!(base.smoothness >= 0.0)) l->fail("must be ≥ 0");
        }
      } else if (build) {
        rest::read_scene_support(b.at("support"), path, copy);
      }
      if (!build) continue;
      base.body = copy.body;
      base.support = copy.support;
      base.source = copy.support_source;
      if (is_start) start_base = base;
      if (baselines) s.baselines.push_back(std::move(base));
    }
  }
  if (!start.empty()) {
    if (!start_base) start_field->fail(fmt::format("no baseline named '{}'", start), "the name of one of the scene's baselines");
    // The design begins on that support; the scene's own is scored beside.
    s.start = start;
    s.scene_support = SceneSupport{s.rest.body, s.rest.support, s.rest.support_source};
  }
  if (start_base && start_base->sit_and_relax) {
    // Fitted on the scene's support once the equilibria are solved.
    s.start_to_fit = std::move(start_base);
  } else if (start_base) {
    begin_on_start(s, start_base->body, start_base->support, start_base->source);
  }
  DesignOptions& o = s.options;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  double facing = 25.0 * 3.14159265358979323846 / 180.0;
  if (const auto d = root.find("design")) {
    d->expect_only({"method", "region", "facing", "direction", "exponent", "pressure_smoothing", "smoothing", "iterations", "min_decrease", "moves", "filter",
                    "threads", "post_smoothing", "pose_to_seat_threshold", "start"});
    if (const auto m = d->find("method")) {
      const std::string v = m->as_string();
      if (v == "cg") {
        o.method = DesignMethod::ConjugateGradient;
      } else if (v == "lbfgs") {
        o.method = DesignMethod::Lbfgs;
      } else {
        m->fail(fmt::format("unknown method '{}'", v), "cg (nonlinear conjugate gradients) or lbfgs");
      }
    }
    if (const auto r = d->find("region")) {
      r->expect_only({"min", "max"});
      lo = sim3d::read_quantity3(r->at("min"), Dimension::Length);
      hi = sim3d::read_quantity3(r->at("max"), Dimension::Length);
      if ((lo.array() >= hi.array()).any()) r->fail("min must lie below max on every axis");
    }
    if (const auto f = d->find("facing")) {
      facing = f->as_quantity(Dimension::Angle);
      if (!(facing > 0.0 && facing <= 3.14159265358979323846)) f->fail("out of range", "an angle in (0, 180] deg");
    }
    if (const auto dir = d->find("direction")) {
      const std::string v = dir->as_string();
      if (v == "normal") {
        o.normal_only = true;
      } else if (v == "free") {
        o.normal_only = false;
      } else {
        dir->fail(fmt::format("unknown direction '{}'", v), "normal or free");
      }
    }
    if (const auto e = d->find("exponent")) o.score.exponent = sim3d::read_count(*e, 2, 4);
    if (const auto l = d->find("pressure_smoothing")) {
      o.score.pressure_smoothing = l->as_number();
      if (!(o.score.pressure_smoothing >= 0.0 && o.score.pressure_smoothing <= 1.0)) {
        l->fail("out of range", "a weight in [0, 1] (½: one Laplacian step, the thesis's; 0: the pressures as they are)");
      }
    }
    if (const auto sm = d->find("smoothing")) {
      sm->expect_only({"exponent", "gamma", "iterations"});
      if (sm->has("exponent") && sm->has("gamma")) sm->fail("give either exponent or gamma", "one of them");
      if (const auto j = sm->find("exponent")) {
        o.smoothing_exponent = j->as_number();
        if (std::abs(o.smoothing_exponent) > 30.0) j->fail("out of range", "a power of ten within ±30");
      }
      if (const auto g = sm->find("gamma")) {
        const double v = g->as_number();
        if (!(v >= 0.0)) g->fail("must be ≥ 0");
        o.gamma = v;
      }
      if (const auto m = sm->find("iterations")) o.taubin_iterations = sim3d::read_count(*m, 1, 100);
    }
    if (const auto it = d->find("iterations")) o.max_iterations = sim3d::read_count(*it, 0, 100000);
    if (const auto m = d->find("min_decrease")) {
      o.min_relative_decrease = m->as_number();
      if (!(o.min_relative_decrease >= 0.0 && o.min_relative_decrease < 1.0)) m->fail("out of range", "a fraction in [0, 1)");
    }
    if (const auto mv = d->find("moves")) {
      o.moves.clear();
      for (std::size_t i = 0; i < mv->size(); ++i) o.moves.push_back(sim3d::read_positive(mv->at(i), Dimension::Length));
      if (o.moves.empty()) mv->fail("no step lengths", "at least one length");
    }
    if (const auto f = d->find("filter")) {
      o.filter_radius = f->as_quantity(Dimension::Length);
      if (!(*o.filter_radius >= 0.0) || !std::isfinite(*o.filter_radius)) f->fail("out of range", "a length ≥ 0 (0: per-vertex moves)");
    }
    if (const auto t = d->find("threads")) o.threads = sim3d::read_count(*t, 0, 64);
    if (const auto p = d->find("post_smoothing")) o.post_smoothing = sim3d::read_count(*p, 0, 1000);
    if (const auto p = d->find("pose_to_seat_threshold")) o.pose_to_seat_threshold = sim3d::read_positive(*p, Dimension::Length);
  }
  const Eigen::Vector3d up = -s.rest.options.gravity;
  if (!(up.norm() > 0.0)) root.at("gravity").fail("zero gravity: no side of the support faces the body", "a gravity vector");
  s.design_vertices = facing_vertices(s.rest.support, up, facing, lo, hi);
  s.region = fmt::format("{} support vertices facing up within {:.0f} deg{}", s.design_vertices.size(),
                         facing * 180.0 / 3.14159265358979323846, std::isfinite(lo[0]) ? " inside the region box" : "");
  if (s.design_vertices.empty()) {
    ErrorContext where;
    where.file = path.string();
    where.field = "design.region";
    throw_input_error("no support vertex lies in the design region and faces the body", where,
                      "a region box around the contact and a facing angle that includes the support's top");
  }
  return s;
}

}  // namespace palpa::design
