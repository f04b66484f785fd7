// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/fit/dataset.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "palpa/core/json.hpp"
#include "palpa/io/csv.hpp"

namespace palpa::fit {

std::string_view to_string(TestKind t) noexcept {
  switch (t) {
    case TestKind::Indentation: return "indentation";
    case TestKind::Compression: return "compression";
    case TestKind::Homogeneous: return "homogeneous";
  }
  return "?";
}

std::string_view to_string(CurveRole r) noexcept {
  return r == CurveRole::Train ? "train" : "validate";
}

std::size_t Dataset::count(CurveRole r) const noexcept {
  return static_cast<std::size_t>(
      std::count_if(curves.begin(), curves.end(), [r](const MeasuredCurve& c) { return c.role == r; }));
}

namespace {

TestKind parse_test(const JsonView& v) {
  const std::string s = v.as_string();
  if (s == "indentation") return TestKind::Indentation;
  if (s == "compression") return TestKind::Compression;
  if (s == "homogeneous") return TestKind::Homogeneous;
  v.fail(fmt::format("unknown test '{}'", s), "\"indentation\", \"compression\" or \"homogeneous\"");
}

// A layer, a sample or a punch is at most a metre across: beyond, it is a
// slip of the unit (and at 1e300 m the mesh's cells round to nothing).
constexpr double kMaxLength = 1.0;

void refuse_over_a_metre(const JsonView& v, double length, const std::string& what) {
  if (!(length <= kMaxLength)) v.fail(fmt::format("{} of {:.4g} m is over a metre", what, length), "at most 1 m");
}

std::vector<double> parse_layer_depths(const JsonView& v) {
  std::vector<double> depths;
  if (v.is_array()) {
    for (std::size_t i = 0; i < v.size(); ++i) depths.push_back(v.at(i).as_quantity(Dimension::Length));
    if (depths.empty()) v.fail("no depth guesses", "at least one layer depth");
  } else if (v.is_object()) {
    v.expect_only({"from", "to", "count"});
    const double from = v.at("from").as_quantity(Dimension::Length);
    const double to = v.at("to").as_quantity(Dimension::Length);
    const long long count = v.at("count").as_integer();
    if (count < 2 || count > 64) v.at("count").fail(fmt::format("{} guesses", count), "2 to 64 guesses");
    if (!(to > from)) v.at("to").fail("the range is empty", "\"to\" greater than \"from\"");
    for (long long k = 0; k < count; ++k)
      depths.push_back(from + (to - from) * static_cast<double>(k) / static_cast<double>(count - 1));
  } else {
    depths.push_back(v.as_quantity(Dimension::Length));
  }
  for (std::size_t i = 0; i < depths.size(); ++i) {
    if (!(depths[i] > 0.0)) v.fail(fmt::format("layer depth {} m is not positive", depths[i]), "positive depths");
    refuse_over_a_metre(v, depths[i], "a layer depth");
    if (i > 0 && !(depths[i] > depths[i - 1]))
      v.fail("the depth guesses are not increasing", "increasing layer depths");
  }
  return depths;
}

axisym::PunchContact parse_contact(const JsonView& v, TestKind test) {
  const std::string s = v.as_string();
  if (s == "frictionless") return axisym::PunchContact::Frictionless;
  if (test == TestKind::Compression) {
    if (s == "bonded") return axisym::PunchContact::Stick;
    v.fail(fmt::format("unknown platen contact '{}'", s), "\"bonded\" or \"frictionless\"");
  }
  if (s == "stick") return axisym::PunchContact::Stick;
  v.fail(fmt::format("unknown punch contact '{}'", s), "\"stick\" or \"frictionless\"");
}

// Reads one curve file into (x, y) in SI and checks it.
void read_curve_file(MeasuredCurve& c, TestKind test, const ErrorContext& where) {
  if (!std::filesystem::exists(c.file)) {
    throw_input_error(fmt::format("curve file '{}' does not exist", c.file.string()), where,
                      "a CSV file (relative paths resolve against the dataset's folder)");
  }
  const CsvTable t = read_csv(c.file);
  const std::string src = c.file.string();
  std::string ycol;
  if (test == TestKind::Homogeneous) {
    const bool shear = c.load_case == material::LoadCase::SimpleShear;
    const std::string xcol = shear ? "shear" : "stretch";
    c.x = t.column(xcol);
    c.y = t.quantity("stress", Dimension::Pressure);
    ycol = "stress";
    for (std::size_t i = 0; i < c.x.size(); ++i) {
      if (!shear && !(c.x[i] > 0.0)) {
        throw_input_error(fmt::format("stretch {} is not positive", c.x[i]), t.context_of(i, xcol),
                          "stretches > 0 (1 = rest)");
      }
    }
  } else {
    c.x = t.quantity("indentation", Dimension::Length);
    c.y = t.quantity("force", Dimension::Force);
    ycol = "force";
    if (c.x.front() < 0.0) {
      throw_input_error(fmt::format("indentation starts at {} m, below 0", c.x.front()),
                        t.context_of(0, t.names().front()), "indentation >= 0 (0 = just touching)");
    }
    for (std::size_t i = 1; i < c.x.size(); ++i) {
      if (!(c.x[i] > c.x[i - 1])) {
        throw_input_error(fmt::format("indentation {} m does not increase (previous {} m)", c.x[i], c.x[i - 1]),
                          t.context_of(i, t.names().front()),
                          "strictly increasing indentation (the loading part of a poke)");
      }
    }
    const double fmax = *std::max_element(c.y.begin(), c.y.end());
    const auto force_column = std::find_if(t.names().begin(), t.names().end(),
                                           [](const std::string& n) { return n.rfind("force_", 0) == 0; });
    for (std::size_t i = 0; i < c.y.size(); ++i) {
      if (c.y[i] < -0.02 * std::max(fmax, 0.0) || (fmax <= 0.0 && c.y[i] < 0.0)) {
        throw_input_error(fmt::format("force {} N is negative", c.y[i]), t.context_of(i, *force_column),
                          "pushing forces >= 0 (compression positive)");
      }
    }
    if (!(fmax > 0.0)) throw_input_error("every force is zero", ErrorContext{src, 0, 0, "force"}, "a loading curve");
  }
  if (c.x.size() < 3) {
    throw_input_error(fmt::format("{} points", c.x.size()), ErrorContext{src, 0, 0, ""}, "at least 3 points per curve");
  }
  if (test == TestKind::Homogeneous) {
    for (std::size_t i = 1; i < c.x.size(); ++i) {
      if (c.x[i] == c.x[i - 1]) {
        throw_input_error("repeated load value", t.context_of(i, t.names().front()), "distinct load values");
      }
    }
  }
}

}  // namespace

Dataset read_dataset(const std::filesystem::path& path) {
  const Json j = read_json_file(path);
  const JsonView root(j, path.string());
  if (!root.is_object()) root.fail("not a JSON object", "a palpa dataset object");
  const auto tag = root.find("palpa_dataset");
  if (!tag) root.fail("missing \"palpa_dataset\"", "\"palpa_dataset\": 1");
  if (tag->as_integer() != 1) tag->fail(fmt::format("format {}", tag->as_integer()), "format 1");

  Dataset d;
  d.file = path;
  d.test = parse_test(root.at("test"));
  std::vector<std::string> allowed{"palpa_dataset", "sample", "test", "contact", "poisson", "curves", "notes"};
  if (d.test == TestKind::Indentation) {
    allowed.insert(allowed.end(), {"layer_depth", "lateral_size"});
  } else if (d.test == TestKind::Compression) {
    allowed.insert(allowed.end(), {"sample_radius", "sample_height"});
  }
  root.expect_only(allowed);
  if (auto s = root.find("sample")) d.sample = s->as_string();
  if (auto p = root.find("poisson")) {
    d.poisson = p->as_number();
    if (!(d.poisson > -0.99 && d.poisson < 0.4999)) p->fail(fmt::format("{}", d.poisson), "-0.99 < nu < 0.4999");
  }

  if (d.test == TestKind::Indentation) {
    d.layer_depths = parse_layer_depths(root.at("layer_depth"));
    if (auto l = root.find("lateral_size")) {
      d.lateral_size = l->as_quantity(Dimension::Length);
      if (!(*d.lateral_size > 0.0)) l->fail("not positive", "the sample's width");
      refuse_over_a_metre(*l, *d.lateral_size, "a lateral size");
    }
    d.contact = parse_contact(root.at("contact"), d.test);
  } else if (d.test == TestKind::Compression) {
    d.sample_radius = root.at("sample_radius").as_quantity(Dimension::Length);
    d.layer_depths = {root.at("sample_height").as_quantity(Dimension::Length)};
    if (!(d.sample_radius > 0.0)) root.at("sample_radius").fail("not positive", "a positive radius");
    if (!(d.layer_depths[0] > 0.0)) root.at("sample_height").fail("not positive", "a positive height");
    refuse_over_a_metre(root.at("sample_radius"), d.sample_radius, "a sample radius");
    refuse_over_a_metre(root.at("sample_height"), d.layer_depths[0], "a sample height");
    d.contact = parse_contact(root.at("contact"), d.test);
  } else {
    d.layer_depths = {0.0};  // one fit, no geometry
  }

  const JsonView curves = root.at("curves");
  if (!curves.is_array()) curves.fail("not an array", "a list of curves");
  const std::filesystem::path folder = path.parent_path();
  for (std::size_t i = 0; i < curves.size(); ++i) {
    const JsonView cv = curves.at(i);
    MeasuredCurve c;
    std::vector<std::string> keys{"file", "role", "name"};
    if (d.test == TestKind::Indentation) keys.push_back("radius");
    if (d.test == TestKind::Homogeneous) keys.push_back("load_case");
    cv.expect_only(keys);
    const std::filesystem::path f = cv.at("file").as_string();
    c.file = f.is_absolute() ? f : folder / f;
    c.name = cv.has("name") ? cv.at("name").as_string() : c.file.stem().string();
    const std::string role = cv.at("role").as_string();
    if (role == "train") {
      c.role = CurveRole::Train;
    } else if (role == "validate") {
      c.role = CurveRole::Validate;
    } else {
      cv.at("role").fail(fmt::format("unknown role '{}'", role), "\"train\" or \"validate\"");
    }
    if (d.test == TestKind::Indentation) {
      c.radius = cv.at("radius").as_quantity(Dimension::Length);
      if (!(c.radius > 0.0)) cv.at("radius").fail("not positive", "a positive punch radius");
      refuse_over_a_metre(cv.at("radius"), c.radius, "a punch radius");
      if (d.lateral_size && !(c.radius < 0.5 * *d.lateral_size)) {
        cv.at("radius").fail(fmt::format("punch radius {} mm is not below half the sample's lateral size {} mm",
                                         c.radius * 1e3, *d.lateral_size * 1e3),
                             "a punch smaller than the sample");
      }
    } else if (d.test == TestKind::Compression) {
      c.radius = d.sample_radius;
    } else {
      const JsonView lc = cv.at("load_case");
      try {
        c.load_case = material::parse_load_case(lc.as_string());
      } catch (const Error& e) {
        lc.fail(e.problem(), e.expected());
      }
    }
    read_curve_file(c, d.test, cv.at("file").context());
    if (d.test != TestKind::Homogeneous) {
      const double deepest = c.x.back();
      if (!(deepest < 0.9 * d.layer_depths.front())) {
        cv.at("file").fail(fmt::format("the curve reaches {} mm, not below 90% of the layer depth {} mm",
                                       deepest * 1e3, d.layer_depths.front() * 1e3),
                           "indentation well below the layer depth");
      }
    }
    d.curves.push_back(std::move(c));
  }
  if (d.curves.empty()) curves.fail("no curves", "at least one curve");
  // Each curve's outputs are named after it (curves/<name>.csv).
  for (std::size_t i = 0; i < d.curves.size(); ++i) {
    const JsonView cv = curves.at(i);
    const JsonView where = cv.has("name") ? cv.at("name") : cv.at("file");
    const std::string& name = d.curves[i].name;
    if (name.empty() || name == "." || name == ".." || name.find_first_of("/\\") != std::string::npos) {
      where.fail(fmt::format("curve name '{}' cannot name its output file", name),
                 "a \"name\" without '/' or '\\'");
    }
    for (std::size_t before = 0; before < i; ++before) {
      if (d.curves[before].name == name) {
        where.fail(fmt::format("curves {} ({}) and {} ({}) are both named '{}', and their outputs would be one file",
                               before + 1, d.curves[before].file.string(), i + 1, d.curves[i].file.string(), name),
                   "a distinct \"name\" for each curve");
      }
    }
  }
  if (d.count(CurveRole::Train) == 0) curves.fail("no curve has role \"train\"", "at least one training curve");
  return d;
}

}  // namespace palpa::fit
