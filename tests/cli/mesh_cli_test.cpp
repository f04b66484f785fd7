// SPDX-License-Identifier: AGPL-3.0-or-later
// `palpa mesh` end to end: a test body and a soft layer around its core with
// every output file, depth samples from a CSV, and bad input failing with exit
// code 2, a message naming the file and place, and no output at all.

#include <fmt/format.h>
#include <unistd.h>
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "common/test_support.hpp"
#include "palpa/core/json.hpp"

namespace palpa {
namespace {

using test::shell_quote;

class MeshCli : public ::testing::Test {
 protected:
  test::ScratchDir in;
  test::ScratchDir out;

  // A 100 mm sphere with 10 mm edges, in metres.
  std::filesystem::path sphere() {
    const auto p = in / "sphere.obj";
    const test::CommandResult r =
        test::run_palpa("mesh body sphere --length 100mm --edge 10mm -o " + shell_quote(p));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return p;
  }

  void expect_failure(const std::string& args, const std::vector<std::string>& fragments) {
    const test::CommandResult r = test::run_palpa("mesh " + args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    for (const std::string& f : fragments) {
      EXPECT_NE(r.err.find(f), std::string::npos) << "stderr lacks '" << f << "':\n" << r.err;
    }
    EXPECT_EQ(out.entry_count(), 0u) << "the output folder is not empty";
  }
};

TEST_F(MeshCli, LayerOfASphereWritesEveryOutputAndTheShellVolume) {
  const auto s = sphere();
  const test::CommandResult r = test::run_palpa("mesh layer --surface " + shell_quote(s) +
                                                " --depth 10mm --edge 10mm -o " + shell_quote(out / "b.vtu"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"b.vtu", "b.node", "b.ele", "b.face", "b_core.obj", "b_outer.obj",
                        "b_attached.csv", "b_summary.json"}) {
    EXPECT_TRUE(std::filesystem::exists(out / f)) << f;
  }
  EXPECT_EQ(out.entry_count(), 8u);
  const Json j = read_json_file(out / "b_summary.json");
  EXPECT_EQ(j["elements"]["inverted_tets"].get<int>(), 0);
  const double shell = 4.0 / 3.0 * std::numbers::pi * (std::pow(0.05, 3) - std::pow(0.04, 3));
  // Inscribed polyhedra with 10 mm edges: 4 %.
  EXPECT_NEAR(j["volume_m3"]["layer"].get<double>(), shell, 0.04 * shell);
  EXPECT_NEAR(j["thickness_m"]["mean"].get<double>(), 0.01, 1e-3);
  EXPECT_GT(j["attached_vertices"].get<int>(), 100);
  EXPECT_NE(test::read_text(out / "b_attached.csv").find("vertex\n"), std::string::npos);
}

// A side output (<name>_core.obj beside -o) that is the input surface is
// refused, and nothing is written: the input stays as it was.
// The staging folder of a run killed between its final renames is cleared
// by the next run into that folder; one of a running process stays.
// Past a file-size limit (ulimit -f) the write fails as on a full disk: an
// input error naming the file, nothing left behind (the signal the limit
// sends would end the run with its temporary file left).
TEST_F(MeshCli, AFileSizeLimitIsAFailedWriteWithNothingLeft) {
  const test::CommandResult r =
      test::run_shell(fmt::format("ulimit -f 20; {} mesh body sphere --length 100mm --edge 2mm -o {}",
                                  shell_quote(test::palpa_binary()), shell_quote(out / "s.obj")));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("s.obj: writing failed"), std::string::npos) << r.err;
  EXPECT_EQ(out.entry_count(), 0u) << "something was left behind";
}

TEST_F(MeshCli, StagedFilesLeftByAKilledRunAreCleared) {
  const std::string dead = ".tmp-4194304-b0.b.node";  // above any pid the kernel hands out
  out.write(dead, "half");
  const std::string alive = fmt::format(".tmp-{}-b0.c.node", ::getpid());
  out.write(alive, "in progress");
  const test::CommandResult r = test::run_palpa("mesh layer --surface " + shell_quote(sphere()) +
                                                " --depth 10mm --edge 10mm -o " + shell_quote(out / "b.vtu"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out / dead));
  EXPECT_TRUE(std::filesystem::exists(out / alive));
  EXPECT_TRUE(std::filesystem::exists(out / "b.vtu"));
}

TEST_F(MeshCli, ASideOutputThatIsTheInputIsRefused) {
  const auto s = sphere();
  std::filesystem::copy_file(s, out / "b_core.obj");
  const std::string before = test::read_text(out / "b_core.obj");
  const test::CommandResult r = test::run_palpa("mesh layer --surface " + shell_quote(out / "b_core.obj") +
                                                " --depth 10mm --edge 10mm -o " + shell_quote(out / "b.vtu"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("b_core.obj: is one of this run's inputs"), std::string::npos) << r.err;
  EXPECT_EQ(test::read_text(out / "b_core.obj"), before);
  EXPECT_EQ(out.entry_count(), 1u);
}

// SIGTERM and SIGINT inside a library call that never checks for them end
// the run within the documented second (0.8 s of grace, then the watchdog):
// exit 143 / 130, nothing left.
TEST_F(MeshCli, ASignalInsideTheRemeshingEndsTheRunWithinASecond) {
  // A sphere 12 m across (a scan in a wrong unit, warned about) remeshed to
  // 20 mm edges: 2.6 million triangles, within what palpa makes, and minutes
  // of remeshing.
  const auto s = sphere();
  const auto mm = in / "sphere_mm.obj";
  ASSERT_EQ(test::run_palpa("convert " + shell_quote(s) + " " + shell_quote(mm) + " --unit '120 m'").exit_code, 0);
  const auto err = in / "stderr";
  for (const auto& [signal, code] : {std::pair{"TERM", 143}, std::pair{"INT", 130}}) {
    const std::string cmd = fmt::format(
        "cd {} && timeout --preserve-status -s {} 2 '{}' mesh layer --surface {} --depth 10mm --edge 20mm -o b.vtu "
        "2>{} </dev/null",
        shell_quote(out.path()), signal, test::palpa_binary(), shell_quote(mm), shell_quote(err));
    const auto t0 = std::chrono::steady_clock::now();
    const int status = std::system(cmd.c_str());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_TRUE(WIFEXITED(status)) << signal;
    EXPECT_EQ(WEXITSTATUS(status), code) << signal;
    const std::string text = test::read_text(err);
    EXPECT_NE(text.find("m across: if its coordinates are in millimetres"), std::string::npos) << text;
    EXPECT_NE(text.find("palpa: interrupted"), std::string::npos) << text;
    // 2 s until the signal, then the second; half a second more for a loaded
    // machine.
    EXPECT_LT(seconds - 2.0, 1.5) << signal << "\n" << text;
    EXPECT_EQ(out.entry_count(), 0u) << signal << ": an interrupted run left files behind";
  }
}

TEST_F(MeshCli, DepthAndStiffnessSamplesFromCsv) {
  const auto s = sphere();
  const auto depths = in.write("depths.csv",
                               "# bone distance, sphere\nx_mm,y_mm,z_mm,bone_distance_mm\n"
                               "50,0,0,8\n-50,0,0,12\n0,50,0,10\n0,0,50,9\n0,0,-50,11\n");
  const auto moduli = in.write("moduli.csv",
                               "x_mm,y_mm,z_mm,youngs_modulus_kPa\n50,0,0,5\n-50,0,0,15\n");
  const test::CommandResult r = test::run_palpa(
      "mesh layer --surface " + shell_quote(s) + " --depth-samples " + shell_quote(depths) +
      " --depth-column bone_distance --stiffness-samples " + shell_quote(moduli) + " --edge 10mm -o " +
      shell_quote(out / "b.vtu"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json j = read_json_file(out / "b_summary.json");
  EXPECT_DOUBLE_EQ(j["requested_depth_m"]["min"].get<double>(), 0.008);
  EXPECT_DOUBLE_EQ(j["requested_depth_m"]["max"].get<double>(), 0.012);
  EXPECT_GE(j["youngs_modulus_Pa"]["min"].get<double>(), 5e3 * (1 - 1e-12));
  EXPECT_LE(j["youngs_modulus_Pa"]["max"].get<double>(), 15e3 * (1 + 1e-12));
}

TEST_F(MeshCli, BadInputLeavesNothing) {
  const auto s = sphere();
  // An open surface: the sphere without its last triangle.
  std::string text = test::read_text(s);
  text.erase(text.rfind("f "));
  const auto open = in.write("open.obj", text);
  expect_failure("layer --surface " + shell_quote(open) + " --depth 10mm --edge 10mm -o " + shell_quote(out / "b.vtu"),
                 {"open.obj", "open"});
  expect_failure("layer --surface " + shell_quote(s) + " --depth 85mm --edge 10mm -o " + shell_quote(out / "b.vtu"),
                 {"sphere.obj", "does not fit"});
  const auto far = in.write("far.csv", "x_mm,y_mm,z_mm,depth_mm\n50,0,0,8\n0,0,90,9\n");
  expect_failure("layer --surface " + shell_quote(s) + " --depth-samples " + shell_quote(far) + " --edge 10mm -o " +
                     shell_quote(out / "b.vtu"),
                 {"far.csv", "line 3", "from the surface"});
  expect_failure("layer --surface " + shell_quote(s) + " --edge 10mm -o " + shell_quote(out / "b.vtu"),
                 {"--depth", "no layer depth"});
  for (const char* depth : {"--depth=-5mm", "--depth 0mm"}) {
    expect_failure("layer --surface " + shell_quote(s) + " " + depth + " --edge 10mm -o " + shell_quote(out / "b.vtu"),
                   {"option --depth", "a layer depth of", "a positive length"});
  }
  expect_failure("layer --surface " + shell_quote(s) + " --depth=-5mm --depth-samples " + shell_quote(far) +
                     " --edge 10mm -o " + shell_quote(out / "b.vtu"),
                 {"both --depth and --depth-samples given"});
  expect_failure("body hand -o " + shell_quote(out / "h.obj"), {"'hand'"});
  // Sizes that mean nothing are refused, not replaced by the defaults.
  expect_failure("body sphere --length 0mm -o " + shell_quote(out / "h.obj"), {"--length: 0mm is zero"});
  expect_failure("body block --length 40mm --width -1mm --height 10mm -o " + shell_quote(out / "h.obj"),
                 {"--width: -1mm is negative"});
  expect_failure("layer --surface " + shell_quote(s) + " --depth 10mm --tet-size 0mm -o " + shell_quote(out / "b.vtu"),
                 {"--tet-size: 0mm is zero"});
  expect_failure("body sphere --length 10mm --edge 5mm -o " + shell_quote(out / "h.obj"),
                 {"option --edge", "an edge of 5 mm for a sphere whose smallest feature is"});
  // Work beyond what palpa makes is refused at once, naming the option.
  expect_failure("body sphere --length 10m --edge 1mm -o " + shell_quote(out / "h.obj"),
                 {"option --edge", "a sphere of", "would make about", "triangles"});
  expect_failure("layer --surface " + shell_quote(s) + " --unit '1000 m' --depth 10mm --edge 10mm -o " +
                     shell_quote(out / "b.vtu"),
                 {"option --edge", "sphere.obj of", "would make about", "--unit"});
}

}  // namespace
}  // namespace palpa
