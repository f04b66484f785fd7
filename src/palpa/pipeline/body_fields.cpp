// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/pipeline/body_fields.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/input_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/units.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/material/material_file.hpp"
#include "palpa/sim3d/scene_json.hpp"

namespace palpa::pipeline {

namespace fs = std::filesystem;

namespace {

LocationFit read_fit(const Subject& s, const Location& l, const fs::path& folder) {
  const std::string who = fmt::format("subject '{}', location '{}'", s.name, l.name);
  LocationFit f;
  f.name = l.name;
  f.position = l.position;
  f.folder = folder;
  for (const char* name : {"material.json", "report.json"}) {
    if (!fs::is_regular_file(folder / name)) {
      throw_input_error(
          fmt::format("{}: its fit has no {} (did the fit fail? see its log)", who, name),
          ErrorContext{(folder / name).string(), 0, 0, ""},
          "the output of palpa fit for this location");
    }
  }
  const material::MaterialFile m = material::read_material_file(folder / "material.json");
  const material::ElasticConstants ec = material::small_strain_constants(*m.material);
  f.young = ec.young();
  f.poisson = ec.poisson();
  const fs::path report_file = folder / "report.json";
  const Json report = read_json_file(report_file);
  const JsonView r(report, report_file.string());
  f.depth = r.at("layer_depth_m").as_number();
  if (!(f.depth > 0.0))
    r.at("layer_depth_m")
        .fail(fmt::format("{}: a layer depth of {} m", who, f.depth), "a depth > 0");
  f.depth_searched = r.at("depth_search").as_bool();
  f.termination = r.at("termination").as_string();
  if (f.termination == "failed" || f.termination == "not_run") {
    r.at("termination")
        .fail(fmt::format("{}: its fit ended '{}'", who, f.termination),
              "a fit that converged or stopped at its limits");
  }
  double sum = 0.0;
  int n = 0;
  const JsonView curves = r.at("curves");
  for (std::size_t i = 0; i < curves.size(); ++i) {
    const JsonView c = curves.at(i);
    if (c.at("role").as_string() != "train" || c.at("rms_error_fitted").json().is_null()) continue;
    const double e = c.at("rms_error_fitted").as_number() / c.at("largest_measured").as_number();
    sum += e * e;
    ++n;
  }
  // No training point simulated with the fitted material: no error to rank it by.
  f.relative_error = n > 0 ? std::sqrt(sum / n) : std::numeric_limits<double>::infinity();
  return f;
}

CsvTable samples_table(const BodyFields& f, const std::string& value, const std::string& unit,
                       Dimension d, const std::string& comment) {
  CsvTable t;
  t.add_comment(comment);
  std::vector<double> x, y, z, v;
  for (const LocationFit& l : f.fits) {
    x.push_back(l.position.x());
    y.push_back(l.position.y());
    z.push_back(l.position.z());
    v.push_back(value == "depth" ? l.depth : l.young);
  }
  t.add_quantity("x", "m", Dimension::Length, x);
  t.add_quantity("y", "m", Dimension::Length, y);
  t.add_quantity("z", "m", Dimension::Length, z);
  t.add_quantity(value, unit, d, v);
  return t;
}

}  // namespace

BodyFields read_location_fits(const Subject& s, const fs::path& fits) {
  BodyFields f;
  for (const Location& l : s.locations) f.fits.push_back(read_fit(s, l, fits / l.name));
  f.shape = 0;
  for (std::size_t i = 0; i < f.fits.size(); ++i) {
    if (s.shape_from.empty() ? f.fits[i].relative_error < f.fits[f.shape].relative_error
                             : f.fits[i].name == s.shape_from) {
      f.shape = i;
    }
  }
  return f;
}

void write_body_fields(const Subject& s, const BodyFields& f, const fs::path& out) {
  OutputFolder folder(out);  // (a failed write leaves no folder it created)
  const LocationFit& shape = f.fits[f.shape];
  OutputBatch batch;
  batch.add(out / "depths.csv") << format_csv(
      samples_table(f, "depth", "m", Dimension::Length,
                    fmt::format("subject {}: layer depth per poke location", s.name)));
  batch.add(out / "moduli.csv") << format_csv(samples_table(
      f, "youngs_modulus", "Pa", Dimension::Pressure,
      fmt::format("subject {}: small-strain Young's modulus of each location's fit", s.name)));
  batch.add(out / "material.json") << read_input_file(shape.folder / "material.json");

  Json locations = Json::array();
  for (const LocationFit& l : f.fits) {
    locations.push_back(
        {{"name", l.name},
         {"position_m", {l.position.x(), l.position.y(), l.position.z()}},
         {"youngs_modulus_Pa", l.young},
         {"poisson", l.poisson},
         {"depth_m", l.depth},
         {"depth", l.depth_searched ? "searched by the fit" : "measured (ultrasound)"},
         {"relative_error", std::isfinite(l.relative_error) ? Json(l.relative_error) : Json(nullptr)},
         {"termination", l.termination},
         {"fit", l.folder.string()}});
  }
  const Json fields = {
      {"palpa_body_fields", 1},
      {"subject", s.name},
      {"shape_from", shape.name},
      {"shape_rule", s.shape_from.empty() ? "the location with the lowest relative training error"
                                          : "named by the subject"},
      {"locations", locations}};
  batch.add(out / "fields.json") << format_json(fields, out / "fields.json");

  // The scenes: the design template's support and load, the subject's body.
  Json design = read_json_file(s.design);
  const JsonView dv(design, s.design.string());
  if (!dv.is_object() || !dv.has("palpa_design"))
    dv.fail("not a design scene", "a palpa design scene (\"palpa_design\": 1)");
  sim3d::absolutize_scene_paths(design, s.design);
  Json body = s.doc.at("body");
  sim3d::absolutize_scene_paths(body, s.file);
  body["depth"] = {{"samples", "depths.csv"}, {"column", "depth"}};
  body["stiffness"] = {{"samples", "moduli.csv"}, {"column", "youngs_modulus"}};
  body["material"] = "material.json";
  design["body"] = body;
  Json rest = design;
  rest.erase("palpa_design");
  rest.erase("design");
  rest.erase("baselines");
  rest["palpa_rest"] = 1;
  batch.add(out / "design.json") << format_json(design, out / "design.json");
  batch.add(out / "rest.json") << format_json(rest, out / "rest.json");
  batch.commit();
  folder.keep();
}

}  // namespace palpa::pipeline
