// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa poke: force–indentation curve of a flat cylindrical punch pressed into a
// layer on a rigid base, or force–compression curve of a cylindrical sample
// between two plates (axisymmetric FEM).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/axisym/output.hpp"
#include "palpa/core/error.hpp"
#include "palpa/material/material_file.hpp"

namespace palpa::cli {

namespace {

struct PokeArgs {
  std::string material;
  std::string output;
  std::string test = "indentation";
  std::string contact;  // default: stick (indentation), bonded (compression)
  std::string element = "fbar";
  std::string vtu_dir;
  std::string sensitivities;
  double thickness = 0.0;
  double radius = 0.0;
  double depth = 0.0;
  double fillet = 0.0;
  double outer_radius = 0.0;
  int steps = 20;
  int level = 2;
  bool no_extrapolation = false;
  bool overwrite = false;
  int vtu_every = 1;
};

// Parses --test and --contact and refuses options that do not apply to the test.
void set_test(const PokeArgs& a, axisym::PokeSetup& setup) {
  setup.test = axisym::parse_poke_test(a.test);
  if (setup.test == axisym::PokeTest::Indentation) {
    if (a.contact == "bonded") {
      throw_input_error("--contact bonded is for the platens of --test compression",
                        ErrorContext{"", 0, 0, "option --contact"},
                        "stick or frictionless for an indentation punch");
    }
    setup.contact = axisym::parse_punch_contact(a.contact.empty() ? "stick" : a.contact);
    return;
  }
  if (a.contact == "stick") {
    throw_input_error("--contact stick is for an indentation punch; compression platens are bonded or frictionless",
                      ErrorContext{"", 0, 0, "option --contact"}, "bonded or frictionless");
  }
  setup.contact = axisym::parse_platen_contact(a.contact.empty() ? "bonded" : a.contact);
  const auto refuse = [](const char* option, const char* why) {
    throw_input_error(fmt::format("{} does not apply to --test compression: {}", option, why),
                      ErrorContext{"", 0, 0, std::string("option ") + option},
                      "--radius (sample radius) and --thickness (sample height) only");
  };
  if (a.fillet != 0.0) refuse("--fillet", "the platens cover the whole sample and have no rim");
  if (a.outer_radius != 0.0) refuse("--outer-radius", "the sample radius is --radius");
}

void run_poke(const PokeArgs& a) {
  if (!a.vtu_dir.empty() && !a.overwrite) require_empty_output(a.vtu_dir, {}, "--vtu");
  axisym::PokeSetup setup;
  set_test(a, setup);
  const material::MaterialFile mf = material::read_material_file(a.material);
  setup.geometry.punch_radius = a.radius;
  setup.geometry.thickness = a.thickness;
  setup.geometry.outer_radius = a.outer_radius;
  setup.mesh_level = a.level;
  setup.extrapolate = !a.no_extrapolation;
  setup.element = axisym::parse_element_formulation(a.element);
  setup.fillet_radius = a.fillet;
  axisym::PokeOptions options;
  options.max_depth = a.depth;
  options.steps = a.steps;
  options.sensitivities = !a.sensitivities.empty();
  axisym::poke_to_files(*mf.material, a.material, setup, options, {a.output, a.sensitivities, a.vtu_dir, a.vtu_every});
}

}  // namespace

void add_poke_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "poke",
      "Simulate a rigid flat cylindrical punch pressed into a layer on a rigid base (or, with "
      "--test compression, a cylindrical sample compressed between two plates) and write the "
      "force-indentation curve.\n"
      "  palpa poke --material m.json --thickness 10mm --radius 3.01mm --depth 2mm --steps 20 "
      "-o curve.csv\n"
      "  palpa poke --test compression --contact bonded --material m.json --radius 15mm "
      "--thickness 30mm --depth 20mm --steps 40 -o curve.csv");
  auto a = std::make_shared<PokeArgs>();
  cmd->add_option("--material", a->material, "Material file (palpa material)")->required();
  cmd->add_option("--test", a->test,
                  "indentation: a punch pressed into a layer; compression: a whole cylindrical sample "
                  "between two plates (default indentation)");
  add_quantity_option(*cmd, "--thickness", a->thickness, Dimension::Length,
                      "Layer thickness D (compression: sample height H)", Sign::Positive)
      ->required();
  add_quantity_option(*cmd, "--radius", a->radius, Dimension::Length, "Punch radius a (compression: sample radius R)",
                      Sign::Positive)
      ->required();
  add_quantity_option(*cmd, "--depth", a->depth, Dimension::Length,
                      "Maximum indentation (compression: travel of the top plate)", Sign::Positive)
      ->required();
  cmd->add_option("--steps", a->steps, "Equal depth increments up to --depth (default 20)")
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--contact", a->contact,
                  "Indentation: stick (punch-face nodes fully held, default) or frictionless (only pushed "
                  "down). Compression: bonded (default) or frictionless platens");
  cmd->add_option("--mesh-level", a->level,
                  "Mesh refinement 0..7, each level halves the cells; the force is extrapolated from this "
                  "level and the one below it (default 2)")
      ->check(CLI::Range(0, 7));
  cmd->add_flag("--no-extrapolation", a->no_extrapolation,
                "Report the force of the --mesh-level mesh alone (about 1% stiff at level 2) instead of "
                "its Richardson extrapolation with the level below");
  cmd->add_option("--element", a->element,
                  "fbar (locking-free for nearly incompressible tissue) or standard (default fbar)");
  add_quantity_option(*cmd, "--fillet", a->fillet, Dimension::Length,
                      "Radius rounding the punch rim (default 0: sharp)", Sign::NonNegative);
  add_quantity_option(*cmd, "--outer-radius", a->outer_radius, Dimension::Length,
                      "Radius of the simulated layer (default 8 max(a, D))", Sign::Positive);
  cmd->add_option("--vtu", a->vtu_dir, "Folder for VTU files of the deformed mesh and a PVD series");
  cmd->add_flag("--overwrite", a->overwrite,
                "Write into a non-empty --vtu folder (the files palpa wrote there before and does not write "
                "again are removed)");
  cmd->add_option("--vtu-every", a->vtu_every, "Write every k-th depth to --vtu (default 1)")
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--sensitivities", a->sensitivities,
                  "Also write dF/dtheta for every material parameter to this CSV");
  cmd->add_option("-o,--output", a->output, "CSV to write: indentation_m,force_N,...")->required();
  declare_paths(*cmd, {"--material"}, {"-o", "--sensitivities", "--vtu"});
  cmd->callback([a] { run_poke(*a); });
}

}  // namespace palpa::cli
