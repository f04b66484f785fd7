// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Shared set-up of the fit tests: curve files and datasets written to a scratch
// folder, and synthetic measurements made with palpa's own simulators plus
// seeded Gaussian noise.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "palpa/axisym/poke.hpp"
#include "palpa/core/json.hpp"
#include "palpa/fit/dataset.hpp"
#include "palpa/material/homogeneous.hpp"
#include "palpa/material/material.hpp"

namespace palpa::fit::test {

// A curve in SI: x (indentation [m], or stretch / shear γ) and y (force [N] or
// nominal stress [Pa]).
struct Curve {
  std::vector<double> x;
  std::vector<double> y;
};

// Writes a force curve as CSV with columns indentation_mm, force_N.
void write_force_csv(const std::filesystem::path& path, const Curve& c);
// Writes a homogeneous curve as CSV with columns stretch (shear for simple
// shear) and stress_kPa.
void write_stress_csv(const std::filesystem::path& path, material::LoadCase lc, const Curve& c);

// The punch (top-platen) force of `setup` at `points` equal depth increments up
// to max_depth (depth 0 left out), from palpa's simulator.
Curve simulate_poke(const material::Material& m, const axisym::PokeSetup& setup, double max_depth, int points);

// Adds seeded Gaussian noise of σ = rel·max|y| + abs to y; returns σ.
double add_noise(std::vector<double>& y, double rel, double abs, std::uint64_t salt);

// A measured curve held in memory (for problems built without files).
MeasuredCurve measured(const std::string& name, CurveRole role, double radius, const Curve& c,
                       material::LoadCase lc = material::LoadCase::Uniaxial);

// An indentation dataset made from a known material: every curve simulated at
// layer depth `true_depth` (mesh level `mesh_level`) with noise, written as
// <folder>/a<radius in µm>.csv, and <folder>/dataset.json naming them with
// `layer_depth` (a quantity string, a range object or a list).
struct IndentationSpec {
  double true_depth = 10e-3;              // [m]
  Json layer_depth = "10 mm";             // what the dataset says
  axisym::PunchContact contact = axisym::PunchContact::Stick;
  double poisson = 0.45;                  // the dataset's ν for stage 1
  std::vector<double> train_radii;        // [m]
  std::vector<double> validate_radii;     // [m]
  double max_depth = 1.5e-3;              // deepest indentation [m]
  int points = 12;                        // measured depths per curve
  int mesh_level = 1;
  double noise_rel = 0.005;               // σ = noise_rel·max F + noise_abs
  double noise_abs = 1e-3;                // [N]
  std::uint64_t salt = 0;                 // noise seed salt
};
struct Synthetic {
  std::filesystem::path dataset;
  std::vector<double> sigma;  // noise σ per curve, in the dataset's order (train, then validate) [N]
};
Synthetic write_indentation_dataset(const std::filesystem::path& folder, const material::Material& truth,
                                    const IndentationSpec& spec);

}  // namespace palpa::fit::test
