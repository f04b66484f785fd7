// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa material: write a material file from a model and its parameters, or
// a spline material that reproduces another material.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <map>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/core/error.hpp"
#include "palpa/material/material_file.hpp"
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
  return make_material(model, std::move(given), ErrorContext{}, option_name);
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
        if (m.find_any(key) != nullptr) users.push_back(m.name);
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

  add_material_inspection(*cmd);
}

}  // namespace palpa::cli
