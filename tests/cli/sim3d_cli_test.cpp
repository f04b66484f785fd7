// SPDX-License-Identifier: AGPL-3.0-or-later
// `palpa sim3d` end to end: outputs, and bad input refused before anything is
// written.
#include <gtest/gtest.h>

#include "common/test_support.hpp"

namespace palpa {
namespace {

using test::run_palpa;
using test::ScratchDir;

constexpr const char* kScene = R"({
  "palpa_scene": 1,
  "body": {
    "box": {"size": ["20 mm", "20 mm", "6 mm"], "cells": [6, 6, 2]},
    "materials": [{"material": {"model": "neo-hookean", "parameters": {"E": "10 kPa", "nu": 0.3}}}],
    "fixed": [{"set": "bottom"}]
  },
  "obstacles": [{"name": "ball", "shape": {"sphere": {"radius": "5 mm", "level": 2}},
                 "path": {"direction": [0, 0, -1], "depth": "1 mm"}}],
  "steps": 2
})";

TEST(Sim3dCli, WritesCurveFramesAndSummary) {
  ScratchDir dir;
  dir.write("scene.json", kScene);
  const auto r = run_palpa("sim3d scene.json -o out", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string curve = test::read_text(dir / "out" / "force_ball.csv");
  EXPECT_NE(curve.find("indentation_m,force_N,force_x_N,force_y_N,force_z_N"), std::string::npos) << curve;
  EXPECT_NE(curve.find("\n0.001,"), std::string::npos) << curve;
  for (const char* f : {"body.pvd", "ball.pvd", "frames/body_0002.vtu", "frames/ball_0001.vtu", "summary.json"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / f)) << f;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "state.json"));
  const std::string vtu = test::read_text(dir / "out" / "frames" / "body_0002.vtu");
  for (const char* a : {"displacement_m", "contact_pressure_Pa", "von_mises_stress_Pa", "det_F"}) {
    EXPECT_NE(vtu.find(a), std::string::npos) << a;
  }
  EXPECT_NE(r.err.find("sim3d: 2 steps"), std::string::npos) << r.err;
  // --resume on the finished run changes nothing; on a new folder it starts afresh.
  const std::string finished = test::read_text(dir / "out" / "summary.json");
  const auto done = run_palpa("sim3d scene.json -o out --resume", dir.path());
  ASSERT_EQ(done.exit_code, 0) << done.err;
  EXPECT_NE(done.err.find("is finished (2 steps); nothing to resume"), std::string::npos) << done.err;
  EXPECT_EQ(test::read_text(dir / "out" / "summary.json"), finished);
  const auto fresh = run_palpa("sim3d scene.json -o fresh --resume", dir.path());
  ASSERT_EQ(fresh.exit_code, 0) << fresh.err;
  EXPECT_NE(fresh.err.find("starting afresh"), std::string::npos) << fresh.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "fresh" / "summary.json"));

  // A second run into the same folder is refused, naming it.
  const auto again = run_palpa("sim3d scene.json -o out", dir.path());
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("output folder 'out' is not empty"), std::string::npos) << again.err;
}

TEST(Sim3dCli, RefusesBadScenesWithoutWritingAnything) {
  ScratchDir dir;
  const auto missing = run_palpa("sim3d nothere.json -o out", dir.path());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("nothere.json"), std::string::npos) << missing.err;

  std::string text = kScene;
  text.replace(text.find("\"1 mm\""), 6, "\"1\"");  // a depth without a unit
  dir.write("nounit.json", text);
  const auto nounit = run_palpa("sim3d nounit.json -o out", dir.path());
  EXPECT_EQ(nounit.exit_code, 2);
  EXPECT_NE(nounit.err.find("obstacles[0].path.depth"), std::string::npos) << nounit.err;

  text = kScene;
  text.replace(text.find("\"bottom\""), 8, "\"floor\"");
  dir.write("floor.json", text);
  const auto floor = run_palpa("sim3d floor.json -o out", dir.path());
  EXPECT_EQ(floor.exit_code, 2);
  EXPECT_NE(floor.err.find("unknown vertex set 'floor'"), std::string::npos) << floor.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

}  // namespace
}  // namespace palpa
