// SPDX-License-Identifier: AGPL-3.0-or-later
// `palpa material` and the top-level options end to end: results on good input, and for
// bad input a clear message, exit code 2 and nothing written.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <link.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "common/test_support.hpp"

namespace palpa {
namespace {

using test::run_palpa;
using test::ScratchDir;


TEST(MaterialCli, WritesShowsAndPlotsAMaterial) {
  ScratchDir dir;
  auto r = run_palpa("material --model neo-hookean --E 12kPa --nu 0.45 -o m.json", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(test::read_text(dir / "m.json").find("\"E\": \"12 kPa\""), std::string::npos);

  r = run_palpa("material show m.json", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("small strain: E = 12 kPa, nu = 0.45"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("volumetric term: logarithmic"), std::string::npos) << r.out;

  r = run_palpa("material curve m.json --test uniaxial --stretch 0.8:1.2 --points 3 -o c.csv",
                dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("wrote c.csv: uniaxial test of m.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("3 points"), std::string::npos) << r.err;
  const std::string csv = test::read_text(dir / "c.csv");
  EXPECT_NE(
      csv.find("stretch,lateral_stretch,nominal_stress_Pa,cauchy_stress_Pa,energy_density_Pa"),
      std::string::npos);
  // The rest state (stretch 1) is stress-free up to round-off.
  const auto rest = csv.find("\n1,");
  ASSERT_NE(rest, std::string::npos) << csv;
  std::stringstream row(csv.substr(rest + 1, csv.find('\n', rest + 1) - rest - 1));
  std::string field;
  std::vector<double> values;
  while (std::getline(row, field, ',')) values.push_back(std::stod(field));
  ASSERT_EQ(values.size(), 5u);
  EXPECT_NEAR(values[1], 1.0, 1e-12);
  EXPECT_NEAR(values[2], 0.0, 1e-6);  // Pa, against E = 12 kPa

  r = run_palpa("material --model spline --from m.json --knots 6 -o s.json", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_palpa("material show s.json", dir.path());
  EXPECT_NE(r.out.find("f: 6 knots from 0.5 to 2"), std::string::npos) << r.out;
}

// Every parameter is spelled on the command line as in the file it writes.
TEST(MaterialCli, ParametersAreSpelledAsInTheFile) {
  ScratchDir dir;
  auto r = run_palpa("material --model neo-hookean-volume --E 10kPa --nu 0.45 --volume_share 0.25 -o v.json",
                     dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(test::read_text(dir / "v.json").find("\"volume_share\": 0.25"), std::string::npos);
  // The isochoric neo-Hookean also takes E and nu: C10 = mu/2 = E / (4 (1 + nu)), D1 = 2/K.
  r = run_palpa("material --model neo-hookean-isochoric --E 12kPa --nu 0.5e0 -o i.json", dir.path());
  EXPECT_EQ(r.exit_code, 2);
  r = run_palpa("material --model neo-hookean-isochoric --E 13kPa --nu 0.3 -o i.json", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(test::read_text(dir / "i.json").find("\"C10\": \"2.5 kPa\""), std::string::npos)
      << test::read_text(dir / "i.json");
  r = run_palpa("material models", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("parameters: E, nu, volume_share (default 0.5)"), std::string::npos) << r.out;
}

struct BadCall {
  const char* args;
  const char* message;
};

TEST(MaterialCli, BadInputIsRefusedAndNothingIsWritten) {
  const BadCall calls[] = {
      {"material --model neo-hookean --E 10 --nu 0.45 -o out.json", "'10' has no unit"},
      {"material --model neo-hookean --E 5kg --nu 0.45 -o out.json", "is a mass, not a pressure"},
      {"material --model neo-hookean --E 10kPa --nu 0.5 -o out.json", "outside (-1, 0.5)"},
      {"material --model neo-hookean --E -3kPa --nu 0.3 -o out.json", "must be positive"},
      {"material --model rubber -o out.json", "unknown model 'rubber'"},
      {"material --model neo-hookean --E 10kPa -o out.json", "needs --nu"},
      {"material --model neo-hookean-isochoric --C10 1kPa --D1 1/Pa -o out.json", "unknown unit"},
      {"material --model stvk --E 10kPa --nu 0.3 --C10 1kPa -o out.json", "--C10 does not apply"},
      {"material --model spline -o out.json", "--from"},
      {"material --model spline --from missing.json -o out.json", "missing.json: file not found"},
      {"material show broken.json", "broken.json:2:"},
      {"material curve good.json --stretch 1.5:1.0 -o out.json", "not an increasing range"},
      {"material curve good.json --test torsion -o out.json", "unknown test 'torsion'"},
      {"material --model neo-hookean --E 10kPa --nu 0.3", "no output file"},
      {"material --model neo-hookean-isochoric --E 10kPa -o out.json", "needs --nu with --E"},
      {"material --model neo-hookean-isochoric --E 10kPa --nu 0.3 --D1 '2e-6 1/Pa' -o out.json", "--D1 with --E"},
      {"material --model yeoh --C10 1kPa --D1 '2e-6 1/Pa' --mu 1kPa -o out.json", "--mu does not apply to model 'yeoh'"},
      {"material --model ogden --mu 1kPa --nu 0.3 -o out.json", "needs --alpha"},
      {"material --model spline --from good.json --E 1kPa -o out.json", "--E does not apply to model 'spline'"},
  };
  for (const BadCall& c : calls) {
    ScratchDir dir;
    dir.write("broken.json", "{\n  \"model\": \"neo-hookean\" \"parameters\": {}\n}\n");
    dir.write("good.json", R"({"model": "neo-hookean", "parameters": {"E": "1 kPa", "nu": 0.3}})");
    const auto r = run_palpa(c.args, dir.path());
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\nstderr: " << r.err;
    EXPECT_EQ(dir.entry_count(), 2u) << c.args << ": something was written";
  }
}

// The BLAS that palpa runs on is the libblas.so.3 that the system's dynamic
// linker finds (Debian's alternatives), not a library linked ahead of it.
TEST(Cli, VersionNamesTheSystemsLibblas) {
  void* handle = dlopen("libblas.so.3", RTLD_LAZY | RTLD_LOCAL);
  ASSERT_NE(handle, nullptr) << dlerror();
  link_map* map = nullptr;
  ASSERT_EQ(dlinfo(handle, RTLD_DI_LINKMAP, &map), 0) << dlerror();
  const std::string libblas = std::filesystem::canonical(map->l_name).string();
  dlclose(handle);
  const auto r = run_palpa("--version");
  ASSERT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("(" + libblas + ")"), std::string::npos) << "libblas.so.3 is " << libblas << "\n" << r.out;
}

// BLAS runs on one thread unless the environment asks for more.
TEST(Cli, BlasRunsOnOneThreadUnlessTheEnvironmentSaysOtherwise) {
  ScratchDir dir;
  const auto version = [&](const std::string& env) {
    const auto out = dir / "version.txt";
    const std::string cmd = fmt::format("env -u OPENBLAS_NUM_THREADS -u OMP_NUM_THREADS {} '{}' --version >'{}' 2>&1",
                                        env, test::palpa_binary(), out.string());
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    return test::read_text(out);
  };
  const std::string plain = version("");
  EXPECT_NE(plain.find(", 1 thread;"), std::string::npos) << plain;
  const std::string two = version("OPENBLAS_NUM_THREADS=2");
  if (two.find("OpenBLAS") != std::string::npos && two.find("openblas-pthread") != std::string::npos) {
    EXPECT_NE(two.find(", 2 threads;"), std::string::npos) << two;
  }
}

TEST(Cli, VersionHelpAndUsageErrors) {
  auto r = run_palpa("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("palpa 0."), std::string::npos);
  // The dense libraries CHOLMOD runs on, as loaded, with their files.
  EXPECT_NE(r.out.find("BLAS: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("LAPACK: /"), std::string::npos) << r.out;
  r = run_palpa("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("material"), std::string::npos);
  r = run_palpa("material --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("--E"), std::string::npos);
  EXPECT_NE(r.out.find("such as 12 kPa"), std::string::npos);  // units explained
  r = run_palpa("material --bogus-option");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bogus-option"), std::string::npos) << r.err;
  r = run_palpa("");
  EXPECT_EQ(r.exit_code, 2);
}

}  // namespace
}  // namespace palpa
