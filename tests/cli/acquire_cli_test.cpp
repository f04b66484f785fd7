// SPDX-License-Identifier: AGPL-3.0-or-later
// `palpa acquire` end to end on the synthetic example recordings.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <initializer_list>
#include <sstream>
#include <string>

#include "common/test_support.hpp"
#include "palpa/core/json.hpp"

namespace palpa {
namespace {

using test::run_palpa;
using test::ScratchDir;

// Copies the files of examples/acquire/<folder> into `dir`.
void copy_example(const ScratchDir& dir, const std::string& folder, std::initializer_list<const char*> files) {
  for (const char* f : files) {
    std::filesystem::copy_file(test::source_path("examples/acquire/" + folder + "/" + f), dir / f);
  }
}

void copy_poke_example(const ScratchDir& dir) {
  copy_example(dir, "poke", {"force.csv", "laser.csv", "laser-calibration.csv"});
}

// `text` with the first occurrence of `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

constexpr const char* kPoke = "acquire poke --force force.csv --laser laser.csv --calibration laser-calibration.csv ";

TEST(AcquireCli, PokeWritesACurveThatFitDatasetsRead) {
  ScratchDir dir;
  copy_poke_example(dir);
  const auto r = run_palpa(std::string(kPoke) + "-o curve.csv --unloading unloading.csv --plots plots "
                                                "--summary summary.json --points 20",
                           dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string curve = test::read_text(dir / "curve.csv");
  EXPECT_NE(curve.find("indentation_m,force_N\n0,"), std::string::npos) << curve;
  EXPECT_NE(test::read_text(dir / "unloading.csv").find("indentation_m,force_N"), std::string::npos);
  EXPECT_NE(test::read_text(dir / "plots" / "signals.svg").find("<svg"), std::string::npos);
  EXPECT_NE(test::read_text(dir / "plots" / "curve.svg").find("<svg"), std::string::npos);
  const std::string summary = test::read_text(dir / "summary.json");
  EXPECT_NE(summary.find("\"clock_shift_s\": -12.34"), std::string::npos) << summary;
  EXPECT_NE(r.err.find("acquire poke: force 100 Hz, laser 500 Hz"), std::string::npos) << r.err;
  // palpa fit reads the curve.
  dir.write("dataset.json", R"({"palpa_dataset": 1, "sample": "synthetic", "test": "indentation",
    "layer_depth": "20 mm", "contact": "stick", "curves": [{"file": "curve.csv", "radius": "3 mm", "role": "train"}]})");
  const auto fit = run_palpa("fit dataset.json --modulus-only --mesh-level 0 --steps 4 -o fit", dir.path());
  EXPECT_EQ(fit.exit_code, 0) << fit.err;
}

TEST(AcquireCli, PokeRefusesBadLogsAndWritesNothing) {
  struct Bad {
    const char* file;  // file to corrupt
    const char* from;
    const char* to;    // replacement; "" with a non-empty `until`: cut from `from` to `until`
    const char* until;
    const char* args;  // extra arguments
    const char* message;
  };
  const Bad cases[] = {
      {"force.csv", "\n1.000000,", "\n0.900000,", "", "", "force.csv:133:1: column 'time_s': time 0.9 s is not after"},
      {"force.csv", "\n1.000000,0.04311", "\n1.000000,nan", "", "", "force.csv:133"},
      {"laser.csv", "\n12.845000,", "", "\n12.945000,", "", "laser.csv:253:1: column 'time_s': a gap of 0.102 s"},
      {"laser-calibration.csv", "\n1,", "\n0.4,", "", "", "laser-calibration.csv:5: input column: the calibration is not monotone"},
      {"force.csv", "", "", "", "--force-columns time,load", "no column 'load'"},
      {"force.csv", "", "", "", "--force-window 3s,2s", "START before END"},
      {"force.csv", "", "", "", "--rest 3s", "no rest plateau found"},
      {"force.csv", "", "", "", "--cutoff 60Hz", "Nyquist"},
      {"force.csv", "", "", "", "--force-columns time", "2 comma-separated"},
      {"force.csv", "", "", "", "--rest 0s", "--rest: 0s is zero (expected a positive value)"},
      {"force.csv", "", "", "", "--saturation -1s", "--saturation: -1s is negative (expected a positive value)"},
      {"force.csv", "", "", "", "--cutoff 0Hz", "--cutoff: 0Hz is zero"},
      {"force.csv", "", "", "", "--points 100000000", "100000000 grid points (expected 3 to 100000)"},
      {"force.csv", "", "", "", "--max-gap nan", "--max-gap: nan is not in range [1.5 - 1e+06] (a finite number)"},
      {"force.csv", "", "", "", "--rest-tolerance nan", "--rest-tolerance: nan is not in range"},
  };
  for (const Bad& b : cases) {
    ScratchDir dir;
    copy_poke_example(dir);
    std::string text = test::read_text(dir / b.file);
    if (*b.until != 0) {
      const auto from = text.find(b.from), until = text.find(b.until);
      ASSERT_TRUE(from != std::string::npos && until != std::string::npos && from < until) << b.message;
      text.erase(from, until - from);
    } else if (*b.from != 0) {
      text = replaced(text, b.from, b.to);
    }
    dir.write(b.file, text);
    const auto r = run_palpa(std::string(kPoke) + "-o curve.csv --plots plots --summary s.json " + b.args, dir.path());
    EXPECT_EQ(r.exit_code, 2) << b.message << "\n" << r.err;
    EXPECT_NE(r.err.find(b.message), std::string::npos) << b.message << "\nstderr: " << r.err;
    EXPECT_EQ(dir.entry_count(), 3u) << b.message << ": something was written";
  }
}

// A side output that is a folder is refused with nothing written, the plots
// folder the run had created included.
TEST(AcquireCli, PokeWithASummaryThatIsAFolderWritesNothing) {
  ScratchDir dir;
  copy_poke_example(dir);
  std::filesystem::create_directory(dir / "taken");
  const auto r = run_palpa(std::string(kPoke) + "-o curve.csv --plots plots --summary taken", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("taken: output path is a folder"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "plots"));
  EXPECT_EQ(dir.entry_count(), 4u) << "something was written";
}

TEST(AcquireCli, PokeRefusesAClippedForceGauge) {
  ScratchDir dir;
  copy_poke_example(dir);
  // Every force above 6 N reads exactly 6 N.
  std::string text = "time_s,force_N\n";
  const std::string original = test::read_text(dir / "force.csv");
  std::size_t pos = original.find("time_s,force_N\n") + 15;
  while (pos < original.size()) {
    const std::size_t eol = original.find('\n', pos);
    const std::string line = original.substr(pos, eol - pos);
    const auto comma = line.find(',');
    const double f = std::stod(line.substr(comma + 1));
    text += line.substr(0, comma + 1) + (f > 6.0 ? std::string("6.00000") : line.substr(comma + 1)) + "\n";
    pos = eol + 1;
  }
  dir.write("force.csv", text);
  const auto r = run_palpa(std::string(kPoke) + "-o curve.csv", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("force.csv:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("the sensor is saturated"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "curve.csv"));
}

void copy_ultrasound_example(const ScratchDir& dir) {
  copy_example(dir, "ultrasound", {"force.csv", "fat.csv", "bone.csv"});
}

constexpr const char* kUltrasound = "acquire ultrasound --force force.csv --interface fat=fat.csv --interface bone=bone.csv ";

TEST(AcquireCli, UltrasoundWritesDepthsAndBuildsADepthTable) {
  ScratchDir dir;
  copy_ultrasound_example(dir);
  auto r = run_palpa(std::string(kUltrasound) + "-o depths.csv --plots plots --summary s.json "
                                                "--depth-table table.csv --position 10mm,20mm,300mm",
                     dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(test::read_text(dir / "depths.csv").find("time_s,force_N,fat_depth_m,bone_depth_m"), std::string::npos);
  EXPECT_NE(test::read_text(dir / "plots" / "depths.svg").find("<svg"), std::string::npos);
  EXPECT_NE(r.err.find("rest depths fat 8"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bone 24"), std::string::npos) << r.err;
  // A second location, then the first again (replaced, not repeated).
  r = run_palpa(std::string(kUltrasound) + "-o d2.csv --depth-table table.csv --position 10mm,20mm,320mm",
                dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_palpa(std::string(kUltrasound) + "-o d3.csv --depth-table table.csv --position 10mm,20mm,300mm "
                                           "--depth-interface fat",
                dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string table = test::read_text(dir / "table.csv");
  EXPECT_NE(table.find("x_m,y_m,z_m,depth_m,fat_depth_m,bone_depth_m\n0.01,0.02,0.32,0.024"), std::string::npos)
      << table;
  EXPECT_NE(table.find("\n0.01,0.02,0.3,0.008"), std::string::npos) << table;  // depth_m = fat now
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 4) << table;     // comment, header, 2 rows
}

TEST(AcquireCli, UltrasoundRefusesBadOptionsAndWritesNothing) {
  struct Bad {
    const char* args;
    const char* message;
  };
  const Bad cases[] = {
      {"--interface fat -o d.csv", "is not a new interface NAME=FILE"},
      {"--interface fat=fat.csv -o d.csv", "is not a new interface"},
      {"-o d.csv --depth-table t.csv", "--depth-table and --position go together"},
      {"-o d.csv --depth-table t.csv --position 1mm,2mm", "is not a position"},
      {"-o d.csv --depth-table t.csv --position 1mm,2mm,3mm --depth-interface skin", "there is no interface 'skin'"},
      {"-o d.csv --offset 10s --no-align", "cover"},
      {"-o bone.csv", "--output 'bone.csv' is the same file as --interface 'bone=bone.csv'"},
  };
  for (const Bad& b : cases) {
    ScratchDir dir;
    copy_ultrasound_example(dir);
    const auto r = run_palpa(std::string(kUltrasound) + b.args, dir.path());
    EXPECT_EQ(r.exit_code, 2) << b.args << "\n" << r.err;
    EXPECT_NE(r.err.find(b.message), std::string::npos) << b.args << "\nstderr: " << r.err;
    EXPECT_EQ(dir.entry_count(), 3u) << b.args << ": something was written";
  }
}

void copy_pressure_example(const ScratchDir& dir) {
  copy_example(dir, "pressure", {"support.obj", "locations.csv", "samples.csv"});
}

constexpr const char* kPressure =
    "acquire pressure --mesh support.obj --locations locations.csv --samples samples.csv --load 343N ";

TEST(AcquireCli, PressureWritesPlyVtuAndASummary) {
  ScratchDir dir;
  copy_pressure_example(dir);
  const auto r = run_palpa(std::string(kPressure) + "-o map", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(test::read_text(dir / "map" / "pressure.ply").find("property double pressure_std_Pa"), std::string::npos);
  const std::string vtu = test::read_text(dir / "map" / "pressure.vtu");
  EXPECT_NE(vtu.find("Name=\"pressure_Pa\""), std::string::npos);
  EXPECT_NE(vtu.find("Name=\"pressure_std_Pa\""), std::string::npos);
  EXPECT_NE(test::read_text(dir / "map" / "locations.csv").find("pressure_Pa,pressure_std_Pa"), std::string::npos);
  const std::string summary = test::read_text(dir / "map" / "summary.json");
  EXPECT_NE(summary.find("\"posture_compensated\": true"), std::string::npos) << summary;
  EXPECT_NE(r.err.find("net force 343 N"), std::string::npos) << r.err;
  // The figures every rest and design summary reports per side.
  const Json s = Json::parse(summary);
  const Json& m = s.at("pressure_map");
  EXPECT_DOUBLE_EQ(m.at("peak_Pa").get<double>(), s.at("pressure_max_Pa").get<double>());
  EXPECT_NEAR(m.at("contact_area_m2").get<double>(), s.at("contact_area_m2").get<double>(),
              1e-9 * s.at("contact_area_m2").get<double>());
  EXPECT_GT(m.at("peak_pressure_index_Pa").get<double>(), 0.0);
  EXPECT_LE(m.at("peak_pressure_index_Pa").get<double>(), m.at("peak_Pa").get<double>());
  EXPECT_LE(m.at("p95_Pa").get<double>(), m.at("peak_Pa").get<double>());
  // On the flat plate the map's own force Σ p·A is the load; it ends one
  // sensor spacing (the 12 locations are 2 cm apart) beyond the mat.
  EXPECT_NEAR(m.at("force_N").get<double>(), 343.0, 1e-6);
  EXPECT_NEAR(s.at("reach_m").get<double>(), 0.02, 1e-12);
  EXPECT_LT(s.at("covered_area_m2").get<double>(), 0.0099);
  const auto whole = run_palpa(std::string(kPressure) + "--reach 20cm -o whole", dir.path());
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  const Json w = Json::parse(test::read_text(dir / "whole" / "summary.json"));
  EXPECT_NEAR(w.at("covered_area_m2").get<double>(), 0.01, 1e-12);  // the whole 10 cm plate
  EXPECT_NEAR(w.at("pressure_map").at("force_N").get<double>(), 343.0, 1e-6);
}

TEST(AcquireCli, PressureRefusesBadInputAndWritesNothing) {
  struct Bad {
    const char* file;
    const char* from;
    const char* to;
    const char* args;
    const char* message;
  };
  const Bad cases[] = {
      {"locations.csv", "\n7,10,0,0", "\n7,10,0,30", "", "location 7 (locations.csv:9)"},
      {"samples.csv", "\n1,", "\n13,", "", "samples.csv:3:1: column 'location': location 13 is not in the locations"},
      {"samples.csv", "\n1,0.", "\n1,nan", "", "samples.csv:3"},
      {"locations.csv", "", "", "--trim 300", "location 1 has 600 samples"},
      {"locations.csv", "", "", "--method spline", "unknown interpolation 'spline'"},
      {"locations.csv", "", "", "--unit kPa", "'kPa' is not a length unit"},
      {"locations.csv", "", "", "--max-distance 0mm", "--max-distance: 0mm is zero"},
      {"locations.csv", "", "", "--reach 0mm", "--reach: 0mm is zero"},
  };
  for (const Bad& b : cases) {
    ScratchDir dir;
    copy_pressure_example(dir);
    if (*b.from != 0) dir.write(b.file, replaced(test::read_text(dir / b.file), b.from, b.to));
    const auto r = run_palpa(std::string(kPressure) + "-o map " + b.args, dir.path());
    EXPECT_EQ(r.exit_code, 2) << b.message << "\n" << r.err;
    EXPECT_NE(r.err.find(b.message), std::string::npos) << b.message << "\nstderr: " << r.err;
    EXPECT_EQ(dir.entry_count(), 3u) << b.message << ": something was written";
  }
}

// A location whose sensor reads below zero on average (an offset left in)
// would become a pull on the map: refused by location and column.
TEST(AcquireCli, PressureRefusesANegativeMeanReading) {
  ScratchDir dir;
  copy_pressure_example(dir);
  std::istringstream in(test::read_text(dir / "samples.csv"));
  std::string text, line;
  while (std::getline(in, line)) text += (line.rfind("3,", 0) == 0 ? "3,-" + line.substr(2) : line) + "\n";
  dir.write("samples.csv", text);
  const auto r = run_palpa(std::string(kPressure) + "-o map", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  for (const char* f : {"samples.csv", "column 'reading_V'", "the mean reading at location 3 is -", "below zero"}) {
    EXPECT_NE(r.err.find(f), std::string::npos) << f << "\n" << r.err;
  }
  EXPECT_EQ(dir.entry_count(), 3u) << "something was written";
}

}  // namespace
}  // namespace palpa
