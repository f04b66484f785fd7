// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/material/material_file.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <ctime>

#include "palpa/core/error.hpp"
#include "palpa/core/version.hpp"
#include "palpa/material/models.hpp"
#include "palpa/material/spline_material.hpp"

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

double scalar(const JsonView& params, const std::string& name, Dimension d) {
  return params.at(name).as_quantity(d);
}

double scalar_or(const JsonView& params, const std::string& name, Dimension d, double fallback) {
  const auto v = params.find(name);
  return v ? v->as_quantity(d) : fallback;
}

std::vector<double> quantity_list(const JsonView& v, Dimension d) {
  std::vector<double> out;
  for (std::size_t i = 0; i < v.size(); ++i) out.push_back(v.at(i).as_quantity(d));
  return out;
}

NaturalCubicSpline spline_from_json(const JsonView& v, const char* name) {
  v.expect_only({"knots", "values_Pa"});
  const std::vector<double> knots = v.at("knots").as_number_array();
  const std::vector<double> values = v.at("values_Pa").as_number_array();
  return with_context(v, [&] { return NaturalCubicSpline(knots, values, name); });
}

Json spline_to_json(const NaturalCubicSpline& s) {
  return Json{{"knots", s.knots()}, {"values_Pa", s.values()}};
}

}  // namespace

const std::vector<ModelInfo>& known_models() {
  static const std::vector<ModelInfo> models = {
      {"neo-hookean", "compressible neo-Hookean, logarithmic volume term", "E, nu"},
      {"neo-hookean-volume", "neo-Hookean with a volume-preservation term (default tissue model)",
       "E, nu, volume_share (default 0.5)"},
      {"neo-hookean-isochoric", "isochoric neo-Hookean of Abaqus/CalculiX/FEBio", "C10, D1"},
      {"mooney-rivlin", "isochoric Mooney-Rivlin", "C10, C01, D1"},
      {"yeoh", "isochoric Yeoh, up to 3 terms", "C10, C20 (0), C30 (0), D1"},
      {"stvk", "Saint Venant-Kirchhoff", "E, nu"},
      {"corotational", "linear corotational", "E, nu"},
      {"ogden", "Ogden, N terms, logarithmic volume term", "mu[], alpha[], nu"},
      {"spline", "Valanis-Landel natural cubic spline material", "f, g, h: knots and values_Pa"},
  };
  return models;
}

std::unique_ptr<Material> material_from_json(const JsonView& root) {
  const std::string model = root.at("model").as_string();
  const JsonView p = root.at("parameters");
  const auto scalars = [&](std::vector<std::string> allowed) { p.expect_only(allowed); };
  const Dimension kPa = Dimension::Pressure;
  const Dimension kNum = Dimension::Dimensionless;
  const Dimension kComp = Dimension::Compliance;

  return with_context(p, [&]() -> std::unique_ptr<Material> {
    if (model == "neo-hookean") {
      scalars({"E", "nu"});
      return std::make_unique<NeoHookean>(scalar(p, "E", kPa), scalar(p, "nu", kNum));
    }
    if (model == "neo-hookean-volume") {
      scalars({"E", "nu", "volume_share"});
      return std::make_unique<NeoHookean>(NeoHookean::with_volume_term(
          scalar(p, "E", kPa), scalar(p, "nu", kNum), scalar_or(p, "volume_share", kNum, 0.5)));
    }
    if (model == "neo-hookean-isochoric") {
      scalars({"C10", "D1"});
      return std::make_unique<IsochoricInvariant>(
          IsochoricInvariant::neo_hookean(scalar(p, "C10", kPa), scalar(p, "D1", kComp)));
    }
    if (model == "mooney-rivlin") {
      scalars({"C10", "C01", "D1"});
      return std::make_unique<IsochoricInvariant>(IsochoricInvariant::mooney_rivlin(
          scalar(p, "C10", kPa), scalar(p, "C01", kPa), scalar(p, "D1", kComp)));
    }
    if (model == "yeoh") {
      scalars({"C10", "C20", "C30", "D1"});
      return std::make_unique<IsochoricInvariant>(IsochoricInvariant::yeoh(
          scalar(p, "C10", kPa), scalar_or(p, "C20", kPa, 0.0), scalar_or(p, "C30", kPa, 0.0),
          scalar(p, "D1", kComp)));
    }
    if (model == "stvk") {
      scalars({"E", "nu"});
      return std::make_unique<StVenantKirchhoff>(scalar(p, "E", kPa), scalar(p, "nu", kNum));
    }
    if (model == "corotational") {
      scalars({"E", "nu"});
      return std::make_unique<Corotational>(scalar(p, "E", kPa), scalar(p, "nu", kNum));
    }
    if (model == "ogden") {
      scalars({"mu", "alpha", "nu"});
      return std::make_unique<Ogden>(quantity_list(p.at("mu"), kPa),
                                     quantity_list(p.at("alpha"), kNum), scalar(p, "nu", kNum));
    }
    if (model == "spline") {
      scalars({"f", "g", "h"});
      return std::make_unique<SplineMaterial>(spline_from_json(p.at("f"), "spline f"),
                                              spline_from_json(p.at("g"), "spline g"),
                                              spline_from_json(p.at("h"), "spline h"));
    }
    std::string names;
    for (const auto& m : known_models()) names += (names.empty() ? "" : ", ") + std::string(m.name);
    root.at("model").fail(fmt::format("unknown model '{}'", model), fmt::format("one of: {}", names));
  });
}

Json material_to_json(const Material& m) {
  Json params = Json::object();
  if (const auto* s = dynamic_cast<const SplineMaterial*>(&m)) {
    params["f"] = spline_to_json(s->spline(SplineMaterial::Part::F));
    params["g"] = spline_to_json(s->spline(SplineMaterial::Part::G));
    params["h"] = spline_to_json(s->spline(SplineMaterial::Part::H));
  } else if (const auto* o = dynamic_cast<const Ogden*>(&m)) {
    const Eigen::VectorXd t = o->params();
    const Eigen::Index n = o->num_terms();
    Json mu = Json::array();
    Json alpha = Json::array();
    for (Eigen::Index q = 0; q < n; ++q) {
      mu.push_back(quantity_json(t[q], Dimension::Pressure));
      alpha.push_back(t[n + q]);
    }
    params["mu"] = mu;
    params["alpha"] = alpha;
    params["nu"] = t[2 * n];
  } else {
    const Eigen::VectorXd t = m.params();
    for (Eigen::Index k = 0; k < m.num_params(); ++k) {
      const ParamInfo info = m.param_info(k);
      params[info.name] = quantity_json(t[k], info.dimension);
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
