// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/tet/material_field.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>

#include "palpa/core/error.hpp"
#include "palpa/material/scaled.hpp"

namespace palpa::tet {

MaterialField scaled_per_element(const BodyMaterial& shape, const Eigen::VectorXd& young,
                                 double step) {
  if (!(step >= 0.0 && std::isfinite(step))) {
    throw Error(ErrorKind::Internal, fmt::format("a modulus step of {}", step));
  }
  MaterialField f;
  f.element_material.resize(young.size());
  // Group key: the modulus itself (step 0) or its level on a log scale.
  const double log_step = std::log1p(step);
  std::map<double, int> groups;
  for (Eigen::Index e = 0; e < young.size(); ++e) {
    const double E = young[e];
    if (!(std::isfinite(E) && E > 0.0)) {
      throw Error(ErrorKind::Input, fmt::format("tet {} has a Young's modulus of {} Pa", e, E), {},
                  "a finite modulus > 0 in every tet");
    }
    const double key = step > 0.0 ? std::round(std::log(E) / log_step) : E;
    auto [it, added] = groups.try_emplace(key, static_cast<int>(f.materials.size()));
    if (added) {
      const double group_young = step > 0.0 ? std::exp(key * log_step) : E;
      f.materials.push_back(
          BodyMaterial{material::with_young(*shape.material, group_young), shape.density});
    }
    f.element_material[e] = it->second;
  }
  return f;
}

Eigen::VectorXd element_young(const ElasticModel& model) {
  std::vector<double> per_material;
  for (const BodyMaterial& m : model.materials()) {
    per_material.push_back(material::small_strain_constants(*m.material).young());
  }
  Eigen::VectorXd E(model.num_elements());
  for (Eigen::Index e = 0; e < E.size(); ++e) {
    E[e] = per_material[static_cast<std::size_t>(model.element_material()[e])];
  }
  return E;
}

}  // namespace palpa::tet
