// SPDX-License-Identifier: AGPL-3.0-or-later
// `palpa poke` end to end.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/test_support.hpp"

namespace palpa {
namespace {

using test::run_palpa;
using test::ScratchDir;


constexpr const char* kMaterial =
    R"({"model": "neo-hookean-volume", "parameters": {"E": "10 kPa", "nu": 0.45}})";

TEST(PokeCli, WritesTheCurveSensitivitiesAndVtuSeries) {
  ScratchDir dir;
  dir.write("m.json", kMaterial);
  const auto r = run_palpa(
      "poke --material m.json --thickness 10mm --radius 3mm --depth 1mm --steps 4 --mesh-level 0 "
      "--vtu frames --vtu-every 2 --sensitivities sens.csv -o curve.csv",
      dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string curve = test::read_text(dir / "curve.csv");
  EXPECT_NE(curve.find("indentation_m,force_N,newton_iterations"), std::string::npos) << curve;
  EXPECT_NE(curve.find("\n0.001,"), std::string::npos) << curve;  // the full depth, in metres
  EXPECT_NE(test::read_text(dir / "sens.csv").find("indentation_m,dF/dE,dF/dnu,dF/dvolume-share"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir / "frames" / "poke.pvd"));
  EXPECT_TRUE(std::filesystem::exists(dir / "frames" / "poke_0001.vtu"));  // two frames
  EXPECT_NE(r.err.find("poke: depth 1 mm -> force"), std::string::npos) << r.err;
}

// A disk that fills while the outputs are written (a file size limit stands
// in for it: a write beyond it fails as on a full disk, EFBIG for ENOSPC):
// exit 2 naming the file, and nothing left — no frame, no curve, no folder.
TEST(PokeCli, AFullDiskFailsNamingTheFileAndLeavesNothing) {
  ScratchDir dir;
  dir.write("m.json", kMaterial);
  const auto err = dir / "stderr.txt";
  const std::string cmd = fmt::format(
      "cd {} && trap '' XFSZ && ulimit -f 8 && exec '{}' poke --material m.json --thickness 10mm --radius 3mm "
      "--depth 1mm --steps 4 --mesh-level 0 --vtu frames -o curve.csv 2>{} </dev/null",
      test::shell_quote(dir.path()), test::palpa_binary(), test::shell_quote(err));
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  const std::string text = test::read_text(err);
  EXPECT_EQ(WEXITSTATUS(status), 2) << text;
  EXPECT_NE(text.find("frames/poke_"), std::string::npos) << text;
  EXPECT_NE(text.find("writing failed (disk full or the file system refused it)"), std::string::npos) << text;
  EXPECT_FALSE(std::filesystem::exists(dir / "frames"));
  EXPECT_FALSE(std::filesystem::exists(dir / "curve.csv"));
  EXPECT_EQ(dir.entry_count(), 2u) << "the run left files behind";
}

TEST(PokeCli, CompressesACylinderBetweenTwoPlates) {
  for (const char* platens : {"bonded", "frictionless"}) {
    ScratchDir dir;
    dir.write("m.json", kMaterial);
    const auto r = run_palpa(std::string("poke --test compression --contact ") + platens +
                                 " --material m.json --radius 5mm --thickness 5mm --depth 2.5mm --steps 5 "
                                 "--mesh-level 0 --vtu frames --sensitivities sens.csv -o curve.csv",
                             dir.path());
    ASSERT_EQ(r.exit_code, 0) << platens << "\n" << r.err;
    const std::string curve = test::read_text(dir / "curve.csv");
    EXPECT_NE(curve.find(std::string("compression, R = 0.005 m, H = 0.005 m, ") + platens + " platens"),
              std::string::npos)
        << curve;
    EXPECT_NE(curve.find("indentation_m,force_N,newton_iterations"), std::string::npos) << curve;
    EXPECT_NE(curve.find("\n0.0025,"), std::string::npos) << curve;  // 50% of the height
    EXPECT_NE(test::read_text(dir / "sens.csv").find("indentation_m,dF/dE,dF/dnu"), std::string::npos);
    EXPECT_TRUE(std::filesystem::exists(dir / "frames" / "poke.pvd"));
    EXPECT_NE(r.err.find("poke: compression 2.5 mm (50%) -> force"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(std::string("between ") + platens + " platens"), std::string::npos) << r.err;
  }
}

TEST(PokeCli, AFailedDepthWritesTheConvergedOnesMarkedIncomplete) {
  // A softening Yeoh (C20 < 0) loses stability between 1 and 2 mm.
  ScratchDir dir;
  dir.write("soft.json",
            R"({"model": "yeoh", "parameters": {"C10": "8 kPa", "C20": "-3 kPa", "C30": "0 kPa", "D1": "1e-5 1/Pa"}})");
  const auto r = run_palpa(
      "poke --material soft.json --thickness 10mm --radius 3mm --depth 6mm --steps 6 --mesh-level 0 "
      "--sensitivities sens.csv --vtu frames -o curve.csv",
      dir.path());
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("the equilibrium at depth 1."), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("This material stops resisting compression below a uniaxial stretch of 0.63"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("wrote the 1 converged depth, to 1 mm, to curve.csv, marked INCOMPLETE"), std::string::npos)
      << r.err;
  const std::string curve = test::read_text(dir / "curve.csv");
  EXPECT_NE(curve.find("# INCOMPLETE: converged to 1 mm of 6 mm (1 of 6 depths); the next depth failed: the "
                       "equilibrium at depth 1."),
            std::string::npos)
      << curve;
  EXPECT_NE(curve.find("\n0,0,"), std::string::npos) << curve;
  EXPECT_NE(curve.find("\n0.001,"), std::string::npos) << curve;
  EXPECT_EQ(curve.find("\n0.002,"), std::string::npos) << curve;
  const std::string sens = test::read_text(dir / "sens.csv");
  EXPECT_NE(sens.find("INCOMPLETE"), std::string::npos) << sens;
  EXPECT_NE(sens.find("\n0.001,"), std::string::npos) << sens;
  EXPECT_FALSE(std::filesystem::exists(dir / "frames"));
}

// A failed depth says what would help: with a stable material and a sharp
// rim, the cells beside the rim are crushed, and a fillet (not a finer mesh)
// is the remedy; with a fillet, a finer mesh.
TEST(PokeCli, AFailedDepthSaysWhatWouldHelp) {
  ScratchDir dir;
  dir.write("nh.json", R"({"model": "neo-hookean", "parameters": {"E": "54 kPa", "nu": 0.25}})");
  const std::string poke =
      "poke --material nh.json --thickness 10mm --radius 1.03mm --depth 8mm --steps 20 --contact frictionless "
      "--mesh-level 0 --no-extrapolation -o curve.csv";
  const auto sharp = run_palpa(poke, dir.path());
  EXPECT_EQ(sharp.exit_code, 3) << sharp.err;
  EXPECT_NE(sharp.err.find("The sharp rim of the punch crushes the cells beside it, and a finer --mesh-level "
                           "crushes them sooner: a fillet radius (--fillet"),
            std::string::npos)
      << sharp.err;
  const auto rounded = run_palpa(poke + " --fillet 0.1mm", dir.path());
  EXPECT_EQ(rounded.exit_code, 3) << rounded.err;
  EXPECT_NE(rounded.err.find("Try a finer --mesh-level or fewer extreme depths"), std::string::npos) << rounded.err;
  EXPECT_EQ(rounded.err.find("sharp rim"), std::string::npos) << rounded.err;
}

TEST(PokeCli, ExtrapolatesTheForceUnlessAskedNotTo) {
  ScratchDir dir;
  dir.write("m.json", kMaterial);
  const std::string args = "poke --material m.json --thickness 10mm --radius 3mm --depth 0.1mm --steps 1 --mesh-level 1 ";
  ASSERT_EQ(run_palpa(args + "-o extrapolated.csv", dir.path()).exit_code, 0);
  ASSERT_EQ(run_palpa(args + "--no-extrapolation -o fine.csv", dir.path()).exit_code, 0);
  ASSERT_EQ(run_palpa("poke --material m.json --thickness 10mm --radius 3mm --depth 0.1mm --steps 1 --mesh-level 0 "
                      "-o coarse.csv",
                      dir.path())
                .exit_code,
            0);
  const auto last_row = [&](const char* name) {
    const std::string text = test::read_text(dir / name);
    std::istringstream in(text.substr(text.rfind("\n0.0001,") + 1));
    std::vector<double> v;
    for (std::string cell; std::getline(in, cell, ',');) v.push_back(std::stod(cell));
    return v;
  };
  const std::string text = test::read_text(dir / "extrapolated.csv");
  EXPECT_NE(text.find("levels 1 and 0 extrapolated"), std::string::npos) << text;
  EXPECT_NE(text.find(",mesh_correction_N\n"), std::string::npos) << text;
  EXPECT_EQ(test::read_text(dir / "fine.csv").find("mesh_correction"), std::string::npos);
  const double fine = last_row("fine.csv")[1];
  const double coarse = last_row("coarse.csv")[1];
  const std::vector<double> e = last_row("extrapolated.csv");
  EXPECT_NEAR(e[1], 2 * fine - coarse, 1e-12 * fine);
  EXPECT_NEAR(e[7], fine - coarse, 1e-12 * fine);
  EXPECT_LT(e[1], fine);  // the finer mesh is still stiff
}

TEST(PokeCli, BadInputIsRefusedAndNothingIsWritten) {
  struct Bad {
    const char* args;
    const char* message;
  };
  const Bad calls[] = {
      {"--thickness 10 --radius 3mm --depth 1mm", "--thickness: '10' has no unit"},
      {"--thickness 10mm --radius 3kPa --depth 1mm", "is a pressure, not a length"},
      {"--thickness 10mm --radius 3mm --depth 9.5mm", "below 90% of the layer thickness"},
      {"--thickness 10mm --radius 3mm --depth 1mm --contact glue", "unknown contact 'glue'"},
      {"--thickness 10mm --radius 3mm --depth 1mm --element q9", "unknown element 'q9'"},
      {"--thickness 10mm --radius 3mm --depth 1mm --fillet 3mm", "fillet radius"},
      {"--thickness 10mm --radius 3mm --depth 1mm --outer-radius 2mm", "outer radius"},
      {"--thickness 10mm --radius 3mm --depth 1mm --vtu /etc/passwd", "not a folder"},
      {"--thickness 10mm --radius 3mm --depth 1mm --vtu m.json", "--vtu 'm.json' is the same file as --material"},
      {"--thickness 10mm --radius 3mm --depth 1mm --test shear", "unknown test 'shear'"},
      {"--thickness 10mm --radius 3mm --depth 1mm --contact bonded", "--contact bonded is for the platens"},
      {"--test compression --thickness 10mm --radius 3mm --depth 1mm --contact stick",
       "compression platens are bonded or frictionless"},
      {"--test compression --thickness 10mm --radius 3mm --depth 1mm --contact glue",
       "unknown platen contact 'glue'"},
      {"--test compression --thickness 10mm --radius 3mm --depth 1mm --fillet 0.1mm",
       "--fillet does not apply to --test compression"},
      {"--test compression --thickness 10mm --radius 3mm --depth 1mm --outer-radius 20mm",
       "--outer-radius does not apply to --test compression"},
      {"--test compression --thickness 10mm --radius 3mm --depth 9.5mm", "below 90% of the sample height"},
      // Sizes that mean nothing, named with what was given.
      {"--thickness 0mm --radius 3mm --depth 1mm", "--thickness: 0mm is zero (expected a positive value)"},
      {"--thickness 10mm --radius -3mm --depth 1mm", "--radius: -3mm is negative (expected a positive value)"},
      {"--thickness 10mm --radius 3mm --depth 0m", "--depth: 0m is zero"},
      {"--thickness 10mm --radius 3mm --depth 1mm --fillet -0.1mm", "--fillet: -0.1mm is negative"},
      {"--thickness 10mm --radius 3mm --depth 1mm --outer-radius 0mm", "--outer-radius: 0mm is zero"},
      // An output that is another output, or the input, under any spelling.
      {"--thickness 10mm --radius 3mm --depth 1mm --sensitivities ./out.csv",
       "--sensitivities './out.csv' is the same file as --output 'out.csv'"},
      {"--thickness 10mm --radius 3mm --depth 1mm --sensitivities sub/../m.json",
       "would overwrite its input"},
  };
  for (const Bad& b : calls) {
    ScratchDir dir;
    dir.write("m.json", kMaterial);
    const auto r = run_palpa(std::string("poke --material m.json --mesh-level 0 -o out.csv ") + b.args,
                             dir.path());
    EXPECT_EQ(r.exit_code, 2) << b.args << "\n" << r.err;
    EXPECT_NE(r.err.find(b.message), std::string::npos) << b.args << "\nstderr: " << r.err;
    EXPECT_EQ(dir.entry_count(), 1u) << b.args << ": something was written";
  }
  ScratchDir dir;
  const auto r = run_palpa("poke --material none.json --thickness 10mm --radius 3mm --depth 1mm -o out.csv",
                           dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("none.json: file not found"), std::string::npos) << r.err;
  EXPECT_EQ(dir.entry_count(), 0u);
}

}  // namespace
}  // namespace palpa
