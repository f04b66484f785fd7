// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/sim3d/scene_json.hpp"

#include <Eigen/Geometry>
#include <fmt/format.h>

namespace palpa::sim3d {

Eigen::Vector3d read_quantity3(const JsonView& v, Dimension d) {
  if (!v.is_array() || v.size() != 3) v.fail("expected 3 values", fmt::format("[x, y, z] in {}", si_unit(d)));
  return {v.at(std::size_t{0}).as_quantity(d), v.at(std::size_t{1}).as_quantity(d), v.at(std::size_t{2}).as_quantity(d)};
}

Eigen::Vector3d read_number3(const JsonView& v) {
  const std::vector<double> a = v.as_number_array();
  if (a.size() != 3) v.fail(fmt::format("expected 3 numbers, got {}", a.size()), "[x, y, z]");
  return {a[0], a[1], a[2]};
}

double read_positive(const JsonView& v, Dimension d) {
  const double x = v.as_quantity(d);
  if (!(x > 0.0)) v.fail("must be > 0", fmt::format("a positive {}", dimension_name(d)));
  return x;
}

Eigen::Matrix3d read_rotation(const JsonView& v) {
  v.expect_only({"axis", "angle"});
  const Eigen::Vector3d axis = read_number3(v.at("axis"));
  if (!(axis.norm() > 0.0)) v.at("axis").fail("zero axis", "a non-zero direction");
  return Eigen::AngleAxisd(v.at("angle").as_quantity(Dimension::Angle), axis.normalized()).toRotationMatrix();
}

std::filesystem::path resolve_scene_path(const std::filesystem::path& scene_file, const std::string& p) {
  const std::filesystem::path q(p);
  return q.is_absolute() ? q : scene_file.parent_path() / q;
}

void absolutize_scene_paths(Json& j, const std::filesystem::path& scene_file) {
  if (j.is_object()) {
    for (auto& [key, value] : j.items()) {
      const bool path_key = key == "file" || key == "grid" || key == "surface" || key == "samples" || key == "layer" ||
                            key == "material";
      if (path_key && value.is_string()) {
        value = resolve_scene_path(scene_file, value.get<std::string>()).lexically_normal().string();
      } else {
        absolutize_scene_paths(value, scene_file);
      }
    }
  } else if (j.is_array()) {
    for (Json& v : j) absolutize_scene_paths(v, scene_file);
  }
}

LineSearchKind read_line_search(const JsonView& v) {
  const std::string n = v.as_string();
  if (n == "backtracking") return LineSearchKind::Backtracking;
  if (n == "golden") return LineSearchKind::GoldenSection;
  if (n == "brent") return LineSearchKind::Brent;
  if (n == "backtracking+brent") return LineSearchKind::BacktrackingThenBrent;
  v.fail(fmt::format("unknown line search '{}'", n), "backtracking, golden, brent or backtracking+brent");
}

int read_count(const JsonView& v, int lo, int hi) {
  const long long n = v.as_integer();
  if (n < lo || n > hi) v.fail(fmt::format("{}", n), fmt::format("{} to {}", lo, hi));
  return static_cast<int>(n);
}

body::ContactSampling read_contact_sampling(const JsonView& v) {
  const std::string s = v.as_string();
  if (s == "vertices") return body::ContactSampling::Vertices;
  if (s == "surface") return body::ContactSampling::Surface;
  v.fail(fmt::format("unknown contact sampling '{}'", s), "\"vertices\" or \"surface\"");
}

tet::ElementChoice read_element(const JsonView& body) {
  tet::ElementChoice c;
  if (const auto el = body.find("element")) {
    const std::string name = el->as_string();
    if (name == "linear") {
      c = {tet::TetElement::Linear, 0.0};
    } else if (name != "nodal-pressure") {
      el->fail(fmt::format("unknown element '{}'", name), "\"linear\" or \"nodal-pressure\"");
    }
  }
  if (const auto st = body.find("stabilization")) {
    if (c.element != tet::TetElement::NodalPressure) {
      st->fail("a stabilization with \"element\": \"linear\"", "no stabilization for the linear tet");
    }
    c.stabilization = st->as_number();
    if (!(c.stabilization >= 0.0 && c.stabilization < 1.0)) {
      st->fail(fmt::format("{} is outside [0, 1)", c.stabilization), "a share β with 0 ≤ β < 1");
    }
  }
  return c;
}

Json element_json(const tet::ElasticModel& model) {
  if (model.element() == tet::TetElement::Linear) return {{"element", "linear"}};
  return {{"element", "nodal-pressure"}, {"stabilization", model.stabilization()}};
}

}  // namespace palpa::sim3d
