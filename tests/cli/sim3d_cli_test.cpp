// SPDX-License-Identifier: AGPL-3.0-or-later
// `palpa sim3d` end to end: outputs, and bad input refused before anything is
// written.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>

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
  for (const char* a : {"displacement_m", "pressure_Pa", "von_mises_stress_Pa", "det_F"}) {
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

  // A file's unit is a unit alone, not a quantity.
  text = kScene;
  const std::string sphere = R"({"sphere": {"radius": "5 mm", "level": 2}})";
  text.replace(text.find(sphere), sphere.size(), R"({"file": "ball.obj", "unit": "0 mm"})");
  dir.write("unit.json", text);
  const auto unit = run_palpa("sim3d unit.json -o out", dir.path());
  EXPECT_EQ(unit.exit_code, 2);
  EXPECT_NE(unit.err.find("obstacles[0].shape.unit': '0 mm' is not a unit"), std::string::npos) << unit.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

// Killed with SIGKILL at several moments, a run continued with --resume ends
// where an uninterrupted run ends (the same force curve, byte for byte); a
// saved state that does not fit is refused by name: a step past the end (a
// hand-edited next_step), or another scene.
TEST(Sim3dCli, SurvivesSigkillAndRefusesAStateThatDoesNotFit) {
  ScratchDir dir;
  std::string text = kScene;
  text.replace(text.find("\"steps\": 2"), 11, "\"steps\": 8");
  dir.write("scene.json", text);
  const auto straight = run_palpa("sim3d scene.json -o straight", dir.path());
  ASSERT_EQ(straight.exit_code, 0) << straight.err;
  const std::string curve = test::read_text(dir / "straight" / "force_ball.csv");
  int resumed = 0;
  std::filesystem::path saved;  // a folder holding a saved state
  // Killed at moments of the run itself, whatever the machine's load: as soon
  // as its folder exists (no state saved yet), and once the state says step
  // 3, then step 6, comes next.
  for (const int next : {0, 3, 6}) {
    const std::string out = fmt::format("killed{}", next);
    const auto moment = [&] {
      if (next == 0) return std::filesystem::exists(dir / out);
      std::error_code ec;
      if (!std::filesystem::exists(dir / out / "state.json", ec)) return false;
      return test::read_text(dir / out / "state.json").find(fmt::format("\"next_step\": {}", next)) !=
             std::string::npos;
    };
    const int killed = test::run_palpa_signalled_when("sim3d scene.json -o " + out, dir.path(), moment, SIGKILL);
    EXPECT_EQ(killed, 128 + SIGKILL) << out << ": the run ended before the moment came";
    if (killed != 128 + SIGKILL) continue;
    EXPECT_FALSE(std::filesystem::exists(dir / out / "summary.json") &&
                 test::read_text(dir / out / "summary.json").find("\"complete\": true") != std::string::npos)
        << out;
    if (std::filesystem::exists(dir / out / "state.json") && saved.empty()) {
      saved = dir / (out + "-copy");
      std::filesystem::copy(dir / out, saved, std::filesystem::copy_options::recursive);
    }
    const auto r = run_palpa("sim3d scene.json -o " + out + " --resume --overwrite", dir.path());
    ASSERT_EQ(r.exit_code, 0) << out << "\n" << r.err;
    EXPECT_EQ(test::read_text(dir / out / "force_ball.csv"), curve) << out;
    ++resumed;
  }
  EXPECT_EQ(resumed, 3) << "every kill lands inside the run";
  ASSERT_FALSE(saved.empty()) << "no kill landed after a saved step";

  const std::string state = test::read_text(saved / "state.json");
  const auto next = state.find("\"next_step\"");
  ASSERT_NE(next, std::string::npos);
  std::string edited = state;
  const auto value = edited.find_first_of("0123456789", next);
  edited.replace(value, edited.find_first_not_of("0123456789", value) - value, "99");
  dir.write(saved.filename() / "state.json", edited);
  const auto past = run_palpa("sim3d scene.json -o " + saved.filename().string() + " --resume", dir.path());
  EXPECT_EQ(past.exit_code, 2) << past.err;
  EXPECT_NE(past.err.find("next_step"), std::string::npos) << past.err;
  EXPECT_NE(past.err.find("step 99 of a 8-step run"), std::string::npos) << past.err;

  dir.write(saved.filename() / "state.json", state);
  std::string other = text;
  other.replace(other.find("\"1 mm\""), 6, "\"1.2 mm\"");
  dir.write("other.json", other);
  const auto another = run_palpa("sim3d other.json -o " + saved.filename().string() + " --resume", dir.path());
  EXPECT_EQ(another.exit_code, 2) << another.err;
  EXPECT_NE(another.err.find("the scene differs from the interrupted run's"), std::string::npos) << another.err;
}

}  // namespace
}  // namespace palpa
