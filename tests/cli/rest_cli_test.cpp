// `palpa rest` end to end: outputs and bad scenes.
#include <gtest/gtest.h>

#include "common/test_support.hpp"

namespace palpa {
namespace {

using test::run_palpa;
using test::ScratchDir;

constexpr const char* kScene = R"({
  "palpa_rest": 1,
  "body": {
    "generate": {"shape": "sphere", "length": "60 mm"},
    "edge": "7 mm", "depth": "8 mm",
    "material": {"model": "neo-hookean", "parameters": {"E": "20 kPa", "nu": 0.4}},
    "position": ["0 mm", "0 mm", "31 mm"]
  },
  "core": {"mass": "0.5 kg", "free": ["z"]},
  "support": {"box": {"size": ["150 mm", "150 mm", "20 mm"], "divisions": 30}}
})";

TEST(RestCli, WritesPressureMapsAndASummary) {
  ScratchDir dir;
  dir.write("scene.json", kScene);
  const auto r = run_palpa("rest scene.json -o out", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"body.vtu", "skin.ply", "support.vtu", "support.ply", "pressure_histogram.svg", "summary.json"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / f)) << f;
  }
  const std::string summary = test::read_text(dir / "out" / "summary.json");
  EXPECT_NE(summary.find("\"balance_error\""), std::string::npos);
  EXPECT_NE(test::read_text(dir / "out" / "skin.ply").find("pressure_Pa"), std::string::npos);
  EXPECT_NE(r.err.find("rest: contact force"), std::string::npos) << r.err;
}

TEST(RestCli, RefusesABodyInsideTheSupportAndUnknownDofs) {
  ScratchDir dir;
  std::string inside = kScene;
  inside.replace(inside.find("\"31 mm\""), 7, "\"20 mm\"");
  dir.write("inside.json", inside);
  const auto a = run_palpa("rest inside.json -o out", dir.path());
  EXPECT_EQ(a.exit_code, 2);
  EXPECT_NE(a.err.find("starts inside"), std::string::npos) << a.err;
  std::string dof = kScene;
  dof.replace(dof.find("[\"z\"]"), 5, "[\"up\"]");
  dir.write("dof.json", dof);
  const auto b = run_palpa("rest dof.json -o out", dir.path());
  EXPECT_EQ(b.exit_code, 2);
  EXPECT_NE(b.err.find("unknown DOF 'up'"), std::string::npos) << b.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

}  // namespace
}  // namespace palpa
