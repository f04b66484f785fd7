// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/pipeline/subject.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <set>
#include <tuple>

#include "palpa/core/error.hpp"
#include "palpa/core/input_file.hpp"
#include "palpa/core/units.hpp"
#include "palpa/fit/fit.hpp"
#include "palpa/fit/run.hpp"
#include "palpa/geometry/closest_point.hpp"
#include "palpa/geometry/format.hpp"
#include "palpa/rest/scene.hpp"
#include "palpa/sim3d/scene_json.hpp"

namespace palpa::pipeline {

namespace fs = std::filesystem;

namespace {

// The body keys a subject may give: a rest body made from a scan, less what
// the fits provide.
const std::vector<std::string> kBodyKeys = {
    "surface", "generate", "unit",        "scale",       "remove_self_intersections",
    "clip",    "cut",      "clamp_depth", "core_offset", "edge",      "refine",
    "density", "position", "rotation",    "element",     "stabilization"};

// The options of each acquisition a subject may pass on (as in `palpa acquire
// <kind> --help`, with '_' for '-').
const std::vector<std::string> kPokeOptions = {
    "force_columns", "laser_columns", "calibration_columns", "cutoff",
    "order",         "rest",          "rest_tolerance",      "max_gap",
    "saturation",    "force_window",  "laser_window",        "points",
    "no_tare"};
const std::vector<std::string> kUltrasoundOptions = {
    "force_columns", "pick_columns", "offset",         "no_align", "search",     "cutoff",
    "order",         "rest",         "rest_tolerance", "max_gap",  "saturation", "force_window"};
const std::vector<std::string> kPressureOptions = {
    "unit",         "trim",     "clip_run",       "method",           "reach",
    "max_distance", "no_clamp", "reading_column", "reference_column"};

bool usable_name(const std::string& n) {
  return !n.empty() && n.size() <= 64 && n.front() != '-' &&
         std::all_of(n.begin(), n.end(), [](char c) {
           return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_';
         });
}

std::string read_name(const JsonView& v, const std::string& what) {
  const std::string n = v.as_string();
  if (!usable_name(n)) {
    v.fail(fmt::format("{} name '{}'", what, n),
           "letters, digits, '-' and '_' (at most 64; it names a folder)");
  }
  return n;
}

// A file the subject names, resolved and checked to exist.
fs::path existing_file(const JsonView& v, const fs::path& subject_file, const std::string& who) {
  const fs::path p = sim3d::resolve_scene_path(subject_file, v.as_string()).lexically_normal();
  if (!fs::is_regular_file(p))
    v.fail(fmt::format("{}: no file {}", who, p.string()), "an existing file");
  return p;
}

// "options": {"laser_columns": "t:ms,dist:mm", "no_tare": true} → --laser-columns t:ms,dist:mm
// --no-tare
void append_options(const JsonView& parent, const std::vector<std::string>& allowed,
                    std::vector<std::string>& args) {
  const auto o = parent.find("options");
  if (!o) return;
  if (!o->is_object()) o->fail("not an object", "{\"option_name\": \"value\", ...}");
  o->expect_only(allowed);
  for (const auto& [key, value] : o->json().items()) {
    std::string flag = "--" + key;
    std::replace(flag.begin(), flag.end(), '_', '-');
    const JsonView v = o->at(key);
    // The switches ("no_tare" and the like) take true or false, the others a value.
    const bool flag_option = key.rfind("no_", 0) == 0;
    if (flag_option && !value.is_boolean()) v.fail("not true or false", "true or false");
    if (!flag_option && !value.is_string() && !value.is_number()) {
      v.fail("not a value", fmt::format("the value of {} as text or a number", flag));
    }
    if (value.is_boolean()) {
      if (value.get<bool>()) args.push_back(flag);
    } else if (value.is_number()) {
      args.push_back(flag);
      args.push_back(fmt::format("{}", v.as_number()));
    } else {
      args.push_back(flag);
      args.push_back(v.as_string());
    }
  }
}

std::string radius_tag(double radius) {
  return fmt::format("r{:.6g}mm", radius * 1e3);
}

std::string format_length(double metres) {
  return fmt::format("{} m", metres);
}

Poke read_poke(const JsonView& p, const fs::path& file, const std::string& who) {
  p.expect_only({"radius", "curve", "force", "laser", "calibration", "options"});
  Poke k;
  k.radius = sim3d::read_positive(p.at("radius"), Dimension::Length);
  k.tag = radius_tag(k.radius);
  const std::string here =
      fmt::format("{}, {} poke", who, format_quantity(k.radius, Dimension::Length));
  if (const auto c = p.find("curve")) {
    for (const char* key : {"force", "laser", "calibration", "options"}) {
      if (p.has(key))
        p.at(key).fail(fmt::format("{}: a ready curve takes no logs", here),
                       "\"curve\" alone, or the logs");
    }
    k.inputs.push_back(existing_file(*c, file, here));
    return k;
  }
  if (!p.has("force") || !p.has("laser")) {
    p.fail(fmt::format("{}: no logs", here),
           "\"force\" and \"laser\" logs (and \"calibration\" for a laser in "
           "volts), or a ready \"curve\"");
  }
  const fs::path force = existing_file(p.at("force"), file, here);
  const fs::path laser = existing_file(p.at("laser"), file, here);
  k.inputs = {force, laser};
  k.acquire_args = {"--force", force.string(), "--laser", laser.string()};
  if (const auto c = p.find("calibration")) {
    const fs::path cal = existing_file(*c, file, here);
    k.inputs.push_back(cal);
    k.acquire_args.insert(k.acquire_args.end(), {"--calibration", cal.string()});
  }
  append_options(p, kPokeOptions, k.acquire_args);
  return k;
}

Ultrasound read_ultrasound(const JsonView& u, const fs::path& file, const std::string& who) {
  u.expect_only({"force", "interfaces", "depth_interface", "options"});
  Ultrasound us;
  const fs::path force = existing_file(u.at("force"), file, who);
  us.inputs.push_back(force);
  us.acquire_args = {"--force", force.string()};
  const JsonView ifs = u.at("interfaces");
  if (!ifs.is_array() || ifs.size() == 0) {
    ifs.fail(fmt::format("{}: no interfaces", who),
             "[{\"name\": \"fat\", \"picks\": \"fat.csv\"}, ...], shallowest first");
  }
  std::set<std::string> names;
  for (std::size_t i = 0; i < ifs.size(); ++i) {
    const JsonView f = ifs.at(i);
    f.expect_only({"name", "picks"});
    const std::string name = read_name(f.at("name"), "interface");
    if (!names.insert(name).second)
      f.at("name").fail(fmt::format("{}: a second interface '{}'", who, name), "distinct names");
    const fs::path picks = existing_file(f.at("picks"), file, who);
    us.inputs.push_back(picks);
    us.acquire_args.insert(us.acquire_args.end(), {"--interface", name + "=" + picks.string()});
    us.depth_interface = name;  // the deepest by default
  }
  if (const auto d = u.find("depth_interface")) {
    us.depth_interface = d->as_string();
    if (names.count(us.depth_interface) == 0) {
      d->fail(fmt::format("{}: no interface '{}'", who, us.depth_interface),
              fmt::format("one of {}", fmt::join(names, ", ")));
    }
  }
  us.acquire_args.insert(us.acquire_args.end(), {"--depth-interface", us.depth_interface});
  append_options(u, kUltrasoundOptions, us.acquire_args);
  return us;
}

Location read_location(const JsonView& l, const fs::path& file, const std::string& subject) {
  l.expect_only({"name", "position", "pokes", "ultrasound", "depth_search"});
  Location loc;
  loc.name = read_name(l.at("name"), "location");
  const std::string who = fmt::format("subject '{}', location '{}'", subject, loc.name);
  loc.position = sim3d::read_quantity3(l.at("position"), Dimension::Length);
  const JsonView pokes = l.at("pokes");
  if (!pokes.is_array() || pokes.size() == 0)
    pokes.fail(fmt::format("{}: no pokes", who), "one poke per punch radius");
  for (std::size_t i = 0; i < pokes.size(); ++i) {
    Poke p = read_poke(pokes.at(i), file, who);
    for (const Poke& q : loc.pokes) {
      if (q.tag == p.tag) {
        pokes.at(i).at("radius").fail(fmt::format("{}: a second poke of radius {}", who,
                                                  format_quantity(p.radius, Dimension::Length)),
                                      "one poke per punch radius");
      }
    }
    loc.pokes.push_back(std::move(p));
  }
  const bool us = l.has("ultrasound"), search = l.has("depth_search");
  if (us == search) {
    l.fail(
        fmt::format("{}: {}", who, us ? "both an ultrasound and a depth search" : "no layer depth"),
        "\"ultrasound\" (the depth measured) or \"depth_search\" (the depths to search)");
  }
  if (us) loc.ultrasound = read_ultrasound(l.at("ultrasound"), file, who);
  if (search) {
    const JsonView d = l.at("depth_search");
    d.expect_only({"from", "to", "count"});
    DepthSearch s;
    s.from = sim3d::read_positive(d.at("from"), Dimension::Length);
    s.to = sim3d::read_positive(d.at("to"), Dimension::Length);
    s.count = static_cast<int>(d.at("count").as_integer());
    if (!(s.to > s.from) || s.count < 2 || s.count > 50) {
      d.fail(
          fmt::format("{}: depths {} to {} in {}", who, format_quantity(s.from, Dimension::Length),
                      format_quantity(s.to, Dimension::Length), s.count),
          "\"from\" below \"to\" and a count of 2 to 50");
    }
    loc.depth_search = s;
  }
  return loc;
}

void read_fit(const JsonView& f, Subject& s) {
  f.expect_only({"model", "poisson", "lateral_size", "contact", "mesh_level", "steps",
                 "max_iterations", "starts", "depth_from", "fix"});
  s.dataset = Json::object();
  if (const auto v = f.find("poisson")) {
    const double nu = v->as_number();
    if (!(nu > -1.0 && nu < 0.5))
      v->fail(fmt::format("a Poisson's ratio of {}", nu), "a ratio in (-1, 0.5)");
    s.dataset["poisson"] = nu;
  }
  if (const auto v = f.find("lateral_size"))
    s.dataset["lateral_size"] = format_length(sim3d::read_positive(*v, Dimension::Length));
  if (const auto v = f.find("contact")) {
    const std::string c = v->as_string();
    if (c != "stick" && c != "frictionless")
      v->fail(fmt::format("contact '{}'", c), "stick or frictionless");
    s.dataset["contact"] = c;
  }
  // Each value checked as palpa fit will check it, so that a subject check
  // finds what would fail only when the workflow runs the fit.
  const auto as_palpa_fit = [](const JsonView& v, const auto& check) {
    try {
      check();
    } catch (const Error& e) {
      v.fail(e.problem(), e.expected());
    }
  };
  if (const auto v = f.find("model")) {
    const std::string model = v->as_string();
    as_palpa_fit(*v, [&] { (void)fit::fit_options_from(model, "lm", "fbar"); });
    s.fit_args.insert(s.fit_args.end(), {"--model", model});
  }
  if (const auto v = f.find("depth_from")) {
    const std::string how = v->as_string();
    as_palpa_fit(*v, [&] { (void)fit::parse_depth_from(how); });
    s.fit_args.insert(s.fit_args.end(), {"--depth-from", how});
  }
  if (const auto v = f.find("fix")) {
    if (!v->is_array() || v->size() == 0) v->fail("not a list of parameter names", "[\"nu\"]");
    s.fit_args.push_back("--fix");
    for (std::size_t i = 0; i < v->size(); ++i) {
      const std::string name = v->at(i).as_string();
      const bool parameter = !name.empty() && std::isalpha(static_cast<unsigned char>(name.front())) &&
                             std::all_of(name.begin(), name.end(), [](char c) {
                               return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
                             });
      if (!parameter) v->at(i).fail(fmt::format("'{}'", name), "a parameter name of the model (\"nu\", \"E\", ...)");
      s.fit_args.push_back(name);
    }
  }
  for (const auto& [key, flag, range] :
       {std::tuple{"mesh_level", "--mesh-level", fit::bounds::mesh_level},
        std::tuple{"steps", "--steps", fit::bounds::steps},
        std::tuple{"max_iterations", "--max-iterations", fit::bounds::max_iterations},
        std::tuple{"starts", "--starts", fit::bounds::starts}}) {
    if (const auto v = f.find(key)) {
      const long long n = v->as_integer();
      if (!range.holds(static_cast<double>(n))) {
        v->fail(fmt::format("{}", n), fmt::format("a whole number from {:g} to {:g}", range.lo, range.hi));
      }
      s.fit_args.insert(s.fit_args.end(), {flag, std::to_string(n)});
    }
  }
}

Json paths(const std::vector<fs::path>& ps) {
  Json a = Json::array();
  for (const fs::path& p : ps) a.push_back(p.string());
  return a;
}

}  // namespace

Subject read_subject(const fs::path& file) {
  Subject s;
  s.file = fs::absolute(file).lexically_normal();
  s.doc = read_json_file(file);
  const JsonView root(s.doc, file.string());
  if (!root.is_object())
    root.fail("not a JSON object", "a subject file {\"palpa_subject\": 1, ...}");
  root.expect_only(
      {"palpa_subject", "name", "body", "locations", "fit", "shape_from", "design", "pressure"});
  if (root.at("palpa_subject").as_integer() != 1)
    root.at("palpa_subject").fail("an unknown version", "1");
  s.name = read_name(root.at("name"), "subject");
  const std::string who = fmt::format("subject '{}'", s.name);

  const JsonView body = root.at("body");
  if (!body.is_object()) body.fail("not an object", "a palpa rest body made from a scan");
  for (const char* k : {"depth", "material", "stiffness", "layer"}) {
    if (body.has(k)) {
      body.at(k).fail(fmt::format("{}: the body's {} comes from the fits", who, k),
                      "the scan and how to prepare it (the layer's depth, material and stiffness "
                      "are the fits')");
    }
  }
  body.expect_only(kBodyKeys);
  // Where the body stands, checked as palpa rest will read it.
  if (const auto v = body.find("position")) (void)sim3d::read_quantity3(*v, Dimension::Length);
  if (const auto v = body.find("rotation")) (void)sim3d::read_rotation(*v);
  // ... and how its layer will be made.
  (void)rest::read_layer_options(body);
  (void)rest::read_body_density(body);
  (void)sim3d::read_element(body);
  if (int(body.has("surface")) + int(body.has("generate")) != 1) {
    body.fail(fmt::format("{}: no scan", who), "exactly one of \"surface\" and \"generate\"");
  }
  if (const auto surf = body.find("surface")) existing_file(*surf, s.file, who);

  const JsonView locs = root.at("locations");
  if (!locs.is_array() || locs.size() == 0)
    locs.fail(fmt::format("{}: no locations", who), "at least one poke location");
  for (std::size_t i = 0; i < locs.size(); ++i) {
    Location l = read_location(locs.at(i), s.file, s.name);
    for (const Location& m : s.locations) {
      if (m.name == l.name)
        locs.at(i).at("name").fail(fmt::format("{}: a second location '{}'", who, l.name),
                                   "distinct names");
    }
    s.locations.push_back(std::move(l));
  }
  if (const auto f = root.find("fit")) {
    read_fit(*f, s);
  } else {
    s.dataset = Json::object();
  }
  if (const auto sf = root.find("shape_from")) {
    s.shape_from = sf->as_string();
    if (std::none_of(s.locations.begin(), s.locations.end(),
                     [&](const Location& l) { return l.name == s.shape_from; })) {
      sf->fail(fmt::format("{}: no location '{}'", who, s.shape_from),
               "one of the subject's locations");
    }
  }
  s.design = existing_file(root.at("design"), s.file, who);
  {
    Json design;
    try {
      design = read_json_file(s.design);
    } catch (const Error& e) {
      root.at("design").fail(fmt::format("{}: its design scene cannot be read: {}", who, e.what()),
                             "a palpa design scene ({\"palpa_design\": 1, ...})");
    }
    if (!design.is_object() || !design.contains("palpa_design")) {
      root.at("design").fail(fmt::format("{}: {} is not a design scene", who, s.design.string()),
                             "a palpa design scene ({\"palpa_design\": 1, ...}) whose body the fits replace");
    }
  }
  if (const auto p = root.find("pressure")) {
    p->expect_only({"locations", "samples", "load", "options"});
    PressureLogs logs;
    const fs::path locations = existing_file(p->at("locations"), s.file, who + ", pressure");
    const fs::path samples = existing_file(p->at("samples"), s.file, who + ", pressure");
    const double load = sim3d::read_positive(p->at("load"), Dimension::Force);
    logs.inputs = {locations, samples};
    logs.acquire_args = {"--locations",    locations.string(), "--samples",
                         samples.string(), "--load",           fmt::format("{}N", load)};
    append_options(*p, kPressureOptions, logs.acquire_args);
    s.pressure = std::move(logs);
  }
  return s;
}

void check_locations_on_body(const Subject& s, double max_distance) {
  const JsonView body(s.doc.at("body"), s.file.string(), "body");
  std::string source;
  const SurfaceMesh skin = rest::read_body_surface(body, s.file, source);
  for (std::size_t i = 0; i < s.locations.size(); ++i) {
    const Location& l = s.locations[i];
    const geometry::SurfacePoint p = geometry::closest_point(skin, l.position);
    if (p.distance > max_distance) {
      const JsonView where(s.doc.at("locations").at(i).at("position"), s.file.string(),
                           fmt::format("locations[{}].position", i));
      where.fail(
          fmt::format(
              "subject '{}', location '{}' at {} is {} from the skin of {} (nearest skin point {})",
              s.name, l.name, geometry::format_point(l.position),
              format_quantity(p.distance, Dimension::Length), source,
              geometry::format_point(p.position)),
          fmt::format("a point on the body's surface (within {}, in the scan's frame)",
                      format_quantity(max_distance, Dimension::Length)));
    }
  }
}

std::vector<Subject> read_subjects(const fs::path& file) {
  const Json doc = read_json_file(file);
  const JsonView root(doc, file.string());
  if (!root.is_object() || !root.has("palpa_cohort")) return {read_subject(file)};
  root.expect_only({"palpa_cohort", "subjects"});
  if (root.at("palpa_cohort").as_integer() != 1)
    root.at("palpa_cohort").fail("an unknown version", "1");
  const JsonView list = root.at("subjects");
  if (!list.is_array() || list.size() == 0) list.fail("no subjects", "[\"s01/subject.json\", ...]");
  std::vector<Subject> subjects;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const fs::path p = sim3d::resolve_scene_path(file, list.at(i).as_string());
    if (!fs::is_regular_file(p))
      list.at(i).fail(fmt::format("no file {}", p.string()), "a subject file");
    Subject s = read_subject(p);
    for (const Subject& t : subjects) {
      if (t.name == s.name) {
        list.at(i).fail(fmt::format("subject '{}' of {} has the name of {}'s", s.name,
                                    s.file.string(), t.file.string()),
                        "one name per subject (it names the subject's output folder)");
      }
    }
    subjects.push_back(std::move(s));
  }
  return subjects;
}

Json cohort_plan(const std::vector<Subject>& subjects) {
  Json list = Json::array();
  for (const Subject& s : subjects) list.push_back(subject_plan(s));
  return {{"palpa_plan", 1}, {"subjects", list}};
}

const Location& find_location(const Subject& s, const std::string& name) {
  for (const Location& l : s.locations) {
    if (l.name == name) return l;
  }
  std::vector<std::string> names;
  for (const Location& l : s.locations) names.push_back(l.name);
  throw_input_error(fmt::format("subject '{}' has no location '{}'", s.name, name),
                    ErrorContext{s.file.string(), 0, 0, ""},
                    fmt::format("one of {}", fmt::join(names, ", ")));
}

Json subject_plan(const Subject& s) {
  Json locations = Json::array();
  for (const Location& l : s.locations) {
    Json pokes = Json::array();
    for (const Poke& p : l.pokes) {
      pokes.push_back(
          {{"tag", p.tag},
           {"radius_m", p.radius},
           {"inputs", paths(p.inputs)},
           {"curve", p.acquire_args.empty() ? Json(p.inputs.front().string()) : Json(nullptr)},
           {"acquire", p.acquire_args}});
    }
    Json loc = {{"name", l.name},
                {"position_m", {l.position.x(), l.position.y(), l.position.z()}},
                {"pokes", pokes},
                {"ultrasound", nullptr},
                {"depth_search", nullptr}};
    if (l.ultrasound)
      loc["ultrasound"] = {{"inputs", paths(l.ultrasound->inputs)},
                           {"acquire", l.ultrasound->acquire_args}};
    if (l.depth_search) {
      loc["depth_search"] = {{"from_m", l.depth_search->from},
                             {"to_m", l.depth_search->to},
                             {"count", l.depth_search->count}};
    }
    locations.push_back(loc);
  }
  Json plan = {{"palpa_subject_plan", 1}, {"subject", s.name}, {"file", s.file.string()},
               {"locations", locations},  {"fit", s.fit_args}, {"design", s.design.string()},
               {"pressure", nullptr}};
  if (s.pressure)
    plan["pressure"] = {{"inputs", paths(s.pressure->inputs)},
                        {"acquire", s.pressure->acquire_args}};
  return plan;
}

Json location_dataset(const Subject& s, const std::string& location, const fs::path& curve_dir,
                      const std::optional<fs::path>& ultrasound_summary,
                      const fs::path& dataset_dir) {
  const Location& l = find_location(s, location);
  const std::string who = fmt::format("subject '{}', location '{}'", s.name, l.name);
  Json d = {{"palpa_dataset", 1}, {"sample", who}, {"test", "indentation"}};
  if (l.ultrasound) {
    if (!ultrasound_summary) {
      throw_input_error(
          fmt::format("{} has an ultrasound: its depth comes from the ultrasound's summary", who),
          ErrorContext{s.file.string(), 0, 0, ""},
          "--ultrasound SUMMARY.json (palpa acquire ultrasound --summary)");
    }
    const Json u = read_json_file(*ultrasound_summary);
    const std::string key = l.ultrasound->depth_interface + "_m";
    const JsonView summary(u, ultrasound_summary->string());
    const auto depths = summary.find("rest_depth");
    if (!depths || !depths->has(key)) {
      summary.fail(
          fmt::format("{}: no rest depth of interface '{}'", who, l.ultrasound->depth_interface),
          "the summary of palpa acquire ultrasound for this location");
    }
    const double depth = depths->at(key).as_number();
    if (!(depth > 0.0))
      depths->at(key).fail(fmt::format("{}: a rest depth of {} m", who, depth), "a depth > 0");
    d["layer_depth"] = format_length(depth);
  } else {
    if (ultrasound_summary) {
      throw_input_error(fmt::format("{} has no ultrasound: its depth is searched", who),
                        ErrorContext{ultrasound_summary->string(), 0, 0, ""},
                        "no --ultrasound for this location");
    }
    d["layer_depth"] = {{"from", format_length(l.depth_search->from)},
                        {"to", format_length(l.depth_search->to)},
                        {"count", l.depth_search->count}};
  }
  for (const auto& [k, v] : s.dataset.items()) d[k] = v;
  Json curves = Json::array();
  for (const Poke& p : l.pokes) {
    const fs::path c = curve_dir / (p.tag + ".csv");
    if (!fs::is_regular_file(c)) {
      throw_input_error(fmt::format("{}: no curve for the {} poke", who,
                                    format_quantity(p.radius, Dimension::Length)),
                        ErrorContext{c.string(), 0, 0, ""},
                        "the curve palpa acquire poke wrote for it");
    }
    remember_input(c);  // the dataset written must not replace one of its curves
    curves.push_back(
        {{"file", fs::proximate(fs::absolute(c), fs::absolute(dataset_dir)).generic_string()},
         {"radius", format_length(p.radius)},
         {"role", "train"}});
  }
  d["curves"] = curves;
  return d;
}

}  // namespace palpa::pipeline
