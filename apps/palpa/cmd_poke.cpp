// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa poke: force–indentation curve of a flat cylindrical punch pressed into a
// layer on a rigid base, or force–compression curve of a cylindrical sample
// between two plates (axisymmetric FEM).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/axisym/poke.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/progress.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/io/vtu.hpp"
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
  int vtu_every = 1;
};

UnstructuredGrid deformed_grid(const axisym::PokeModel& m, const Eigen::VectorXd& x) {
  const axisym::AxisymMesh& mesh = m.mesh();
  const Eigen::MatrixX2d u = m.displacements(x);
  UnstructuredGrid grid;
  grid.points = embed_planar(mesh.nodes + u);
  grid.cells.push_back(CellBlock{VtkCellType::Quad, mesh.quads});
  Eigen::MatrixXd disp = Eigen::MatrixXd::Zero(mesh.num_nodes(), 3);
  disp.leftCols<2>() = u;
  grid.point_data.push_back(DataArray{"displacement_m", disp});
  grid.point_data.push_back(DataArray{"contact_pressure_Pa", m.contact_pressure(x)});
  const auto states = m.element_states(x);
  const auto n = static_cast<Eigen::Index>(states.size());
  Eigen::MatrixXd stretch(n, 3), jac(n, 1), cauchy(n, 4), mises(n, 1);
  for (Eigen::Index e = 0; e < n; ++e) {
    const auto& s = states[static_cast<std::size_t>(e)];
    stretch.row(e) = s.stretches.transpose();
    jac(e, 0) = s.jacobian;
    const Eigen::Vector4d c = s.cauchy;  // rr, zz, rz, θθ
    mises(e, 0) = std::sqrt(0.5 * ((c[0] - c[1]) * (c[0] - c[1]) + (c[1] - c[3]) * (c[1] - c[3]) +
                                   (c[3] - c[0]) * (c[3] - c[0])) +
                            3.0 * c[2] * c[2]);
    cauchy.row(e) = c.transpose();
  }
  grid.cell_data.push_back(DataArray{"principal_stretches", stretch});
  grid.cell_data.push_back(DataArray{"det_F", jac});
  grid.cell_data.push_back(DataArray{"cauchy_stress_rr_zz_rz_thth_Pa", cauchy});
  grid.cell_data.push_back(DataArray{"von_mises_stress_Pa", mises});
  return grid;
}

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

// The sample at depth 0 (zero force and sensitivities).
axisym::PokeSample curve_start(const axisym::PokeSimulator& sim) {
  axisym::PokeSample s;
  s.min_jacobian = 1.0;
  s.dforce_dparams = Eigen::VectorXd::Zero(sim.model().num_params());
  return s;
}

// "level 2" or "levels 2 and 1 extrapolated".
std::string level_note(const axisym::PokeSimulator& sim, int level) {
  return sim.extrapolates() ? fmt::format("levels {} and {} extrapolated", level, level - 1)
                            : fmt::format("level {}", level);
}

std::string contact_name(const axisym::PokeSetup& s) {
  return std::string(s.test == axisym::PokeTest::Compression ? axisym::platen_contact_name(s.contact)
                                                             : axisym::to_string(s.contact));
}

void run_poke(const PokeArgs& a) {
  axisym::PokeSetup setup;
  set_test(a, setup);
  const material::MaterialFile mf = material::read_material_file(a.material);
  const bool compression = setup.test == axisym::PokeTest::Compression;
  setup.geometry.punch_radius = a.radius;
  setup.geometry.thickness = a.thickness;
  setup.geometry.outer_radius = a.outer_radius;
  setup.mesh_level = a.level;
  setup.extrapolate = !a.no_extrapolation;
  if (a.element == "fbar") {
    setup.element = axisym::ElementFormulation::FBar;
  } else if (a.element == "standard") {
    setup.element = axisym::ElementFormulation::Standard;
  } else {
    throw_input_error(fmt::format("unknown element '{}'", a.element),
                      ErrorContext{"", 0, 0, "option --element"}, "fbar or standard");
  }
  setup.fillet_radius = a.fillet;
  axisym::PokeOptions options;
  options.max_depth = a.depth;
  options.steps = a.steps;
  options.sensitivities = !a.sensitivities.empty();

  // Check every output location before the (long) simulation.
  std::optional<OutputFolder> vtu_folder;
  if (!a.vtu_dir.empty()) vtu_folder.emplace(a.vtu_dir, OutputFolder::OnFailure::Wipe);
  OutputBatch outputs;
  std::ostream& curve_out = outputs.add(a.output);
  std::ostream* sens_out = options.sensitivities ? &outputs.add(a.sensitivities) : nullptr;

  const auto start = std::chrono::steady_clock::now();
  axisym::PokeSimulator sim(*mf.material, setup);
  const std::string contact = contact_name(setup);
  if (compression) {
    spdlog::info("poke: {} ({}), compression of a cylinder of radius {} and height {} between {} platens, "
                 "mesh level {} ({} nodes)",
                 a.material, mf.material->model(), format_quantity(a.radius, Dimension::Length),
                 format_quantity(a.thickness, Dimension::Length), contact, a.level,
                 sim.model().mesh().num_nodes());
  } else {
    spdlog::info("poke: {} ({}), punch radius {}, layer {}, {} contact, mesh level {} ({} nodes)",
                 a.material, mf.material->model(), format_quantity(a.radius, Dimension::Length),
                 format_quantity(a.thickness, Dimension::Length), contact, a.level,
                 sim.model().mesh().num_nodes());
  }
  Progress progress("poke", static_cast<std::size_t>(a.steps));
  // VTU files go to a temporary series and are kept only if the run succeeds.
  std::vector<std::pair<double, UnstructuredGrid>> frames;
  // Every converged depth, from depth 0: what is written if a deeper one fails.
  std::vector<axisym::PokeSample> reached;
  axisym::PokeCurve curve;
  std::optional<Error> failure;
  try {
    curve = sim.run(options, [&](const axisym::PokeModel& m, const Eigen::VectorXd& x, const axisym::PokeSample& s) {
      if (reached.empty()) reached.push_back(curve_start(sim));
      reached.push_back(s);
      const int index = static_cast<int>(reached.size()) - 1;
      if (!a.vtu_dir.empty() && (index % a.vtu_every == 0 || index == a.steps)) {
        frames.emplace_back(s.depth, deformed_grid(m, x));
      }
      progress.set_note(fmt::format("d = {:.4g} mm, F = {:.4g} N, {} Newton it.", s.depth * 1e3, s.force,
                                    s.newton_iterations));
      progress.advance();
    });
    reached = curve.samples;
    progress.finish();
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Solver) throw;
    failure = e;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  CsvTable t;
  if (compression) {
    // The platen travel is the curve's indentation (as the fit datasets read it).
    t.add_comment(fmt::format("palpa poke: {} ({}), compression, R = {} m, H = {} m, {} platens, {} element, {}",
                              a.material, mf.material->model(), a.radius, a.thickness, contact, a.element,
                              level_note(sim, a.level)));
  } else {
    t.add_comment(fmt::format("palpa poke: {} ({}), a = {} m, D = {} m, {} contact, {} element, {}, fillet {} m",
                              a.material, mf.material->model(), a.radius, a.thickness, contact, a.element,
                              level_note(sim, a.level), a.fillet));
  }
  if (failure) {
    t.add_comment(fmt::format("INCOMPLETE: converged to {} of {} ({} of {} depths); the next depth failed: {}",
                              format_quantity(reached.empty() ? 0.0 : reached.back().depth, Dimension::Length),
                              format_quantity(a.depth, Dimension::Length),
                              reached.empty() ? 0 : reached.size() - 1, a.steps, failure->problem()));
    if (reached.empty()) reached.push_back(curve_start(sim));
  }
  std::vector<double> depth, force, iters, subs, resid, pen, minj, correction;
  for (const auto& s : reached) {
    depth.push_back(s.depth);
    force.push_back(s.force);
    iters.push_back(s.newton_iterations);
    subs.push_back(s.substeps);
    resid.push_back(s.residual);
    pen.push_back(s.max_penetration);
    minj.push_back(s.min_jacobian);
    correction.push_back(s.mesh_correction);
  }
  t.add_quantity("indentation", "m", Dimension::Length, depth);
  t.add_quantity("force", "N", Dimension::Force, force);
  t.add_column("newton_iterations", iters);
  t.add_column("substeps", subs);
  t.add_quantity("residual", "N", Dimension::Force, resid);
  t.add_quantity("max_penetration", "m", Dimension::Length, pen);
  t.add_column("min_det_F", minj);
  if (sim.extrapolates()) t.add_quantity("mesh_correction", "N", Dimension::Force, correction);
  curve_out << format_csv(t);
  if (sens_out != nullptr) {
    CsvTable st;
    st.add_comment("dF/dtheta per material parameter: newtons per unit of the parameter (SI)");
    if (failure) st.add_comment("INCOMPLETE: the depths the simulation converged to (see the curve)");
    st.add_quantity("indentation", "m", Dimension::Length, depth);
    const auto& mat = sim.model().material();
    for (Eigen::Index k = 0; k < mat.num_params(); ++k) {
      std::string name = mat.param_info(k).name;
      for (char& c : name) {
        if (c == '_') c = '-';
      }
      std::vector<double> col;
      for (const auto& s : reached) col.push_back(s.dforce_dparams[k]);
      st.add_column("dF/d" + name, col);
    }
    *sens_out << format_csv(st);
  }
  if (failure) {
    // The converged depths only; no VTU series (the folder is removed).
    outputs.commit();
    throw Error(ErrorKind::Solver,
                fmt::format("{}\n(wrote the {} converged depth{}, to {}, to {}, marked INCOMPLETE)",
                            failure->problem(), reached.size() - 1, reached.size() == 2 ? "" : "s",
                            format_quantity(reached.back().depth, Dimension::Length), a.output));
  }
  if (!frames.empty()) {
    // Written after the simulation succeeded; each file atomically.
    PvdSeries series(std::filesystem::path(a.vtu_dir) / "poke.pvd");
    for (const auto& [d, grid] : frames) series.add(d, grid);
  }
  outputs.commit();
  if (vtu_folder) vtu_folder->keep();
  const auto& last = curve.samples.back();
  if (compression) {
    spdlog::info("poke: compression {} ({:.4g}%) -> force {:.6g} N; {} Newton iterations, {} factorizations, {:.2f} s",
                 format_quantity(last.depth, Dimension::Length), 100.0 * last.depth / a.thickness, last.force,
                 curve.newton_iterations, curve.factorizations, seconds);
  } else {
    spdlog::info("poke: depth {} -> force {:.6g} N; {} Newton iterations, {} factorizations, {:.2f} s",
                 format_quantity(last.depth, Dimension::Length), last.force, curve.newton_iterations,
                 curve.factorizations, seconds);
  }
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
  cmd->add_option("--vtu-every", a->vtu_every, "Write every k-th depth to --vtu (default 1)")
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--sensitivities", a->sensitivities,
                  "Also write dF/dtheta for every material parameter to this CSV");
  cmd->add_option("-o,--output", a->output, "CSV to write: indentation_m,force_N,...")->required();
  declare_paths(*cmd, {"--material"}, {"-o", "--sensitivities", "--vtu"});
  cmd->callback([a] { run_poke(*a); });
}

}  // namespace palpa::cli
