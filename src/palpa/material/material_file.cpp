// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/material/material_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>

#include "palpa/core/error.hpp"
#include "palpa/core/version.hpp"
#include "palpa/material/registry.hpp"
#include "palpa/material/spline.hpp"

namespace palpa::material {

namespace {

constexpr int kFormatVersion = 1;

// A quantity as text that parses back to exactly `value`: the display unit when
// that is exact, SI otherwise.
Json quantity_json(double value, Dimension d) {
  if (d == Dimension::Dimensionless) return value;
  const std::string pretty = format_quantity(value, d);
  const auto space = pretty.rfind(' ');
  const std::string unit = pretty.substr(space + 1);
  const double in_unit = si_to_unit(value, unit, d);
  // The readable unit when 15 significant digits read back bit-exactly, else
  // SI, whose shortest form always does.
  const std::string candidate = fmt::format("{:.15g} {}", in_unit, unit);
  if (parse_quantity(candidate, d, ErrorContext{}) == value) return candidate;
  return fmt::format("{} {}", value, si_unit(d));
}

// Re-throws a validation error from a constructor with the file and field.
template <class Fn>
auto with_context(const JsonView& where, Fn&& build) {
  try {
    return build();
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Input || !e.context().file.empty()) throw;
    where.fail(e.problem(), e.expected());
  }
}

std::vector<double> quantity_list(const JsonView& v, Dimension d) {
  std::vector<double> out;
  for (std::size_t i = 0; i < v.size(); ++i) out.push_back(v.at(i).as_quantity(d));
  return out;
}

// A spline's knots and values, checked here so that a problem names its field.
SplineValues spline_from_json(const JsonView& v, const std::string& key) {
  v.expect_only({"knots", "values_Pa"});
  SplineValues s{v.at("knots").as_number_array(), v.at("values_Pa").as_number_array()};
  with_context(v, [&] { return NaturalCubicSpline(s.knots, s.values, "spline " + key); });
  return s;
}

}  // namespace

std::unique_ptr<Material> material_from_json(const JsonView& root) {
  // (Written inline in a scene, a material may be a material file's whole text.)
  root.expect_only({"palpa_material", "model", "parameters", "provenance"});
  const JsonView name = root.at("model");
  const ModelSpec& model = model_spec(name.as_string(), name.context());
  const JsonView p = root.at("parameters");
  std::vector<std::string> keys;
  for (const auto& spec : model.parameters) keys.emplace_back(spec.key);
  for (const auto& alt : model.alternatives) {
    for (const auto& spec : alt.parameters) keys.emplace_back(spec.key);
  }
  p.expect_only(keys);
  ParameterValues values;
  // The alternative parameters given are read as they are (make_material
  // checks that they come as a whole set); the model's own otherwise.
  std::vector<ParameterSpec> read = model.parameters;
  for (const auto& alt : model.alternatives) {
    const bool any = std::any_of(alt.parameters.begin(), alt.parameters.end(),
                                 [&](const ParameterSpec& s) { return p.has(std::string(s.key)); });
    if (!any) continue;
    read = alt.parameters;
    for (const auto& spec : model.parameters) {
      if (p.has(std::string(spec.key))) read.push_back(spec);
    }
  }
  for (const auto& spec : read) {
    const std::string key(spec.key);
    if (spec.default_value && !p.has(key)) continue;
    const JsonView v = p.at(key);  // names a missing required parameter
    switch (spec.kind) {
      case ParameterKind::Scalar: values.scalars[key] = v.as_quantity(spec.dimension); break;
      case ParameterKind::List: values.lists[key] = quantity_list(v, spec.dimension); break;
      case ParameterKind::Spline: values.splines[key] = spline_from_json(v, key); break;
    }
  }
  return with_context(p, [&] { return make_material(model, std::move(values), p.context()); });
}

Json material_to_json(const Material& m) {
  const ModelSpec& model = model_spec(m.model());
  const ParameterValues values = parameter_values(m);
  Json params = Json::object();
  for (const auto& spec : model.parameters) {
    const std::string key(spec.key);
    switch (spec.kind) {
      case ParameterKind::Scalar: params[key] = quantity_json(values.scalars.at(key), spec.dimension); break;
      case ParameterKind::List: {
        Json list = Json::array();
        for (const double x : values.lists.at(key)) list.push_back(quantity_json(x, spec.dimension));
        params[key] = list;
        break;
      }
      case ParameterKind::Spline: {
        const SplineValues& s = values.splines.at(key);
        params[key] = Json{{"knots", s.knots}, {"values_Pa", s.values}};
        break;
      }
    }
  }
  return Json{{"palpa_material", kFormatVersion}, {"model", std::string(m.model())}, {"parameters", params}};
}

MaterialFile read_material_file(const std::filesystem::path& path) {
  const Json j = read_json_file(path);
  const JsonView root(j, path.string());
  if (!j.is_object()) root.fail("is not a JSON object", "a material file object");
  root.expect_only({"palpa_material", "model", "parameters", "provenance"});
  if (const auto v = root.find("palpa_material")) {
    if (v->as_integer() != kFormatVersion) {
      v->fail(fmt::format("format version {} is not supported", v->as_integer()),
              fmt::format("version {}", kFormatVersion));
    }
  }
  MaterialFile out;
  out.material = material_from_json(root);
  if (const auto prov = root.find("provenance")) {
    if (const auto v = prov->find("created_by")) out.provenance.created_by = v->as_string();
    if (const auto v = prov->find("created")) out.provenance.created = v->as_string();
    if (const auto v = prov->find("method")) out.provenance.method = v->as_string();
    if (const auto v = prov->find("objective"); v && !v->json().is_null()) {
      out.provenance.objective = v->as_number();
    }
    if (const auto v = prov->find("details")) out.provenance.details = v->json();
  }
  return out;
}

void write_material_file(const std::filesystem::path& path, const Material& m,
                         const Provenance& provenance) {
  Json j = material_to_json(m);
  j["provenance"] = Json{{"created_by", provenance.created_by},
                         {"created", provenance.created},
                         {"method", provenance.method},
                         {"objective", provenance.objective ? Json(*provenance.objective) : Json()},
                         {"details", provenance.details}};
  write_json_file(path, j);
}

Provenance make_provenance(std::string method) {
  Provenance p;
  p.created_by = fmt::format("palpa {}", kVersion);
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &utc);
  p.created = buf;
  p.method = std::move(method);
  return p;
}

}  // namespace palpa::material
