// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa material show / models / curve: look at a material file, list the
// models, and write homogeneous stress-stretch curves.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/core/error.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/material/material_file.hpp"
#include "palpa/material/output.hpp"
#include "palpa/material/registry.hpp"

namespace palpa::cli {

namespace {

using namespace palpa::material;

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

void add_material_inspection(CLI::App& cmd) {
  auto* show_cmd = cmd.add_subcommand("show", "Print a material's parameters, small-strain E and nu, "
                                               "its volumetric term and stability checks.\n"
                                               "  palpa material show m.json");
  auto show_path = std::make_shared<std::string>();
  show_cmd->add_option("file", *show_path, "Material file")->required();
  show_cmd->callback([show_path] { fmt::print("{}", describe(read_material_file(*show_path), *show_path)); });

  auto* models_cmd = cmd.add_subcommand("models", "List the material models and their parameters.");
  models_cmd->callback([] {
    for (const ModelSpec& m : models()) {
      fmt::print("{:<24} {}\n{:<24} parameters: {}\n", m.name, m.summary, "", m.parameter_summary());
    }
  });

  auto* curve_cmd = cmd.add_subcommand(
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
