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
#include "palpa/material/material_file.hpp"
#include "palpa/material/elastic_constants.hpp"
#include "palpa/material/output.hpp"
#include "palpa/material/registry.hpp"
#include "palpa/material/spline_material.hpp"

namespace palpa::cli {

namespace {

using namespace palpa::material;

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
  // Scalar parameters by key, SI, and their options.
  std::map<std::string, double> values;
  std::map<std::string, CLI::Option*> options;
};

std::string option_name(std::string_view key) { return fmt::format("--{}", key); }

// The parameters given on the command line, by key.
ParameterValues given_parameters(const CreateOptions& o) {
  ParameterValues v;
  for (const auto& [key, opt] : o.options) {
    if (opt->count() > 0) v.scalars[key] = o.values.at(key);
  }
  if (!o.mu.empty()) {
    auto& mu = v.lists["mu"];
    for (const auto& text : o.mu) {
      mu.push_back(parse_quantity(text, Dimension::Pressure, ErrorContext{"", 0, 0, "option --mu"}));
    }
  }
  if (!o.alpha.empty()) v.lists["alpha"] = o.alpha;
  return v;
}

// neo-hookean-isochoric also takes E and nu: C10 = mu/2, D1 = 2/K.
void isochoric_from_young(ParameterValues& v) {
  if (!v.has("E") && !v.has("nu")) return;
  for (const char* key : {"E", "nu"}) {
    if (!v.has(key)) {
      throw_input_error(fmt::format("model 'neo-hookean-isochoric' needs --{} with {}", key, key[0] == 'E' ? "--nu" : "--E"),
                        ErrorContext{}, "--E and --nu, or --C10 and --D1");
    }
  }
  for (const char* key : {"C10", "D1"}) {
    if (v.has(key)) {
      throw_input_error(fmt::format("--{} with --E and --nu", key), ErrorContext{}, "--E and --nu, or --C10 and --D1");
    }
  }
  const ElasticConstants l = lame_from_young(v.scalars.at("E"), v.scalars.at("nu"));
  v.scalars.erase("E");
  v.scalars.erase("nu");
  v.scalars["C10"] = l.mu / 2.0;
  v.scalars["D1"] = 2.0 / l.bulk();
}

std::unique_ptr<Material> spline_from(const CreateOptions& o) {
  if (o.from.empty()) {
    throw_input_error("model 'spline' is built from another material", ErrorContext{},
                      "--from material.json (the material the spline reproduces)");
  }
  const MaterialFile source = read_material_file(o.from);
  const auto range = [&](const std::string& text, const std::string& name) {
    const auto [lo, hi] = parse_range(text, name, "0.6:1.6");
    return SplineRange{lo, hi, o.knots};
  };
  SplineLayout layout;
  layout.f = range(o.f_range, "--f-range");
  layout.g = range(o.g_range, "--g-range");
  layout.h = range(o.h_range, "--h-range");
  return std::make_unique<SplineMaterial>(SplineMaterial::from_model(*source.material, layout));
}

std::unique_ptr<Material> build_material(const CreateOptions& o) {
  const ModelSpec& model = model_spec(o.model, ErrorContext{"", 0, 0, "option --model"});
  ParameterValues given = given_parameters(o);
  if (model.name != "spline" && !o.from.empty()) {
    throw_input_error(fmt::format("--from does not apply to model '{}'", model.name), ErrorContext{},
                      "--model spline --from material.json");
  }
  if (model.name == "spline") {
    const auto keys = given.keys();
    if (!keys.empty()) {
      throw_input_error(fmt::format("--{} does not apply to model 'spline'", keys.front()), ErrorContext{},
                        "--from material.json and the knot options");
    }
    return spline_from(o);
  }
  if (model.name == "neo-hookean-isochoric") isochoric_from_young(given);
  return make_material(model, std::move(given), ErrorContext{}, option_name);
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
  const bool shear = lc == LoadCase::SimpleShear;
  if (shear && stretch_opt->count() > 0) {
    throw_input_error("--stretch is for uniaxial and equibiaxial tests", ErrorContext{},
                      "--shear LOW:HIGH for the shear test");
  }
  if (!shear && shear_opt->count() > 0) {
    throw_input_error("--shear is for the shear test", ErrorContext{}, "--stretch LOW:HIGH");
  }
  const auto [lo, hi] = shear ? parse_range(o.shear, "--shear", "-0.5:0.5") : parse_range(o.stretch, "--stretch", "0.6:1.6");
  if (!shear && !(lo > 0.0)) {
    throw_input_error(fmt::format("stretch range starts at {}", lo), ErrorContext{"", 0, 0, "option --stretch"},
                      "stretches > 0");
  }
  write_csv(o.output, homogeneous_curve_table(*f.material, lc, lo, hi, o.points,
                                              fmt::format("{} test of {} ({})", o.test, o.input, f.material->model())));
  spdlog::info("wrote {}: {} test of {} ({}), {} points, {} {} to {}", o.output, o.test, o.input, f.material->model(),
               o.points, shear ? "shear" : "stretch", lo, hi);
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
  // One option per scalar parameter key of any model, named as in material files.
  for (const ModelSpec& model : models()) {
    for (const ParameterSpec& p : model.parameters) {
      if (p.kind != ParameterKind::Scalar || opts->options.count(std::string(p.key)) > 0) continue;
      const std::string key(p.key);
      opts->values[key] = 0.0;
      std::vector<std::string_view> users;
      for (const ModelSpec& m : models()) {
        if (m.find(key) != nullptr) users.push_back(m.name);
      }
      std::string help = users.size() == 1 ? fmt::format("{}: {}", users.front(), p.meaning) : std::string(p.meaning);
      if (p.default_value) help += fmt::format(" (default {:g})", *p.default_value);
      opts->options[key] = add_quantity_option(*cmd, option_name(key), opts->values[key], p.dimension, help);
    }
  }
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
  show_cmd->callback([show_path] { fmt::print("{}", describe(read_material_file(*show_path), *show_path)); });

  auto* models_cmd = cmd->add_subcommand("models", "List the material models and their parameters.");
  models_cmd->callback([] {
    for (const ModelSpec& m : models()) {
      fmt::print("{:<24} {}\n{:<24} parameters: {}\n", m.name, m.summary, "", m.parameter_summary());
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
