// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// What `palpa poke` writes: the curve (indentation_m, force_N and the solver's
// diagnostics per depth), the sensitivities dF/dθ, and the deformed mesh per
// depth as a VTU series; and the run that simulates and writes them, keeping
// the converged depths when a deeper one fails.

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

#include "palpa/axisym/poke.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/io/vtu.hpp"

namespace palpa::axisym {

// The deformed mesh at x: displacement and contact pressure per node; principal
// stretches, det F, Cauchy stress (rr, zz, rz, θθ) and von Mises stress per cell.
UnstructuredGrid deformed_grid(const PokeModel& m, const Eigen::VectorXd& x);

// indentation_m, force_N, newton_iterations, substeps, residual_N,
// max_penetration_m, min_det_F (and mesh_correction_N when extrapolated), under
// the comment lines given.
CsvTable poke_curve_table(const std::vector<PokeSample>& samples, bool extrapolated,
                          const std::vector<std::string>& comments);
// indentation_m and dF/d<parameter> per material parameter [N per SI unit].
CsvTable poke_sensitivity_table(const std::vector<PokeSample>& samples, const material::Material& m, bool incomplete);

struct PokeFiles {
  std::filesystem::path curve;          // required
  std::filesystem::path sensitivities;  // empty: none
  std::filesystem::path vtu;            // folder for poke.pvd and its frames; empty: none
  int vtu_every = 1;                    // every k-th depth (and the last)
};

// Simulates `material` (named `material_name` in the files' comments) and
// writes `files`, every output location checked before the simulation; logs
// the setup, progress per depth and the result. When a depth fails to
// converge, writes the converged depths marked INCOMPLETE (no VTU series) and
// throws palpa::Error (Solver) saying so.
PokeCurve poke_to_files(const material::Material& material, const std::string& material_name, const PokeSetup& setup,
                        const PokeOptions& options, const PokeFiles& files);

}  // namespace palpa::axisym
