// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/design/checkpoint.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <string>

#include "palpa/core/checkpoint.hpp"

namespace palpa::design {

namespace {

const char* method_name(DesignMethod m) { return m == DesignMethod::Lbfgs ? "lbfgs" : "cg"; }

Json to_json(const Eigen::VectorXd& v) { return Json(std::vector<double>(v.data(), v.data() + v.size())); }

Eigen::VectorXd vector_of(const JsonView& j, Eigen::Index expected) {
  const std::vector<double> v = j.as_number_array();
  if (static_cast<Eigen::Index>(v.size()) != expected) {
    j.fail(fmt::format("{} values", v.size()), fmt::format("{} (the checkpoint is of another design)", expected));
  }
  return Eigen::Map<const Eigen::VectorXd>(v.data(), expected);
}

Json state_json(const rest::RestState& s) {
  const Eigen::Map<const Eigen::VectorXd> R(s.core.rotation.data(), 9);
  Json j = {{"x", to_json(s.x)},
            {"rotation", to_json(R)},
            {"omega", to_json(s.core.omega)},
            {"spring_areas", s.spring_areas},
            {"stiffness", s.stiffness}};
  if (s.support.size() > 0) j["support"] = to_json(s.support);
  return j;
}

rest::RestState state_of(const JsonView& j, const rest::RestState& like) {
  rest::RestState s;
  s.x = vector_of(j.at("x"), like.x.size());
  const Eigen::VectorXd R = vector_of(j.at("rotation"), 9);
  s.core.rotation = Eigen::Map<const Eigen::Matrix3d>(R.data());
  s.core.omega = vector_of(j.at("omega"), 3);
  const Eigen::VectorXd a = vector_of(j.at("spring_areas"), static_cast<Eigen::Index>(like.spring_areas.size()));
  s.spring_areas.assign(a.data(), a.data() + a.size());
  s.stiffness = j.at("stiffness").as_number();
  // A deformable support's DOFs (a rigid support has none).
  if (like.support.size() > 0) s.support = vector_of(j.at("support"), like.support.size());
  return s;
}

Json record_json(const IterationRecord& r) {
  return {{"iteration", r.iteration}, {"phi", r.phi},   {"zeta", r.zeta},         {"psi", r.psi},
          {"move_m", r.move},         {"evaluations", r.evaluations}, {"restarted", r.restarted},
          {"seconds", r.seconds},     {"stiffness", r.stiffness},     {"refrozen", r.refrozen}};
}

IterationRecord record_of(const JsonView& j) {
  IterationRecord r;
  r.iteration = static_cast<int>(j.at("iteration").as_integer());
  r.phi = j.at("phi").as_number();
  r.zeta = j.at("zeta").as_number();
  r.psi = j.at("psi").as_number();
  r.move = j.at("move_m").as_number();
  r.evaluations = static_cast<int>(j.at("evaluations").as_integer());
  r.restarted = j.at("restarted").as_bool();
  r.seconds = j.at("seconds").as_number();
  if (const auto k = j.find("stiffness")) r.stiffness = k->as_number();
  if (const auto f = j.find("refrozen")) r.refrozen = f->as_bool();
  return r;
}

// A one-body design's checkpoint keeps its body's members at the top.
bool one_body(const DesignCheckpoint& c) { return c.bodies.size() == 1 && c.bodies.front().name.empty(); }

BodyCheckpoint body_of(const JsonView& j, const BodyCheckpoint& like) {
  BodyCheckpoint b = like;
  // (A body another rank holds: its state is that rank's to read.)
  if (like.state.x.size() > 0) b.state = state_of(j.at("state"), like.state);
  if (const auto p = j.find("max_penetration")) b.max_penetration = p->as_number();
  if (const auto rf = j.find("refreeze_failed")) b.refreeze_failed = rf->as_bool();
  return b;
}

}  // namespace

Json checkpoint_json(const DesignCheckpoint& c) {
  Json hist = Json::array();
  for (const IterationRecord& r : c.history) hist.push_back(record_json(r));
  Json doc = checkpoint_document("design");
  doc.update(Json{{"method", method_name(c.method)},
                  {"iteration", c.iteration},
                  {"gamma", c.gamma},
                  {"theta", to_json(c.theta)},
                  {"direction", to_json(c.direction)},
                  {"gradient", to_json(c.gradient)},
                  {"steepest", c.steepest},
                  {"phi", c.phi},
                  {"zeta", c.zeta},
                  {"psi", c.psi},
                  {"history", hist},
                  {"evaluations", c.evaluations},
                  {"newton_iterations", c.newton_iterations},
                  {"moves", c.moves},
                  {"filter_radius", c.filter_radius},
                  {"seconds", c.seconds}});
  if (one_body(c)) {
    const BodyCheckpoint& b = c.bodies.front();
    doc.update(Json{{"max_penetration", b.max_penetration},
                    {"refreeze_failed", b.refreeze_failed},
                    {"state", state_json(b.state)}});
  } else {
    Json bodies = Json::array();
    for (const BodyCheckpoint& b : c.bodies) {
      bodies.push_back(Json{{"name", b.name},
                            {"max_penetration", b.max_penetration},
                            {"refreeze_failed", b.refreeze_failed},
                            {"state", state_json(b.state)}});
    }
    doc["bodies"] = std::move(bodies);
  }
  return doc;
}

DesignCheckpoint read_design_checkpoint(const std::filesystem::path& path, const DesignCheckpoint& like) {
  // The run's scene and options are checked member by member below, each
  // with its own message.
  const Json doc = read_checkpoint(path, {"design", {}, {}, {}});
  const JsonView j(doc, path.string());
  DesignCheckpoint c = like;
  const std::string method = j.at("method").as_string();
  if (method != method_name(like.method)) {
    j.at("method").fail(fmt::format("a checkpoint of the {} method", method),
                        fmt::format("{} (the method of this run)", method_name(like.method)));
  }
  const double saved_gamma = j.at("gamma").as_number();
  if (std::abs(saved_gamma - like.gamma) > 1e-9 * std::max(std::abs(like.gamma), 1e-300)) {
    j.at("gamma").fail(fmt::format("γ = {:.6g} differs from this scene's {:.6g}", saved_gamma, like.gamma),
                       "a checkpoint of the same scene and options");
  }
  {
    const JsonView mv = j.at("moves");
    std::vector<double> saved;
    for (std::size_t i = 0; i < mv.size(); ++i) saved.push_back(mv.at(i).as_number());
    if (saved != like.moves) {
      mv.fail(fmt::format("step lengths [{}] differ from this scene's [{}]", fmt::join(saved, ", "),
                          fmt::join(like.moves, ", ")),
              "a checkpoint of the same scene and options");
    }
  }
  if (const auto fr = j.find("filter_radius")) {
    const double saved = fr->as_number();
    if (std::abs(saved - like.filter_radius) > 1e-12) {
      fr->fail(fmt::format("a design filter of radius {:.6g} m differs from this scene's {:.6g} m", saved,
                           like.filter_radius),
               "a checkpoint of the same scene and options");
    }
  } else if (like.filter_radius > 0.0) {
    j.fail("a checkpoint of per-vertex moves", "one of this scene's filtered design (its θ means other shapes)");
  }
  if (const auto sec = j.find("seconds")) c.seconds = sec->as_number();
  c.theta = vector_of(j.at("theta"), like.theta.size());
  c.direction = vector_of(j.at("direction"), like.theta.size());
  c.gradient = vector_of(j.at("gradient"), like.theta.size());
  c.steepest = j.at("steepest").as_bool();
  if (one_body(like)) {
    c.bodies = {body_of(j, like.bodies.front())};
  } else {
    const JsonView bodies = j.at("bodies");
    if (bodies.size() != like.bodies.size()) {
      bodies.fail(fmt::format("{} bodies", bodies.size()),
                  fmt::format("{} (the checkpoint is of another cohort)", like.bodies.size()));
    }
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      const JsonView b = bodies.at(i);
      if (const std::string name = b.at("name").as_string(); name != like.bodies[i].name) {
        b.at("name").fail(fmt::format("the body '{}'", name),
                          fmt::format("'{}' (the checkpoint is of another cohort)", like.bodies[i].name));
      }
      c.bodies[i] = body_of(b, like.bodies[i]);
    }
  }
  c.phi = j.at("phi").as_number();
  c.zeta = j.at("zeta").as_number();
  c.psi = j.at("psi").as_number();
  const JsonView h = j.at("history");
  c.history.clear();
  for (std::size_t i = 0; i < h.size(); ++i) c.history.push_back(record_of(h.at(i)));
  c.evaluations = static_cast<int>(j.at("evaluations").as_integer());
  c.newton_iterations = static_cast<int>(j.at("newton_iterations").as_integer());
  const long long iteration = j.at("iteration").as_integer();
  if (iteration < 0 || iteration > 1000000) j.at("iteration").fail(fmt::format("{}", iteration), "0 to 1000000");
  c.iteration = static_cast<int>(iteration);
  return c;
}

}  // namespace palpa::design
