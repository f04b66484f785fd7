// SPDX-License-Identifier: AGPL-3.0-or-later
// `palpa fit` end to end.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fmt/format.h>

#include <chrono>
#include <filesystem>

#include "common/test_support.hpp"
#include "fit/bad_datasets.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/core/json.hpp"

namespace palpa {
namespace {

using test::run_palpa;
using test::ScratchDir;

// A layer with ν = 0.3 fitted from a start with the dataset's ν = 0.45: the
// shape stage has something to lower.
constexpr const char* kTruth = R"({"model": "neo-hookean", "parameters": {"E": "20 kPa", "nu": 0.3}})";

std::size_t files_in(const std::filesystem::path& p) {
  std::size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(p)) n += e.is_regular_file() ? 1 : 0;
  return n;
}

// Killed with SIGKILL at five moments of its run, a fit continued with
// --resume ends bit for bit where an uninterrupted fit ends (every checkpoint
// is written whole; the optimizer restarts from the last one exactly: NLCG's
// direction and Levenberg-Marquardt's trust-region radius are in it), and a
// killed run never leaves a report.json presented as finished.
void expect_sigkill_safe(const std::string& optimizer) {
  ScratchDir dir;
  dir.write("truth.json", kTruth);
  ASSERT_EQ(run_palpa("poke --material truth.json --thickness 10mm --radius 3mm --depth 1.5mm --steps 6 "
                      "--mesh-level 0 -o a3mm.csv",
                      dir.path())
                .exit_code,
            0);
  dir.write("dataset.json", R"({"palpa_dataset": 1, "sample": "cli test", "test": "indentation",
    "layer_depth": ["8 mm", "9 mm", "10 mm", "11 mm"], "contact": "stick", "poisson": 0.45,
    "curves": [{"file": "a3mm.csv", "radius": "3 mm", "role": "train"}]})");
  // Four guesses of up to 15 iterations each (about 2 s on 2 cores),
  // checkpointed after every iteration.
  const std::string fit = "fit dataset.json --model neo-hookean --optimizer " + optimizer +
                          " --mesh-level 0 --steps 6 --max-iterations 15 --tolerance 1e-12 -o ";
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(run_palpa(fit + "straight", dir.path()).exit_code, 0);
  const double whole = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const Json straight = Json::parse(test::read_text(dir / "straight" / "report.json"));
  int killed = 0;
  for (const double f : {0.1, 0.3, 0.5, 0.7, 0.9}) {
    const std::string out = fmt::format("killed{:.0f}", 10 * f);
    if (test::run_palpa_killed_after(fit + out, dir.path(), f * whole)) {
      ++killed;
      EXPECT_FALSE(std::filesystem::exists(dir / out / "report.json")) << out;
    }
    const auto r = run_palpa(fit + out + " --resume", dir.path());
    ASSERT_EQ(r.exit_code, 0) << out << "\n" << r.err;
    const Json resumed = Json::parse(test::read_text(dir / out / "report.json"));
    EXPECT_EQ(resumed["objective"]["final"].get<double>(), straight["objective"]["final"].get<double>()) << out;
    EXPECT_EQ(resumed["iterations"], straight["iterations"]) << out;
    const auto parameters = [](const std::string& material) { return material.substr(0, material.find("provenance")); };
    EXPECT_EQ(parameters(test::read_text(dir / out / "material.json")),
              parameters(test::read_text(dir / "straight" / "material.json")))
        << out;
  }
  EXPECT_GE(killed, 3) << "most kills should land inside the run";
}

TEST(FitCli, SurvivesSigkillAtFiveMomentsAndResumesToTheSameResultNlcg) { expect_sigkill_safe("nlcg"); }

TEST(FitCli, SurvivesSigkillAtFiveMomentsAndResumesToTheSameResultLm) { expect_sigkill_safe("lm"); }

TEST(FitCli, WithoutAValidationCurveTheValidationErrorIsNotApplicable) {
  ScratchDir dir;
  std::string csv = "stretch,stress_kPa\n";
  for (int k = 0; k <= 10; ++k) {
    const double l = 0.7 + 0.06 * k;
    csv += fmt::format("{},{}\n", l, 10.0 * (l - 1.0 / (l * l)));  // incompressible neo-Hookean, mu = 10 kPa
  }
  dir.write("uni.csv", csv);
  dir.write("dataset.json", R"({"palpa_dataset": 1, "test": "homogeneous", "poisson": 0.49,
    "curves": [{"file": "uni.csv", "load_case": "uniaxial", "role": "train"}]})");
  const auto r = run_palpa("fit dataset.json -o out --model neo-hookean", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("validate n/a (no validation curve)"), std::string::npos) << r.err;
  const Json report = Json::parse(test::read_text(dir / "out" / "report.json"));
  EXPECT_TRUE(report["rms_error"]["validate"].is_null()) << report["rms_error"];
  EXPECT_EQ(report["rms_error"]["validate_points_measured"], 0);
}

TEST(FitCli, WritesTheMaterialReportCurvesAndPlots) {
  ScratchDir dir;
  dir.write("truth.json", kTruth);
  for (const char* r : {"3mm", "2mm"}) {
    const auto p = run_palpa(fmt::format("poke --material truth.json --thickness 10mm --radius {} --depth 1.5mm "
                                         "--steps 6 --mesh-level 0 -o a{}.csv",
                                         r, r),
                             dir.path());
    ASSERT_EQ(p.exit_code, 0) << p.err;
  }
  dir.write("dataset.json", R"({"palpa_dataset": 1, "sample": "cli test", "test": "indentation",
    "layer_depth": ["9 mm", "10 mm"], "contact": "stick", "poisson": 0.45,
    "curves": [{"file": "a3mm.csv", "radius": "3 mm", "role": "train"},
               {"file": "a2mm.csv", "radius": "2 mm", "role": "validate"}]})");
  const auto r = run_palpa("fit dataset.json -o out --model neo-hookean --mesh-level 0 --steps 6 --max-iterations 4",
                           dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto out = dir / "out";
  for (const char* f : {"material.json", "report.json", "curves/a3mm.csv", "curves/a2mm.csv", "curves.svg",
                        "objective.svg", "depth.svg"}) {
    EXPECT_TRUE(std::filesystem::exists(out / f)) << f;
  }
  const Json report = Json::parse(test::read_text(out / "report.json"));
  EXPECT_EQ(report["test"], "indentation");
  EXPECT_EQ(report["model"], "neo-hookean");
  EXPECT_EQ(report["guesses"].size(), 2u);
  EXPECT_EQ(report["layer_depth_m"], 0.01);  // the depth the data was made at
  const double final_eps = report["objective"]["final"].get<double>();
  const double stage1_eps = report["objective"]["stage1"].get<double>();
  EXPECT_LT(final_eps, stage1_eps);
  ASSERT_TRUE(report["rms_error"].contains("validate"));
  EXPECT_GT(report["rms_error"]["validate"].get<double>(), 0.0);
  EXPECT_LT(report["rms_error"]["validate"].get<double>(), 0.05);  // N, largest force ~0.3 N
  EXPECT_EQ(report["curves"].size(), 2u);
  const std::string material = test::read_text(out / "material.json");
  EXPECT_NE(material.find("\"palpa_material\""), std::string::npos);
  EXPECT_NE(material.find("\"neo-hookean\""), std::string::npos);
  const std::string curve = test::read_text(out / "curves" / "a2mm.csv");
  EXPECT_NE(curve.find("indentation_m,force_measured_N,force_stage1_N,force_fitted_N"), std::string::npos) << curve;
  for (const char* svg : {"curves.svg", "objective.svg", "depth.svg"}) {
    EXPECT_NE(test::read_text(out / svg).find("<svg"), std::string::npos) << svg;
  }
  // The report a person opens: the material, the curves and the search, in a browser.
  const std::string html = test::read_text(out / "report.html");
  for (const char* part : {"<h2>Material</h2>", "<td>E (small strain)</td>", "<td>a2mm</td><td>validate</td>",
                           "layer-depth search", "data:image/svg+xml;base64,"}) {
    EXPECT_NE(html.find(part), std::string::npos) << part;
  }
  const auto page = test::check_page_in_browser(out / "report.html");
  EXPECT_EQ(page.exit_code, 0) << page.out << page.err;
  EXPECT_NE(r.err.find("fit: layer depth 10 mm"), std::string::npos) << r.err;
  // How sure: E's 95% interval around E, in the report and the summary; the
  // best depth is the deeper end of the two searched, and a warning says so.
  const Json& u = report["uncertainty"];
  ASSERT_TRUE(u["defined"].get<bool>()) << u.dump();
  const Json& e = u["estimates"][0];
  EXPECT_EQ(e["name"], "E");
  EXPECT_LT(e["lo95"].get<double>(), e["value"].get<double>());
  EXPECT_GT(e["hi95"].get<double>(), e["value"].get<double>());
  EXPECT_NE(r.err.find("E (small strain) = "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(", 95% "), std::string::npos) << r.err;
  ASSERT_FALSE(report["warnings"].empty());
  EXPECT_NE(report["warnings"].dump().find("end of the searched depths"), std::string::npos) << report["warnings"];
  EXPECT_NE(r.err.find("warning: fit: the lowest objective is at an end"), std::string::npos) << r.err;

  // The folder is now not empty: refused without --resume or --overwrite, and untouched.
  const auto before = std::filesystem::last_write_time(out / "report.json");
  const auto again = run_palpa("fit dataset.json -o out --model neo-hookean --mesh-level 0", dir.path());
  EXPECT_EQ(again.exit_code, 2) << again.err;
  EXPECT_NE(again.err.find("output folder 'out' is not empty"), std::string::npos) << again.err;
  EXPECT_EQ(std::filesystem::last_write_time(out / "report.json"), before);

  // --resume on the finished fit says so and changes nothing; with other
  // options it refuses, naming what differs.
  const auto done = run_palpa(
      "fit dataset.json -o out --model neo-hookean --mesh-level 0 --steps 6 --max-iterations 4 --resume", dir.path());
  EXPECT_EQ(done.exit_code, 0) << done.err;
  EXPECT_NE(done.err.find("is finished (report.json); nothing to resume"), std::string::npos) << done.err;
  EXPECT_EQ(std::filesystem::last_write_time(out / "report.json"), before);
  const auto other = run_palpa(
      "fit dataset.json -o out --model neo-hookean --mesh-level 0 --steps 6 --max-iterations 9 --resume", dir.path());
  EXPECT_EQ(other.exit_code, 2) << other.err;
  EXPECT_NE(other.err.find("the fit options differ"), std::string::npos) << other.err;
  EXPECT_EQ(std::filesystem::last_write_time(out / "report.json"), before);
}

TEST(FitCli, BadDatasetsAreRefusedAndNothingIsWritten) {
  for (const auto& bad : fit::test::bad_datasets()) {
    ScratchDir dir;
    for (const auto& [name, text] : bad.files) dir.write(name, text);
    dir.write("dataset.json", bad.dataset);
    const auto r = run_palpa("fit dataset.json -o out --mesh-level 0", dir.path());
    EXPECT_EQ(r.exit_code, 2) << bad.what << "\n" << r.err;
    for (const auto& f : bad.fragments) EXPECT_NE(r.err.find(f), std::string::npos) << bad.what << ": " << f << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out")) << bad.what << ": the output folder was created";
  }
}

// An option out of its range is named with a range a person can read (not
// "0 to 1.797...e308" written out in 309 digits).
TEST(FitCli, OptionsOutOfRangeAreNamedWithTheirRange) {
  ScratchDir dir;
  dir.write("a.csv", fit::test::kGoodCurve);
  dir.write("dataset.json", fit::test::indentation_dataset());
  for (const char* bad : {"--tolerance -1", "--tolerance 0", "--smoothing -1", "--tolerance nan", "--smoothing nan",
                          "--smoothing inf", "--starts 11", "--mesh-level 8"}) {
    const auto r = run_palpa(fmt::format("fit dataset.json -o out {}", bad), dir.path());
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find(std::string(bad).substr(0, std::string(bad).find(' '))), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("not in range"), std::string::npos) << r.err;
    EXPECT_LT(r.err.size(), 200u) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out")) << bad;
  }
}

TEST(FitCli, ANonEmptyOutputFolderOrAMissingCheckpointIsRefused) {
  ScratchDir dir;
  dir.write("a.csv", fit::test::kGoodCurve);
  dir.write("dataset.json", fit::test::indentation_dataset());
  std::filesystem::create_directories(dir / "out");
  dir.write("out/notes.txt", "mine");
  const auto r = run_palpa("fit dataset.json -o out --mesh-level 0", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("output folder 'out' is not empty"), std::string::npos) << r.err;
  EXPECT_EQ(files_in(dir / "out"), 1u);
  EXPECT_EQ(test::read_text(dir / "out" / "notes.txt"), "mine");

  // --resume without a checkpoint starts afresh (a workflow can always pass
  // it), in an empty folder only: here it is refused without claiming to
  // start, and without offering the --resume it was given.
  const auto resume2 = run_palpa("fit dataset.json -o out --resume --mesh-level 0", dir.path());
  EXPECT_EQ(resume2.exit_code, 2) << resume2.err;
  EXPECT_EQ(resume2.err.find("starting afresh"), std::string::npos) << resume2.err;
  EXPECT_NE(resume2.err.find("output folder 'out' is not empty"), std::string::npos) << resume2.err;
  EXPECT_EQ(resume2.err.find("--resume to continue"), std::string::npos) << resume2.err;
  // A bad option found only when the fit starts leaves no folder behind.
  const auto model = run_palpa("fit dataset.json -o fresh --resume --mesh-level 0 --model nosuch", dir.path());
  EXPECT_EQ(model.exit_code, 2) << model.err;
  EXPECT_NE(model.err.find("nosuch"), std::string::npos) << model.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "fresh"));
  EXPECT_EQ(files_in(dir / "out"), 1u);
}

// A second run into a folder that a run is writing into is refused, before it
// writes anything, with or without --overwrite.
TEST(FitCli, ASecondRunIntoABusyFolderIsRefused) {
  ScratchDir dir;
  dir.write("a.csv", fit::test::kGoodCurve);
  dir.write("dataset.json", fit::test::indentation_dataset());
  OutputFolder busy(dir / "out");  // this process plays the run in progress
  for (const char* extra : {"", " --overwrite", " --resume"}) {
    const auto r = run_palpa(fmt::format("fit dataset.json -o out --mesh-level 0{}", extra), dir.path());
    EXPECT_EQ(r.exit_code, 2) << extra << r.err;
    EXPECT_NE(r.err.find(fmt::format("another palpa run (process {}) is writing into this output folder", ::getpid())),
              std::string::npos)
        << r.err;
    EXPECT_EQ(files_in(dir / "out"), 1u);  // the lock alone
  }
}

// An input inside the output folder is never replaced by an output, even with
// --overwrite: the fit is refused before it starts and writes nothing.
TEST(FitCli, AnInputInsideTheOutputFolderIsNotOverwritten) {
  ScratchDir dir;
  dir.write("a.csv", fit::test::kGoodCurve);
  dir.write("dataset.json", fit::test::indentation_dataset());
  std::filesystem::create_directories(dir / "prev");
  dir.write("prev/material.json", kTruth);
  const auto r = run_palpa(
      "fit dataset.json --model neo-hookean --initial prev/material.json -o prev --overwrite --mesh-level 0",
      dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("prev/material.json: is one of this run's inputs"), std::string::npos) << r.err;
  EXPECT_EQ(test::read_text(dir / "prev" / "material.json"), kTruth);
  EXPECT_EQ(files_in(dir / "prev"), 1u);
}

}  // namespace
}  // namespace palpa
