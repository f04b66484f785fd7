// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa material: write a material file, show one, list models, and write
// homogeneous stress–stretch curves.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <map>
#include <optional>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/text.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/material/checks.hpp"
#include "palpa/material/homogeneous.hpp"
#include "palpa/material/material_file.hpp"
#include "palpa/material/models.hpp"
#include "palpa/material/spline_material.hpp"

namespace palpa::cli {

namespace {

using namespace palpa::material;

// "lo:hi" -> (lo, hi), plain numbers.
std::pair<double, double> parse_range(const std::string& text, const std::string& option) {
  const auto parts = split(text, ':');
  ErrorContext where;
  where.field = fmt::format("option {}", option);
  if (parts.size() != 2) throw_input_error(fmt::format("'{}' is not a range", text), where, "LOW:HIGH, e.g. 0.6:1.6");
  const auto lo = parse_finite_double(parts[0]);
  const auto hi = parse_finite_double(parts[1]);
  if (!lo || !hi || !(*hi > *lo)) {
    throw_input_error(fmt::format("'{}' is not an increasing range of numbers", text), where,
                      "LOW:HIGH with LOW < HIGH, e.g. 0.6:1.6");
  }
  return {*lo, *hi};
}

struct CreateOptions {
  std::string model = "neo-hookean-volume";
  std::string output;
  std::string from;
  int knots = 8;
  std::string f_range = "0.5:2";
  std::string g_range = "0.4:2.5";
  std::string h_range = "0.6:1.6";
  std::vector<std::string> mu;
  std::vector<double> alpha;
  // Scalar parameters by option name, SI.
  std::map<std::string, double> values;
  std::map<std::string, CLI::Option*> options;
};

double required(const CreateOptions& o, const std::string& name) {
  const auto it = o.values.find(name);
  if (it == o.values.end() || o.options.at(name)->count() == 0) {
    throw_input_error(fmt::format("model '{}' needs --{}", o.model, name), ErrorContext{},
                      fmt::format("--{} with its value", name));
  }
  return it->second;
}

double optional(const CreateOptions& o, const std::string& name, double fallback) {
  return o.options.at(name)->count() > 0 ? o.values.at(name) : fallback;
}

// Refuses options that do not belong to the chosen model.
void only(const CreateOptions& o, std::initializer_list<const char*> allowed) {
  for (const auto& [name, opt] : o.options) {
    if (opt->count() == 0) continue;
    bool ok = false;
    for (const char* a : allowed) ok = ok || name == a;
    if (!ok) {
      std::string list;
      for (const char* a : allowed) list += (list.empty() ? "--" : ", --") + std::string(a);
      throw_input_error(fmt::format("--{} does not apply to model '{}'", name, o.model),
                        ErrorContext{}, list.empty() ? "no parameter options" : list);
    }
  }
}

std::unique_ptr<Material> build_material(const CreateOptions& o) {
  const std::string& m = o.model;
  if (m != "ogden" && (!o.mu.empty() || !o.alpha.empty())) {
    throw_input_error(fmt::format("--mu and --alpha do not apply to model '{}'", m), ErrorContext{},
                      "--model ogden for Ogden parameters");
  }
  if (m != "spline" && !o.from.empty()) {
    throw_input_error(fmt::format("--from does not apply to model '{}'", m), ErrorContext{},
                      "--model spline --from material.json");
  }
  if (m == "neo-hookean" || m == "stvk" || m == "corotational") {
    only(o, {"E", "nu"});
    const double e = required(o, "E");
    const double nu = required(o, "nu");
    if (m == "neo-hookean") return std::make_unique<NeoHookean>(e, nu);
    if (m == "stvk") return std::make_unique<StVenantKirchhoff>(e, nu);
    return std::make_unique<Corotational>(e, nu);
  }
  if (m == "neo-hookean-volume") {
    only(o, {"E", "nu", "volume-share"});
    return std::make_unique<NeoHookean>(NeoHookean::with_volume_term(
        required(o, "E"), required(o, "nu"), optional(o, "volume-share", 0.5)));
  }
  if (m == "neo-hookean-isochoric") {
    // Either the native C10, D1, or E and nu converted (C10 = mu/2, D1 = 2/K).
    if (o.options.at("E")->count() > 0 || o.options.at("nu")->count() > 0) {
      only(o, {"E", "nu"});
      const ElasticConstants l = lame_from_young(required(o, "E"), required(o, "nu"));
      return std::make_unique<IsochoricInvariant>(IsochoricInvariant::neo_hookean(l.mu / 2.0, 2.0 / l.bulk()));
    }
    only(o, {"C10", "D1"});
    return std::make_unique<IsochoricInvariant>(
        IsochoricInvariant::neo_hookean(required(o, "C10"), required(o, "D1")));
  }
  if (m == "mooney-rivlin") {
    only(o, {"C10", "C01", "D1"});
    return std::make_unique<IsochoricInvariant>(IsochoricInvariant::mooney_rivlin(
        required(o, "C10"), required(o, "C01"), required(o, "D1")));
  }
  if (m == "yeoh") {
    only(o, {"C10", "C20", "C30", "D1"});
    return std::make_unique<IsochoricInvariant>(IsochoricInvariant::yeoh(
        required(o, "C10"), optional(o, "C20", 0.0), optional(o, "C30", 0.0), required(o, "D1")));
  }
  if (m == "ogden") {
    only(o, {"nu"});
    if (o.mu.empty() || o.alpha.empty()) {
      throw_input_error("model 'ogden' needs --mu and --alpha", ErrorContext{},
                        "--mu 6kPa,-0.5kPa --alpha 4.7,-2 --nu 0.45");
    }
    std::vector<double> mu;
    for (const auto& text : o.mu) {
      mu.push_back(parse_quantity(text, Dimension::Pressure, ErrorContext{"", 0, 0, "option --mu"}));
    }
    return std::make_unique<Ogden>(std::move(mu), o.alpha, required(o, "nu"));
  }
  if (m == "spline") {
    only(o, {});
    if (o.from.empty()) {
      throw_input_error("model 'spline' is built from another material", ErrorContext{},
                        "--from material.json (the material the spline reproduces)");
    }
    const MaterialFile source = read_material_file(o.from);
    SplineLayout layout;
    const auto range = [&](const std::string& text, const std::string& name) {
      const auto [lo, hi] = parse_range(text, name);
      return SplineRange{lo, hi, o.knots};
    };
    layout.f = range(o.f_range, "--f-range");
    layout.g = range(o.g_range, "--g-range");
    layout.h = range(o.h_range, "--h-range");
    return std::make_unique<SplineMaterial>(SplineMaterial::from_model(*source.material, layout));
  }
  std::string names;
  for (const auto& info : known_models()) names += (names.empty() ? "" : ", ") + std::string(info.name);
  throw_input_error(fmt::format("unknown model '{}'", m), ErrorContext{"", 0, 0, "option --model"},
                    fmt::format("one of: {}", names));
}

void show(const std::string& path) {
  const MaterialFile f = read_material_file(path);
  const Material& m = *f.material;
  fmt::print("{}\n  model: {}\n  {}\n", path, m.model(), m.description());
  fmt::print("parameters:\n");
  const Eigen::VectorXd theta = m.params();
  if (m.model() == "spline") {
    const Json j = material_to_json(m);
    for (const char* part : {"f", "g", "h"}) {
      const auto& knots = j["parameters"][part]["knots"];
      fmt::print("  {}: {} knots from {:.4g} to {:.4g}\n", part, knots.size(), knots.front().get<double>(),
                 knots.back().get<double>());
    }
  } else {
    for (Eigen::Index k = 0; k < m.num_params(); ++k) {
      const ParamInfo info = m.param_info(k);
      fmt::print("  {:<14} {:<16} {}\n", info.name, format_quantity(theta[k], info.dimension), info.meaning);
    }
  }
  const MaterialCheck c = check_material(m);
  fmt::print("small strain: E = {}, nu = {:.4g}, shear modulus = {}, bulk modulus = {}\n",
             format_quantity(c.small_strain.young(), Dimension::Pressure), c.small_strain.poisson(),
             format_quantity(c.small_strain.mu, Dimension::Pressure),
             format_quantity(c.small_strain.bulk(), Dimension::Pressure));
  if (c.problems.empty()) {
    fmt::print("checks: stress-free at rest, stable at rest, stable in uniaxial, equibiaxial "
               "and shear loading for stretches 0.5 to 2\n");
  } else {
    for (const auto& p : c.problems) fmt::print("warning: {}\n", p);
  }
  if (!f.provenance.created_by.empty() || !f.provenance.method.empty()) {
    fmt::print("provenance: {} {} {}", f.provenance.method, f.provenance.created_by, f.provenance.created);
    if (f.provenance.objective) fmt::print(", objective {:.6g}", *f.provenance.objective);
    fmt::print("\n");
  }
}

struct CurveOptions {
  std::string input;
  std::string output;
  std::string test = "uniaxial";
  std::string stretch = "0.6:1.6";
  std::string shear = "-0.5:0.5";
  int points = 101;
};

void curve(const CurveOptions& o, const CLI::Option* stretch_opt, const CLI::Option* shear_opt) {
  const MaterialFile f = read_material_file(o.input);
  const LoadCase lc = parse_load_case(o.test);
  if (lc == LoadCase::SimpleShear && stretch_opt->count() > 0) {
    throw_input_error("--stretch is for uniaxial and equibiaxial tests", ErrorContext{},
                      "--shear LOW:HIGH for the shear test");
  }
  if (lc != LoadCase::SimpleShear && shear_opt->count() > 0) {
    throw_input_error("--shear is for the shear test", ErrorContext{}, "--stretch LOW:HIGH");
  }
  const auto [lo, hi] = lc == LoadCase::SimpleShear ? parse_range(o.shear, "--shear")
                                                    : parse_range(o.stretch, "--stretch");
  if (lc != LoadCase::SimpleShear && !(lo > 0.0)) {
    throw_input_error(fmt::format("stretch range starts at {}", lo), ErrorContext{"", 0, 0, "option --stretch"},
                      "stretches > 0");
  }
  const auto pts = homogeneous_curve(*f.material, lc, lo, hi, o.points);
  CsvTable t;
  t.add_comment(fmt::format("{} test of {} ({})", o.test, o.input, f.material->model()));
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
  if (lc == LoadCase::SimpleShear) {
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
  write_csv(o.output, t);
  spdlog::info("wrote {}: {} test of {} ({}), {} points, {} {} to {}", o.output, o.test, o.input,
               f.material->model(), pts.size(), lc == LoadCase::SimpleShear ? "shear" : "stretch", lo, hi);
}

}  // namespace

void add_material_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "material",
      "Write a material file (material.json), or show one, list the models, and write "
      "stress-stretch curves.\n"
      "  palpa material --model neo-hookean --E 10kPa --nu 0.45 -o m.json\n"
      "  palpa material --model ogden --mu 6kPa,-0.5kPa --alpha 4.7,-2 --nu 0.45 -o o.json\n"
      "  palpa material --model spline --from m.json --knots 10 -o s.json\n"
      "  palpa material show m.json\n"
      "  palpa material curve m.json --test uniaxial --stretch 0.6:1.6 -o c.csv");
  cmd->require_subcommand(0, 1);
  auto opts = std::make_shared<CreateOptions>();
  cmd->add_option("--model", opts->model,
                  "Model name (see `palpa material models`); default neo-hookean-volume");
  cmd->add_option("-o,--output", opts->output, "Material file to write (.json)");
  const auto quantity = [&](const std::string& name, Dimension d, const std::string& help) {
    opts->values[name] = 0.0;
    opts->options[name] = add_quantity_option(*cmd, "--" + name, opts->values[name], d, help);
  };
  quantity("E", Dimension::Pressure, "Young's modulus at small strain");
  quantity("nu", Dimension::Dimensionless, "Poisson's ratio at small strain, -1 < nu < 0.5");
  quantity("volume-share", Dimension::Dimensionless,
           "neo-hookean-volume: share of Lame's lambda in the (J-1)^2 term, 0..1 (default 0.5)");
  quantity("C10", Dimension::Pressure, "coefficient of (Ibar1 - 3)");
  quantity("C01", Dimension::Pressure, "mooney-rivlin: coefficient of (Ibar2 - 3)");
  quantity("C20", Dimension::Pressure, "yeoh: coefficient of (Ibar1 - 3)^2 (default 0)");
  quantity("C30", Dimension::Pressure, "yeoh: coefficient of (Ibar1 - 3)^3 (default 0)");
  quantity("D1", Dimension::Compliance, "volumetric compliance, bulk modulus K = 2/D1");
  cmd->add_option("--mu", opts->mu, "ogden: moduli mu_p with units, comma-separated")->delimiter(',');
  cmd->add_option("--alpha", opts->alpha, "ogden: exponents alpha_p, comma-separated")->delimiter(',');
  cmd->add_option("--from", opts->from, "spline: material file the spline reproduces");
  cmd->add_option("--knots", opts->knots, "spline: knots per function (default 8)")
      ->check(CLI::Range(3, 200));
  cmd->add_option("--f-range", opts->f_range, "spline: knot range of f over stretches (default 0.5:2)");
  cmd->add_option("--g-range", opts->g_range, "spline: knot range of g over stretch products (default 0.4:2.5)");
  cmd->add_option("--h-range", opts->h_range, "spline: knot range of h over J (default 0.6:1.6)");
  declare_paths(*cmd, {"--from"}, {"-o"});
  cmd->callback([cmd, opts] {
    if (!cmd->get_subcommands().empty()) return;  // show / curve / models ran
    if (opts->output.empty()) {
      throw_input_error("no output file", ErrorContext{"", 0, 0, "option -o"},
                        "-o material.json (or a subcommand: show, curve, models)");
    }
    const auto material = build_material(*opts);
    Provenance prov = make_provenance(opts->model == "spline"
                                          ? fmt::format("palpa material --model spline --from {}", opts->from)
                                          : "palpa material (user-specified parameters)");
    write_material_file(opts->output, *material, prov);
    spdlog::info("wrote {} ({})", opts->output, material->model());
  });

  auto* show_cmd = cmd->add_subcommand("show", "Print a material's parameters, small-strain E and nu, "
                                               "its volumetric term and stability checks.\n"
                                               "  palpa material show m.json");
  auto show_path = std::make_shared<std::string>();
  show_cmd->add_option("file", *show_path, "Material file")->required();
  show_cmd->callback([show_path] { show(*show_path); });

  auto* models_cmd = cmd->add_subcommand("models", "List the material models and their parameters.");
  models_cmd->callback([] {
    for (const auto& info : known_models()) {
      fmt::print("{:<24} {}\n{:<24} parameters: {}\n", info.name, info.summary, "", info.parameters);
    }
  });

  auto* curve_cmd = cmd->add_subcommand(
      "curve",
      "Write homogeneous stress-stretch curves (traction-free lateral faces) as CSV.\n"
      "  palpa material curve m.json --test uniaxial --stretch 0.6:1.6 -o c.csv\n"
      "  palpa material curve m.json --test shear --shear=-0.5:0.5 -o s.csv");
  auto copts = std::make_shared<CurveOptions>();
  curve_cmd->add_option("file", copts->input, "Material file")->required();
  curve_cmd->add_option("--test", copts->test, "uniaxial, equibiaxial or shear (default uniaxial)");
  auto* stretch_opt = curve_cmd->add_option("--stretch", copts->stretch,
                                            "Stretch range LOW:HIGH (default 0.6:1.6)");
  auto* shear_opt = curve_cmd->add_option("--shear", copts->shear,
                                          "Shear strain range LOW:HIGH for --test shear (default -0.5:0.5)");
  curve_cmd->add_option("--points", copts->points, "Number of points (default 101)")->check(CLI::Range(2, 100000));
  curve_cmd->add_option("-o,--output", copts->output, "CSV file to write")->required();
  declare_paths(*curve_cmd, {"file"}, {"-o"});
  curve_cmd->callback([copts, stretch_opt, shear_opt] { curve(*copts, stretch_opt, shear_opt); });
}

}  // namespace palpa::cli
