// SPDX-License-Identifier: AGPL-3.0-or-later
#include "fit/fit_fixtures.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "common/test_support.hpp"
#include "palpa/io/csv.hpp"

namespace palpa::fit::test {

void write_force_csv(const std::filesystem::path& path, const Curve& c) {
  CsvTable t;
  t.add_comment("synthetic curve (palpa fit tests)");
  t.add_quantity("indentation", "mm", Dimension::Length, c.x);
  t.add_quantity("force", "N", Dimension::Force, c.y);
  write_csv(path, t);
}

void write_stress_csv(const std::filesystem::path& path, material::LoadCase lc, const Curve& c) {
  CsvTable t;
  t.add_column(lc == material::LoadCase::SimpleShear ? "shear" : "stretch", c.x);
  t.add_quantity("stress", "kPa", Dimension::Pressure, c.y);
  write_csv(path, t);
}

Curve simulate_poke(const material::Material& m, const axisym::PokeSetup& setup, double max_depth, int points) {
  axisym::PokeSimulator sim(m, setup);
  axisym::PokeOptions o;
  o.max_depth = max_depth;
  o.steps = points;
  const axisym::PokeCurve pc = sim.run(o);
  Curve c;
  for (std::size_t k = 1; k < pc.samples.size(); ++k) {
    c.x.push_back(pc.samples[k].depth);
    c.y.push_back(pc.samples[k].force);
  }
  return c;
}

double add_noise(std::vector<double>& y, double rel, double abs, std::uint64_t salt) {
  double largest = 0.0;
  for (double v : y) largest = std::max(largest, std::abs(v));
  const double sigma = rel * largest + abs;
  auto rng = palpa::test::make_rng(salt);
  std::normal_distribution<double> noise(0.0, sigma);
  for (double& v : y) v += noise(rng);
  return sigma;
}

MeasuredCurve measured(const std::string& name, CurveRole role, double radius, const Curve& c,
                       material::LoadCase lc) {
  MeasuredCurve m;
  m.name = name;
  m.file = name + ".csv";
  m.role = role;
  m.radius = radius;
  m.load_case = lc;
  m.x = c.x;
  m.y = c.y;
  return m;
}

Synthetic write_indentation_dataset(const std::filesystem::path& folder, const material::Material& truth,
                                    const IndentationSpec& spec) {
  Synthetic out;
  out.dataset = folder / "dataset.json";
  Json curves = Json::array();
  std::uint64_t salt = spec.salt * 1000;
  auto add = [&](double radius, CurveRole role) {
    axisym::PokeSetup s;
    s.geometry.punch_radius = radius;
    s.geometry.thickness = spec.true_depth;
    s.mesh_level = spec.mesh_level;
    s.contact = spec.contact;
    Curve c = simulate_poke(truth, s, spec.max_depth, spec.points);
    out.sigma.push_back(add_noise(c.y, spec.noise_rel, spec.noise_abs, ++salt));
    const std::string file = fmt::format("a{:.0f}.csv", radius * 1e6);
    write_force_csv(folder / file, c);
    curves.push_back(Json{{"file", file},
                          {"radius", fmt::format("{} mm", radius * 1e3)},
                          {"role", std::string(to_string(role))}});
  };
  for (double r : spec.train_radii) add(r, CurveRole::Train);
  for (double r : spec.validate_radii) add(r, CurveRole::Validate);
  const Json d{{"palpa_dataset", 1},
               {"sample", "synthetic"},
               {"test", "indentation"},
               {"layer_depth", spec.layer_depth},
               {"contact", std::string(axisym::to_string(spec.contact))},
               {"poisson", spec.poisson},
               {"curves", curves}};
  write_json_file(out.dataset, d);
  return out;
}

}  // namespace palpa::fit::test
