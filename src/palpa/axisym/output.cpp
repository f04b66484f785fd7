// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/axisym/output.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <optional>
#include <utility>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/progress.hpp"
#include "palpa/core/units.hpp"

namespace palpa::axisym {

namespace {

// The sample at depth 0 (zero force and sensitivities).
PokeSample curve_start(const PokeSimulator& sim) {
  PokeSample s;
  s.min_jacobian = 1.0;
  s.dforce_dparams = Eigen::VectorXd::Zero(sim.model().num_params());
  return s;
}

// "level 2" or "levels 2 and 1 extrapolated".
std::string level_note(const PokeSimulator& sim, int level) {
  return sim.extrapolates() ? fmt::format("levels {} and {} extrapolated", level, level - 1)
                            : fmt::format("level {}", level);
}

std::string contact_name(const PokeSetup& s) {
  return std::string(s.test == PokeTest::Compression ? platen_contact_name(s.contact) : to_string(s.contact));
}

double von_mises(const Eigen::Vector4d& c) {  // rr, zz, rz, θθ
  return std::sqrt(0.5 * ((c[0] - c[1]) * (c[0] - c[1]) + (c[1] - c[3]) * (c[1] - c[3]) + (c[3] - c[0]) * (c[3] - c[0])) +
                   3.0 * c[2] * c[2]);
}

}  // namespace

UnstructuredGrid deformed_grid(const PokeModel& m, const Eigen::VectorXd& x) {
  const AxisymMesh& mesh = m.mesh();
  const Eigen::MatrixX2d u = m.displacements(x);
  UnstructuredGrid grid;
  grid.points = embed_planar(mesh.nodes + u);
  grid.cells.push_back(CellBlock{VtkCellType::Quad, mesh.quads});
  Eigen::MatrixXd disp = Eigen::MatrixXd::Zero(mesh.num_nodes(), 3);
  disp.leftCols<2>() = u;
  grid.point_data.push_back(DataArray{"displacement_m", disp});
  grid.point_data.push_back(DataArray{"pressure_Pa", m.contact_pressure(x)});
  const auto states = m.element_states(x);
  const auto n = static_cast<Eigen::Index>(states.size());
  Eigen::MatrixXd stretch(n, 3), jac(n, 1), cauchy(n, 4), mises(n, 1);
  for (Eigen::Index e = 0; e < n; ++e) {
    const auto& s = states[static_cast<std::size_t>(e)];
    stretch.row(e) = s.stretches.transpose();
    jac(e, 0) = s.jacobian;
    mises(e, 0) = von_mises(s.cauchy);
    cauchy.row(e) = s.cauchy.transpose();
  }
  grid.cell_data.push_back(DataArray{"principal_stretches", stretch});
  grid.cell_data.push_back(DataArray{"det_F", jac});
  grid.cell_data.push_back(DataArray{"cauchy_stress_rr_zz_rz_thth_Pa", cauchy});
  grid.cell_data.push_back(DataArray{"von_mises_stress_Pa", mises});
  return grid;
}

CsvTable poke_curve_table(const std::vector<PokeSample>& samples, bool extrapolated,
                          const std::vector<std::string>& comments) {
  CsvTable t;
  for (const std::string& c : comments) t.add_comment(c);
  std::vector<double> depth, force, iters, subs, resid, pen, minj, correction;
  for (const auto& s : samples) {
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
  if (extrapolated) t.add_quantity("mesh_correction", "N", Dimension::Force, correction);
  return t;
}

CsvTable poke_sensitivity_table(const std::vector<PokeSample>& samples, const material::Material& m, bool incomplete) {
  CsvTable st;
  st.add_comment("dF/dtheta per material parameter: newtons per unit of the parameter (SI)");
  if (incomplete) st.add_comment("INCOMPLETE: the depths the simulation converged to (see the curve)");
  std::vector<double> depth;
  for (const auto& s : samples) depth.push_back(s.depth);
  st.add_quantity("indentation", "m", Dimension::Length, depth);
  for (Eigen::Index k = 0; k < m.num_params(); ++k) {
    std::string name = m.param_info(k).name;
    for (char& c : name) {
      if (c == '_') c = '-';
    }
    std::vector<double> col;
    for (const auto& s : samples) col.push_back(s.dforce_dparams[k]);
    st.add_column("dF/d" + name, col);
  }
  return st;
}

PokeCurve poke_to_files(const material::Material& material, const std::string& material_name, const PokeSetup& setup,
                        const PokeOptions& options, const PokeFiles& files) {
  const bool compression = setup.test == PokeTest::Compression;
  const double radius = setup.geometry.punch_radius, thickness = setup.geometry.thickness;
  // Check every output location before the (long) simulation.
  std::optional<OutputFolder> vtu_folder;
  if (!files.vtu.empty()) vtu_folder.emplace(files.vtu, OutputFolder::OnFailure::Wipe);
  OutputBatch outputs;
  std::ostream& curve_out = outputs.add(files.curve);
  std::ostream* sens_out = options.sensitivities ? &outputs.add(files.sensitivities) : nullptr;

  const auto start = std::chrono::steady_clock::now();
  PokeSimulator sim(material, setup);
  const std::string contact = contact_name(setup);
  if (compression) {
    spdlog::info("poke: {} ({}), compression of a cylinder of radius {} and height {} between {} platens, "
                 "mesh level {} ({} nodes)",
                 material_name, material.model(), format_quantity(radius, Dimension::Length),
                 format_quantity(thickness, Dimension::Length), contact, setup.mesh_level,
                 sim.model().mesh().num_nodes());
  } else {
    spdlog::info("poke: {} ({}), punch radius {}, layer {}, {} contact, mesh level {} ({} nodes)", material_name,
                 material.model(), format_quantity(radius, Dimension::Length),
                 format_quantity(thickness, Dimension::Length), contact, setup.mesh_level,
                 sim.model().mesh().num_nodes());
  }
  Progress progress("poke", static_cast<std::size_t>(options.steps));
  // VTU files go to a temporary series and are kept only if the run succeeds.
  std::vector<std::pair<double, UnstructuredGrid>> frames;
  // Every converged depth, from depth 0: what is written if a deeper one fails.
  std::vector<PokeSample> reached;
  PokeCurve curve;
  std::optional<Error> failure;
  try {
    curve = sim.run(options, [&](const PokeModel& m, const Eigen::VectorXd& x, const PokeSample& s) {
      if (reached.empty()) reached.push_back(curve_start(sim));
      reached.push_back(s);
      const int index = static_cast<int>(reached.size()) - 1;
      if (!files.vtu.empty() && (index % files.vtu_every == 0 || index == options.steps)) {
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

  const std::string element(to_string(setup.element));
  std::vector<std::string> comments;
  if (compression) {
    // The platen travel is the curve's indentation (as the fit datasets read it).
    comments.push_back(fmt::format("palpa poke: {} ({}), compression, R = {} m, H = {} m, {} platens, {} element, {}",
                                   material_name, material.model(), radius, thickness, contact, element,
                                   level_note(sim, setup.mesh_level)));
  } else {
    comments.push_back(fmt::format("palpa poke: {} ({}), a = {} m, D = {} m, {} contact, {} element, {}, fillet {} m",
                                   material_name, material.model(), radius, thickness, contact, element,
                                   level_note(sim, setup.mesh_level), setup.fillet_radius));
  }
  if (failure) {
    comments.push_back(fmt::format("INCOMPLETE: converged to {} of {} ({} of {} depths); the next depth failed: {}",
                                   format_quantity(reached.empty() ? 0.0 : reached.back().depth, Dimension::Length),
                                   format_quantity(options.max_depth, Dimension::Length),
                                   reached.empty() ? 0 : reached.size() - 1, options.steps, failure->problem()));
    if (reached.empty()) reached.push_back(curve_start(sim));
  }
  curve_out << format_csv(poke_curve_table(reached, sim.extrapolates(), comments));
  if (sens_out != nullptr) {
    *sens_out << format_csv(poke_sensitivity_table(reached, sim.model().material(), failure.has_value()));
  }
  if (failure) {
    // The converged depths only; no VTU series (the folder is removed).
    outputs.commit();
    throw Error(ErrorKind::Solver,
                fmt::format("{}\n(wrote the {} converged depth{}, to {}, to {}, marked INCOMPLETE)",
                            failure->problem(), reached.size() - 1, reached.size() == 2 ? "" : "s",
                            format_quantity(reached.back().depth, Dimension::Length), files.curve.string()));
  }
  if (!frames.empty()) {
    // Written after the simulation succeeded; each file atomically.
    PvdSeries series(files.vtu / "poke.pvd");
    for (const auto& [d, grid] : frames) series.add(d, grid);
  }
  outputs.commit();
  if (vtu_folder) vtu_folder->keep();
  const auto& last = curve.samples.back();
  if (compression) {
    spdlog::info("poke: compression {} ({:.4g}%) -> force {:.6g} N; {} Newton iterations, {} factorizations, {:.2f} s",
                 format_quantity(last.depth, Dimension::Length), 100.0 * last.depth / thickness, last.force,
                 curve.newton_iterations, curve.factorizations, seconds);
  } else {
    spdlog::info("poke: depth {} -> force {:.6g} N; {} Newton iterations, {} factorizations, {:.2f} s",
                 format_quantity(last.depth, Dimension::Length), last.force, curve.newton_iterations,
                 curve.factorizations, seconds);
  }
  return curve;
}

}  // namespace palpa::axisym
