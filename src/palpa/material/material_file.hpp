// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Material files (material.json); the models and their parameters are in
// registry.hpp.
//
// {
//   "palpa_material": 1,
//   "model": "neo-hookean",
//   "parameters": { "E": "12 kPa", "nu": 0.45 },
//   "provenance": { "created_by": "palpa 0.1.0", "created": "2026-11-23T10:00:00Z",
//                   "method": "palpa material (user-specified)", "objective": null }
// }
// Moduli carry units ("12 kPa"); ratios and exponents are plain numbers; D1 is a
// compliance ("2e-5 1/Pa"). Ogden: "mu": ["6 kPa", ...], "alpha": [4.7, ...],
// "nu": 0.45. Spline: "f": {"knots": [...], "values_Pa": [...]}, and "g", "h"
// likewise (knots dimensionless, values in Pa, i.e. SI).
//
// The reader names the file and the field for every problem (unknown model,
// missing or unknown parameter, non-physical or non-finite value).
// Parameters that have a default (registry.hpp) may be left out.
//
// (This lives in the material module rather than io: reading a file means
// constructing models, and io may not depend on material.)

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "palpa/core/json.hpp"
#include "palpa/material/material.hpp"

namespace palpa::material {

struct Provenance {
  std::string created_by;            // "palpa 0.1.0"
  std::string created;               // ISO 8601 UTC time
  std::string method;                // what produced it ("palpa fit ...", "user-specified")
  std::optional<double> objective;   // final objective value of a fit, if any
  Json details = Json::object();     // free-form extra information
};

// Builds a material from the "model" and "parameters" fields of a view; any
// key but those, "palpa_material" and "provenance" is refused (Input).
std::unique_ptr<Material> material_from_json(const JsonView& root);
// The "model" and "parameters" (and format tag) of a material, round-trip exact.
Json material_to_json(const Material& m);

struct MaterialFile {
  std::unique_ptr<Material> material;
  Provenance provenance;
};
MaterialFile read_material_file(const std::filesystem::path& path);
// Writes atomically.
void write_material_file(const std::filesystem::path& path, const Material& m,
                         const Provenance& provenance);

// Provenance for something made now by `method`.
Provenance make_provenance(std::string method);

}  // namespace palpa::material
