// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The tour of palpa on its bundled examples (`palpa demo`): the material
// stage (for each example material its small-strain constants and checks, its
// homogeneous stress-stretch curves, and the spline material that reproduces
// it, the starting point of a fit), the indentation stage (each material poked
// by a 3 mm punch into a 10 mm layer, with the force's sensitivity to every
// material parameter) and the fitting stage (a spline material fitted to the
// bundled foam indentation curves, validated on the punches it was not
// trained on).

#include <cstddef>
#include <filesystem>
#include <string>

namespace palpa::pipeline {

struct DemoResult {
  std::string summary;      // what summary.txt holds
  std::size_t files = 0;    // files written (the fit's folder aside)
};

// Runs it on the examples folder `examples` (its materials/ and
// fit/foam/dataset.json) into `out` (created if missing).
DemoResult run_demo(const std::filesystem::path& examples, const std::filesystem::path& out);

}  // namespace palpa::pipeline
