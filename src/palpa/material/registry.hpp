// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The material models palpa knows, each with its named parameters: one key
// spelling for material files ("parameters": {"volume_share": 0.5}), the
// command line (--volume_share 0.5), the fit and Python. A model is built from
// named SI values; unknown keys and missing required ones are refused, naming
// the key as the caller's user writes it.

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "palpa/core/error.hpp"
#include "palpa/core/units.hpp"
#include "palpa/material/material.hpp"

namespace palpa::material {

enum class ParameterKind {
  Scalar,  // one value
  List,    // one value per term (Ogden's mu and alpha)
  Spline,  // knots (dimensionless) and values (Pa) of a natural cubic spline
};

struct ParameterSpec {
  std::string_view key;
  ParameterKind kind = ParameterKind::Scalar;
  Dimension dimension = Dimension::Dimensionless;
  std::optional<double> default_value;  // scalars; absent: the parameter is required
  std::string_view meaning;
};

struct SplineValues {
  std::vector<double> knots;
  std::vector<double> values;  // Pa
};

// Named parameter values, SI.
struct ParameterValues {
  std::map<std::string, double, std::less<>> scalars;
  std::map<std::string, std::vector<double>, std::less<>> lists;
  std::map<std::string, SplineValues, std::less<>> splines;

  bool has(std::string_view key) const;
  std::vector<std::string> keys() const;
};

// Another set of parameters a model also takes (the isochoric neo-Hookean
// from E and nu), converted to its own.
struct AlternativeParameters {
  std::vector<ParameterSpec> parameters;  // all required
  std::function<ParameterValues(const ParameterValues&)> convert;
};

struct ModelSpec {
  std::string_view name;
  std::string_view summary;
  std::vector<ParameterSpec> parameters;
  bool fittable = false;  // palpa fit can fit it
  // Builds the model from complete values (every required key present,
  // defaults filled in); the constructors validate the values themselves.
  std::function<std::unique_ptr<Material>(const ParameterValues&)> build;
  std::vector<AlternativeParameters> alternatives;

  // The model's own parameter `key`, or null.
  const ParameterSpec* find(std::string_view key) const;
  // `key` among the model's own or alternative parameters, or null.
  const ParameterSpec* find_any(std::string_view key) const;
  // "E, nu, volume_share (default 0.5)".
  std::string parameter_summary() const;
};

// Every model, in a stable order.
const std::vector<ModelSpec>& models();
// "neo-hookean, neo-hookean-volume, ..." (only the fittable ones if asked).
std::string model_names(bool fittable_only = false);
// The model called `name`; an input error at `where` listing the models
// otherwise (or the fittable ones, which `fittable_only` then requires).
const ModelSpec& model_spec(std::string_view name, const ErrorContext& where = {}, bool fittable_only = false);

// How a caller's user writes a parameter key: "--E" on the command line, "E"
// in a file.
using KeySpelling = std::function<std::string(std::string_view key)>;

// Builds `model` from `values`: a key the model does not take, a required
// parameter missing, a value of the wrong kind, own and alternative
// parameters mixed are input errors at `where` naming the key as `spell`
// writes it; defaults fill the optional ones.
std::unique_ptr<Material> make_material(const ModelSpec& model, ParameterValues values, const ErrorContext& where = {},
                                        const KeySpelling& spell = {});
std::unique_ptr<Material> make_material(std::string_view model, ParameterValues values,
                                        const ErrorContext& where = {}, const KeySpelling& spell = {});

// The named parameters of a material, by its model's keys (exactly the values
// make_material builds it from).
ParameterValues parameter_values(const Material& m);

}  // namespace palpa::material
