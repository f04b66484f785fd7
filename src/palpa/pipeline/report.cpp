// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/pipeline/report.hpp"

#include <fmt/format.h>

#include "palpa/core/error.hpp"
#include "palpa/core/json.hpp"
#include "palpa/design/output.hpp"

namespace palpa::pipeline {

namespace fs = std::filesystem;

namespace {

std::optional<Json> read_if_there(const fs::path& p) {
  if (!fs::is_regular_file(p)) return std::nullopt;
  return read_json_file(p);
}

std::string kpa(double pa) { return fmt::format("{:.3g} kPa", pa * 1e-3); }

// Runs `use` on a result file's JSON; a key missing or of the wrong type is
// an input error naming the file.
template <class F>
void from_result(const fs::path& file, F&& use) {
  try {
    use();
  } catch (const Json::exception& e) {
    throw_input_error(fmt::format("is not the result palpa writes there: {}", e.what()), in_file(file.string()),
                      "the file as palpa wrote it (run that step again)");
  }
}

}  // namespace

report::HtmlReport subject_report(const Subject& s, const fs::path& results) {
  const std::optional<Json> fields = read_if_there(results / "body" / "fields.json");
  const std::optional<Json> design = read_if_there(results / "design" / "summary.json");
  std::string headline = "no design yet";
  if (design) {
    from_result(results / "design" / "summary.json", [&] { headline = design::design_headline_text(*design); });
  }
  report::HtmlReport h(fmt::format("palpa subject {}", s.name),
                       fmt::format("{} poke locations · {} · {}", s.locations.size(), s.file.string(), headline));

  h.heading("Locations: measured and fitted");
  if (fields) from_result(results / "body" / "fields.json", [&] {
    std::vector<std::vector<std::string>> rows;
    for (const Json& l : fields->at("locations")) {
      const Json& p = l.at("position_m");
      rows.push_back({l.at("name").get<std::string>(),
                      fmt::format("{:.0f}, {:.0f}, {:.0f}", p[0].get<double>() * 1e3, p[1].get<double>() * 1e3,
                                  p[2].get<double>() * 1e3),
                      kpa(l.at("youngs_modulus_Pa").get<double>()), fmt::format("{:.3f}", l.at("poisson").get<double>()),
                      fmt::format("{:.1f} mm", l.at("depth_m").get<double>() * 1e3), l.at("depth").get<std::string>(),
                      l.at("relative_error").is_null()
                          ? std::string("-")
                          : fmt::format("{:.2f}%", 100.0 * l.at("relative_error").get<double>()),
                      l.at("termination").get<std::string>()});
    }
    h.table({"location", "position [mm]", "E (small strain)", "ν", "layer depth", "depth", "fit error", "fit"}, rows);
    h.paragraph(fmt::format(
        "Fit error: the RMS difference of the fitted and measured forces over the training curves, relative to "
        "each curve's largest force. The body's material is the shape fitted at {} ({}), scaled at every place "
        "to the modulus interpolated from the locations.",
        fields->at("shape_from").get<std::string>(), fields->at("shape_rule").get<std::string>()));
  });
  if (!fields) h.paragraph("The fits have not all finished: no body fields yet.");
  std::vector<std::pair<fs::path, std::string>> row;
  for (const Location& l : s.locations) {
    row.emplace_back(results / "fits" / l.name / "curves.svg", l.name + ": measured and fitted curves");
    if (row.size() == 2) {
      h.picture_files(row);
      row.clear();
    }
  }
  if (!row.empty()) h.picture_files(row);

  h.heading("The body carries the fits");
  h.picture_files({{results / "rest" / "body_depth.svg", "the soft layer's depth over the skin"},
                   {results / "rest" / "body_stiffness.svg", "its Young's modulus"}});

  h.heading("At rest on the initial support");
  const std::optional<Json> rest = read_if_there(results / "rest" / "summary.json");
  if (rest) from_result(results / "rest" / "summary.json", [&] {
    const Json& body = rest->at("pressure_map").at("body");
    h.table({"load", "body peak", "body PPI", "body mean", "contact area", "support peak"},
            {{fmt::format("{:.1f} N", rest->at("pressure_map_force_N").at("load").get<double>()),
              kpa(rest->at("peak_pressure_Pa").at("body").get<double>()),
              kpa(body.at("peak_pressure_index_Pa").get<double>()), kpa(body.at("mean_Pa").get<double>()),
              fmt::format("{:.1f} cm²", body.at("contact_area_m2").get<double>() * 1e4),
              kpa(rest->at("peak_pressure_Pa").at("support").get<double>())}});
  });
  h.paragraph("Pressures are the normal traction per deformed area, what a pressure-mapping mat between the body "
              "and the support would read; the two sides carry the same contact, drawn on the skin and on the "
              "support.");
  h.picture_files({{results / "rest" / "body_pressure.svg", "what the person feels"},
                   {results / "rest" / "support_pressure.svg", "what the support sees"}});

  h.heading("The support designed for this body");
  if (design) {
    h.paragraph(headline);
    from_result(results / "design" / "summary.json",
                [&] { design::add_design_sections(h, results / "design", *design); });
  } else {
    h.paragraph("The design has not finished.");
  }

  if (s.pressure) {
    h.heading("Measured against simulated (the initial support)");
    if (const std::optional<Json> c = read_if_there(results / "compare.json")) {
      std::vector<std::vector<std::string>> rows;
      for (const auto& [key, value] : c->items()) {
        if (value.is_number()) rows.push_back({key, fmt::format("{:.4g}", value.get<double>())});
      }
      h.table({"figure", "value"}, rows);
    } else {
      h.paragraph("The comparison has not run.");
    }
  }
  return h;
}

}  // namespace palpa::pipeline
