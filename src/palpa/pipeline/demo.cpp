// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/pipeline/demo.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "palpa/axisym/poke.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/json.hpp"
#include "palpa/core/progress.hpp"
#include "palpa/fit/run.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/material/checks.hpp"
#include "palpa/material/homogeneous.hpp"
#include "palpa/material/material_file.hpp"
#include "palpa/material/spline_material.hpp"

namespace palpa::pipeline {

namespace {

using namespace palpa::material;

struct Case {
  LoadCase load;
  const char* name;
  double from;
  double to;
};

constexpr Case kCases[] = {
    {LoadCase::Uniaxial, "uniaxial", 0.6, 1.6},
    {LoadCase::Equibiaxial, "equibiaxial", 0.8, 1.3},
    {LoadCase::SimpleShear, "shear", -0.6, 0.6},
};

std::string curve_csv(const std::vector<CurvePoint>& model, const std::vector<CurvePoint>& spline,
                      const Case& c) {
  CsvTable t;
  std::vector<double> load, a, b;
  for (std::size_t i = 0; i < model.size(); ++i) {
    load.push_back(model[i].load);
    a.push_back(model[i].nominal);
    b.push_back(spline[i].nominal);
  }
  t.add_column(c.load == LoadCase::SimpleShear ? "shear_strain" : "stretch", load);
  t.add_quantity("nominal_stress_model", "Pa", Dimension::Pressure, a);
  t.add_quantity("nominal_stress_spline", "Pa", Dimension::Pressure, b);
  return format_csv(t);
}

}  // namespace

DemoResult run_demo(const std::filesystem::path& examples, const std::filesystem::path& out) {
  const std::filesystem::path dir = examples / "materials";
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    if (e.path().extension() == ".json") files.push_back(e.path());
  }
  if (ec || files.empty()) {
    throw_input_error("no example materials found", ErrorContext{dir.string(), 0, 0, ""},
                      "the examples folder of the palpa source tree (--examples DIR)");
  }
  std::sort(files.begin(), files.end());
  // The demo has no --resume: a failed run takes back the folder it made.
  OutputFolder folder(out, OutputFolder::OnFailure::Wipe);

  OutputBatch batch;
  std::string summary = "palpa demo: material and indentation stages on the bundled examples\n\n";
  Progress progress("demo materials", files.size());
  for (const auto& file : files) {
    const MaterialFile mf = read_material_file(file);
    const Material& m = *mf.material;
    const std::string stem = file.stem().string();
    const MaterialCheck check = check_material(m);
    SplineLayout layout;
    layout.f = {0.5, 2.0, 12};
    layout.g = {0.4, 2.5, 12};
    layout.h = {0.6, 1.6, 12};
    const SplineMaterial spline = SplineMaterial::from_model(m, layout);
    summary += fmt::format("{} ({}): small-strain E = {}, nu = {:.3f}; {}\n", stem, m.model(),
                           format_quantity(check.small_strain.young(), Dimension::Pressure),
                           check.small_strain.poisson(),
                           check.problems.empty() ? "stable in all checks" : check.problems.front());
    for (const Case& c : kCases) {
      const auto ref = homogeneous_curve(m, c.load, c.from, c.to, 41);
      const auto spl = homogeneous_curve(spline, c.load, c.from, c.to, 41);
      double peak = 0.0;
      double err = 0.0;
      for (std::size_t i = 0; i < ref.size(); ++i) {
        peak = std::max(peak, std::abs(ref[i].nominal));
        err = std::max(err, std::abs(spl[i].nominal - ref[i].nominal));
      }
      batch.add(out / fmt::format("{}_{}.csv", stem, c.name)) << curve_csv(ref, spl, c);
      summary += fmt::format("  {:<12} {} from {} to {}: peak nominal stress {}, spline error {:.2f}%\n",
                             c.name, c.load == LoadCase::SimpleShear ? "shear" : "stretch", c.from, c.to,
                             format_quantity(peak, Dimension::Pressure), 100.0 * err / peak);
    }
    const auto spline_file = out / fmt::format("{}_spline.json", stem);
    batch.add(spline_file) << format_json(material_to_json(spline), spline_file);

    // Indentation: a 3 mm punch into a 10 mm layer, 2 mm deep.
    axisym::PokeSetup setup;
    setup.geometry.punch_radius = 3e-3;
    setup.geometry.thickness = 10e-3;
    axisym::PokeOptions options;
    options.max_depth = 2e-3;
    options.steps = 10;
    options.sensitivities = true;
    axisym::PokeSimulator sim(m, setup);
    const auto curve = sim.run(options);
    CsvTable poke;
    poke.add_comment(fmt::format("{}: punch radius 3 mm, layer 10 mm, stick contact, mesh level 2", stem));
    std::vector<double> depth, force, dfde;
    for (const auto& p : curve.samples) {
      depth.push_back(p.depth);
      force.push_back(p.force);
    }
    poke.add_quantity("indentation", "m", Dimension::Length, depth);
    poke.add_quantity("force", "N", Dimension::Force, force);
    batch.add(out / fmt::format("{}_poke.csv", stem)) << format_csv(poke);
    const auto& last = curve.samples.back();
    std::string sens;
    for (Eigen::Index k = 0; k < m.num_params(); ++k) {
      const ParamInfo info = m.param_info(k);
      // Relative sensitivity: % force change per % parameter change.
      const double rel = last.dforce_dparams[k] * m.params()[k] / last.force;
      sens += fmt::format("{}{} {:+.3f}", sens.empty() ? "" : ", ", info.name, rel);
    }
    summary += fmt::format("  poke         3 mm punch, 10 mm layer: {} at 2 mm ({} Newton iterations); "
                           "d ln F / d ln theta: {}\n",
                           format_quantity(last.force, Dimension::Force), curve.newton_iterations, sens);
    progress.advance();
  }
  progress.finish();

  // Fitting: the foam sample's curves (made with an independent solver, see
  // examples/fit/foam/README.md) -> a spline material.
  const std::filesystem::path dataset = examples / "fit" / "foam" / "dataset.json";
  const std::filesystem::path fit_out = out / "fit-foam";
  const fit::FitSummary f =
      fit::run_fit(dataset, fit_out, fit::FitOptions{}, false, "palpa demo: palpa fit " + dataset.string());
  summary += fmt::format(
      "\nfit {} (spline, Levenberg-Marquardt): sqrt(eps) {:.4g} N after the modulus stage -> {:.4g} N; "
      "RMS error train {:.3g} N, validate {:.3g} N; {:.1f} s. Results in {}\n",
      dataset.lexically_relative(examples).string(), f.sqrt_objective_stage1, f.sqrt_objective_final, f.rms_train,
      f.rms_validate, f.seconds, fit_out.string());
  batch.add(out / "summary.txt") << summary;
  DemoResult result{summary, batch.size()};
  batch.commit();
  folder.keep();
  return result;
}

}  // namespace palpa::pipeline
