// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/material/output.hpp"

#include <fmt/format.h>

#include "palpa/material/checks.hpp"
#include "palpa/material/registry.hpp"

namespace palpa::material {

std::string describe(const MaterialFile& file, std::string_view path) {
  const Material& m = *file.material;
  std::string out = fmt::format("{}\n  model: {}\n  {}\n", path, m.model(), m.description());
  out += "parameters:\n";
  const Eigen::VectorXd theta = m.params();
  if (m.model() == "spline") {
    const ParameterValues values = parameter_values(m);
    for (const auto& [part, spline] : values.splines) {
      out += fmt::format("  {}: {} knots from {:.4g} to {:.4g}\n", part, spline.knots.size(), spline.knots.front(),
                         spline.knots.back());
    }
  } else {
    for (Eigen::Index k = 0; k < m.num_params(); ++k) {
      const ParamInfo info = m.param_info(k);
      out += fmt::format("  {:<14} {:<16} {}\n", info.name, format_quantity(theta[k], info.dimension), info.meaning);
    }
  }
  const MaterialCheck c = check_material(m);
  out += fmt::format("small strain: E = {}, nu = {:.4g}, shear modulus = {}, bulk modulus = {}\n",
                     format_quantity(c.small_strain.young(), Dimension::Pressure), c.small_strain.poisson(),
                     format_quantity(c.small_strain.mu, Dimension::Pressure),
                     format_quantity(c.small_strain.bulk(), Dimension::Pressure));
  if (c.problems.empty()) {
    out += "checks: stress-free at rest, stable at rest, stable in uniaxial, equibiaxial and shear loading for "
           "stretches 0.5 to 2\n";
  } else {
    for (const auto& p : c.problems) out += fmt::format("warning: {}\n", p);
  }
  const Provenance& prov = file.provenance;
  if (!prov.created_by.empty() || !prov.method.empty()) {
    out += fmt::format("provenance: {} {} {}", prov.method, prov.created_by, prov.created);
    if (prov.objective) out += fmt::format(", objective {:.6g}", *prov.objective);
    out += "\n";
  }
  return out;
}

CsvTable homogeneous_curve_table(const Material& m, LoadCase test, double lo, double hi, int points,
                                 std::string comment) {
  const auto pts = homogeneous_curve(m, test, lo, hi, points);
  CsvTable t;
  t.add_comment(std::move(comment));
  std::vector<double> load, lateral, nominal, cauchy, c11, c22, energy;
  for (const auto& p : pts) {
    load.push_back(p.load);
    lateral.push_back(p.lateral);
    nominal.push_back(p.nominal);
    cauchy.push_back(p.cauchy);
    c11.push_back(p.cauchy_11);
    c22.push_back(p.cauchy_22);
    energy.push_back(p.energy);
  }
  if (test == LoadCase::SimpleShear) {
    t.add_column("shear_strain", load);
    t.add_quantity("nominal_shear_stress", "Pa", Dimension::Pressure, nominal);
    t.add_quantity("cauchy_shear_stress", "Pa", Dimension::Pressure, cauchy);
    t.add_quantity("cauchy_normal_11", "Pa", Dimension::Pressure, c11);
    t.add_quantity("cauchy_normal_22", "Pa", Dimension::Pressure, c22);
  } else {
    t.add_column("stretch", load);
    t.add_column("lateral_stretch", lateral);
    t.add_quantity("nominal_stress", "Pa", Dimension::Pressure, nominal);
    t.add_quantity("cauchy_stress", "Pa", Dimension::Pressure, cauchy);
  }
  t.add_quantity("energy_density", "Pa", Dimension::Pressure, energy);
  return t;
}

}  // namespace palpa::material
