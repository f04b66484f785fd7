// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/material/registry.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "palpa/material/elastic_constants.hpp"
#include "palpa/material/models.hpp"
#include "palpa/material/spline_material.hpp"

namespace palpa::material {

namespace {

constexpr Dimension kPressure = Dimension::Pressure;
constexpr Dimension kNumber = Dimension::Dimensionless;

ParameterSpec scalar(std::string_view key, Dimension d, std::string_view meaning,
                     std::optional<double> fallback = std::nullopt) {
  return ParameterSpec{key, ParameterKind::Scalar, d, fallback, meaning};
}

const ParameterSpec kYoung = scalar("E", kPressure, "Young's modulus at small strain");
const ParameterSpec kPoisson = scalar("nu", kNumber, "Poisson's ratio at small strain, -1 < nu < 0.5");
const ParameterSpec kD1 = scalar("D1", Dimension::Compliance, "volumetric compliance, bulk modulus K = 2/D1");
const ParameterSpec kC10 = scalar("C10", kPressure, "coefficient of (Ibar1 - 3)");

double at(const ParameterValues& v, std::string_view key) { return v.scalars.find(key)->second; }

NaturalCubicSpline spline_of(const ParameterValues& v, std::string_view key) {
  const SplineValues& s = v.splines.find(key)->second;
  return NaturalCubicSpline(s.knots, s.values, fmt::format("spline {}", key));
}

std::vector<ModelSpec> make_models() {
  std::vector<ModelSpec> out;
  out.push_back({"neo-hookean", "compressible neo-Hookean, logarithmic volume term", {kYoung, kPoisson}, true,
                 [](const ParameterValues& v) { return std::make_unique<NeoHookean>(at(v, "E"), at(v, "nu")); }, {}});
  out.push_back({"neo-hookean-volume",
                 "neo-Hookean with a volume-preservation term (default tissue model)",
                 {kYoung, kPoisson,
                  scalar("volume_share", kNumber, "share of Lame's lambda in the (J-1)^2 term, 0..1", 0.5)},
                 true, [](const ParameterValues& v) {
                   return std::make_unique<NeoHookean>(
                       NeoHookean::with_volume_term(at(v, "E"), at(v, "nu"), at(v, "volume_share")));
                 }, {}});
  out.push_back({"neo-hookean-isochoric", "isochoric neo-Hookean of Abaqus/CalculiX/FEBio", {kC10, kD1}, true,
                 [](const ParameterValues& v) {
                   return std::make_unique<IsochoricInvariant>(
                       IsochoricInvariant::neo_hookean(at(v, "C10"), at(v, "D1")));
                 },
                 // Or from the small-strain E and nu: C10 = mu/2, D1 = 2/K.
                 {AlternativeParameters{{kYoung, kPoisson}, [](const ParameterValues& v) {
                    const ElasticConstants c = lame_from_young(at(v, "E"), at(v, "nu"));
                    ParameterValues own;
                    own.scalars = {{"C10", c.mu / 2.0}, {"D1", 2.0 / c.bulk()}};
                    return own;
                  }}}});
  out.push_back({"mooney-rivlin", "isochoric Mooney-Rivlin",
                 {kC10, scalar("C01", kPressure, "coefficient of (Ibar2 - 3)"), kD1}, true,
                 [](const ParameterValues& v) {
                   return std::make_unique<IsochoricInvariant>(
                       IsochoricInvariant::mooney_rivlin(at(v, "C10"), at(v, "C01"), at(v, "D1")));
                 }, {}});
  out.push_back({"yeoh", "isochoric Yeoh, up to 3 terms",
                 {kC10, scalar("C20", kPressure, "coefficient of (Ibar1 - 3)^2", 0.0),
                  scalar("C30", kPressure, "coefficient of (Ibar1 - 3)^3", 0.0), kD1},
                 true, [](const ParameterValues& v) {
                   return std::make_unique<IsochoricInvariant>(
                       IsochoricInvariant::yeoh(at(v, "C10"), at(v, "C20"), at(v, "C30"), at(v, "D1")));
                 }, {}});
  out.push_back({"stvk", "Saint Venant-Kirchhoff", {kYoung, kPoisson}, false, [](const ParameterValues& v) {
                   return std::make_unique<StVenantKirchhoff>(at(v, "E"), at(v, "nu"));
                 }, {}});
  out.push_back({"corotational", "linear corotational", {kYoung, kPoisson}, false, [](const ParameterValues& v) {
                   return std::make_unique<Corotational>(at(v, "E"), at(v, "nu"));
                 }, {}});
  out.push_back({"ogden", "Ogden, N terms, logarithmic volume term",
                 {ParameterSpec{"mu", ParameterKind::List, kPressure, std::nullopt, "moduli mu_p, one per term"},
                  ParameterSpec{"alpha", ParameterKind::List, kNumber, std::nullopt, "exponents alpha_p, one per term"},
                  kPoisson},
                 true, [](const ParameterValues& v) {
                   return std::make_unique<Ogden>(v.lists.find("mu")->second, v.lists.find("alpha")->second,
                                                  at(v, "nu"));
                 }, {}});
  const auto spline = [](std::string_view key, std::string_view meaning) {
    return ParameterSpec{key, ParameterKind::Spline, kPressure, std::nullopt, meaning};
  };
  out.push_back({"spline", "Valanis-Landel natural cubic spline material",
                 {spline("f", "f(stretch): knots and values_Pa"), spline("g", "g(stretch product): knots and values_Pa"),
                  spline("h", "h(J): knots and values_Pa")},
                 true, [](const ParameterValues& v) {
                   return std::make_unique<SplineMaterial>(spline_of(v, "f"), spline_of(v, "g"), spline_of(v, "h"));
                 }, {}});
  return out;
}

std::string_view kind_name(ParameterKind k) {
  switch (k) {
    case ParameterKind::Scalar: return "one value";
    case ParameterKind::List: return "a list of values";
    case ParameterKind::Spline: return "spline knots and values";
  }
  return "?";
}

std::optional<ParameterKind> kind_of(const ParameterValues& v, std::string_view key) {
  if (v.scalars.count(key) > 0) return ParameterKind::Scalar;
  if (v.lists.count(key) > 0) return ParameterKind::List;
  if (v.splines.count(key) > 0) return ParameterKind::Spline;
  return std::nullopt;
}

}  // namespace

bool ParameterValues::has(std::string_view key) const { return kind_of(*this, key).has_value(); }

std::vector<std::string> ParameterValues::keys() const {
  std::vector<std::string> out;
  for (const auto& [k, v] : scalars) out.push_back(k);
  for (const auto& [k, v] : lists) out.push_back(k);
  for (const auto& [k, v] : splines) out.push_back(k);
  return out;
}

const ParameterSpec* ModelSpec::find(std::string_view key) const {
  for (const auto& p : parameters) {
    if (p.key == key) return &p;
  }
  return nullptr;
}

const ParameterSpec* ModelSpec::find_any(std::string_view key) const {
  if (const ParameterSpec* p = find(key)) return p;
  for (const auto& alt : alternatives) {
    for (const auto& p : alt.parameters) {
      if (p.key == key) return &p;
    }
  }
  return nullptr;
}

std::string ModelSpec::parameter_summary() const {
  std::string out;
  for (const auto& p : parameters) {
    if (!out.empty()) out += ", ";
    out += p.key;
    if (p.kind == ParameterKind::List) out += "[]";
    if (p.default_value) out += fmt::format(" (default {:g})", *p.default_value);
  }
  for (const auto& alt : alternatives) {
    std::string keys;
    for (const auto& p : alt.parameters) keys += (keys.empty() ? "" : ", ") + std::string(p.key);
    out += fmt::format("; or {}", keys);
  }
  return out;
}

const std::vector<ModelSpec>& models() {
  static const std::vector<ModelSpec> all = make_models();
  return all;
}

std::string model_names(bool fittable_only) {
  std::string out;
  for (const auto& m : models()) {
    if (fittable_only && !m.fittable) continue;
    out += (out.empty() ? "" : ", ") + std::string(m.name);
  }
  return out;
}

const ModelSpec& model_spec(std::string_view name, const ErrorContext& where, bool fittable_only) {
  for (const auto& m : models()) {
    if (m.name != name) continue;
    if (fittable_only && !m.fittable) {
      throw_input_error(fmt::format("model '{}' cannot be fitted", name), where,
                        fmt::format("one of: {}", model_names(true)));
    }
    return m;
  }
  throw_input_error(fmt::format("unknown model '{}'", name), where,
                    fmt::format("one of: {}", model_names(fittable_only)));
}

std::unique_ptr<Material> make_material(const ModelSpec& model, ParameterValues values, const ErrorContext& where,
                                        const KeySpelling& spell) {
  const auto spelled = [&](std::string_view key) { return spell ? spell(key) : std::string(key); };
  const auto list = [&](const std::vector<ParameterSpec>& params) {
    std::string out;
    for (const auto& p : params) out += (out.empty() ? "" : ", ") + spelled(p.key);
    return out;
  };
  std::string allowed = list(model.parameters);
  for (const auto& alt : model.alternatives) allowed += " or " + list(alt.parameters);
  for (const std::string& key : values.keys()) {
    if (model.find_any(key) != nullptr) continue;
    throw_input_error(fmt::format("{} does not apply to model '{}'", spelled(key), model.name), where,
                      allowed.empty() ? "no parameters" : allowed);
  }
  // Alternative parameters: all of one set and none of the model's own.
  for (const auto& alt : model.alternatives) {
    const auto given = std::find_if(alt.parameters.begin(), alt.parameters.end(),
                                    [&](const ParameterSpec& p) { return values.has(p.key); });
    if (given == alt.parameters.end()) continue;
    for (const auto& p : alt.parameters) {
      if (!values.has(p.key)) {
        throw_input_error(fmt::format("model '{}' needs {} with {}", model.name, spelled(p.key), spelled(given->key)),
                          where, allowed);
      }
    }
    for (const auto& p : model.parameters) {
      if (values.has(p.key)) {
        throw_input_error(fmt::format("{} with {}", spelled(p.key), spelled(given->key)), where, allowed);
      }
    }
    values = alt.convert(values);
    break;
  }
  for (const auto& p : model.parameters) {
    const auto kind = kind_of(values, p.key);
    if (!kind && p.default_value) {
      values.scalars.emplace(std::string(p.key), *p.default_value);
      continue;
    }
    if (!kind) {
      throw_input_error(fmt::format("model '{}' needs {}", model.name, spelled(p.key)), where,
                        fmt::format("{}: {}", spelled(p.key), p.meaning));
    }
    if (*kind != p.kind) {
      throw_input_error(fmt::format("{} is {}", spelled(p.key), kind_name(*kind)), where,
                        fmt::format("{} for {}", kind_name(p.kind), spelled(p.key)));
    }
  }
  return model.build(values);
}

std::unique_ptr<Material> make_material(std::string_view model, ParameterValues values, const ErrorContext& where,
                                        const KeySpelling& spell) {
  return make_material(model_spec(model, where), std::move(values), where, spell);
}

ParameterValues parameter_values(const Material& m) {
  ParameterValues out;
  if (const auto* s = dynamic_cast<const SplineMaterial*>(&m)) {
    for (const auto& [key, part] : {std::pair{"f", SplineMaterial::Part::F}, std::pair{"g", SplineMaterial::Part::G},
                                    std::pair{"h", SplineMaterial::Part::H}}) {
      const NaturalCubicSpline& spline = s->spline(part);
      out.splines[key] = SplineValues{spline.knots(), spline.values()};
    }
    return out;
  }
  const Eigen::VectorXd theta = m.params();
  if (const auto* o = dynamic_cast<const Ogden*>(&m)) {
    const Eigen::Index n = o->num_terms();
    auto& mu = out.lists["mu"];
    auto& alpha = out.lists["alpha"];
    for (Eigen::Index q = 0; q < n; ++q) {
      mu.push_back(theta[q]);
      alpha.push_back(theta[n + q]);
    }
    out.scalars["nu"] = theta[2 * n];
    return out;
  }
  for (Eigen::Index k = 0; k < m.num_params(); ++k) out.scalars[m.param_info(k).name] = theta[k];
  return out;
}

}  // namespace palpa::material
