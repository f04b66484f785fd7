// `palpa acquire` end to end on the synthetic example recordings.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "common/test_support.hpp"

namespace palpa {
namespace {

using test::run_palpa;
using test::ScratchDir;

// Copies the example poke logs into `dir`.
void copy_poke_example(const ScratchDir& dir) {
  for (const char* f : {"force.csv", "laser.csv", "laser-calibration.csv"}) {
    std::filesystem::copy_file(test::source_path(std::string("examples/acquire/poke/") + f), dir / f);
  }
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

}  // namespace
}  // namespace palpa
