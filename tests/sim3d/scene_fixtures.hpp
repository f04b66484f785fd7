// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Scenes for the sim3d tests, written as JSON text into scratch folders.

#include <filesystem>
#include <string>

#include "common/test_support.hpp"

namespace palpa::sim3d::test {

struct PunchScene {
  std::string size_mm = "[\"40 mm\", \"40 mm\", \"10 mm\"]";
  std::string cells = "[8, 8, 3]";
  std::string body;  // the body's shape member instead of the box (e.g. "\"cylinder\": {...}")
  std::string element;  // the body's element members, with a leading comma (empty: the default)
  std::string fixed = R"([{"set": "bottom"}])";
  std::string material = R"({"model": "neo-hookean", "parameters": {"E": "10 kPa", "nu": 0.3}})";
  std::string shape = R"({"cylinder": {"radius": "5 mm", "height": "10 mm", "segments": 32}})";
  std::string depth = "1 mm";
  int steps = 4;
  std::string contact = R"({"max_penetration": "0.05 mm"})";
  std::string extra;  // more top-level members, with a leading comma
};

// The scene's JSON text.
std::string punch_scene_json(const PunchScene& p);

// Writes it as scene.json into `dir` and returns the path.
std::filesystem::path write_punch_scene(const palpa::test::ScratchDir& dir, const PunchScene& p,
                                        const std::string& name = "scene.json");

}  // namespace palpa::sim3d::test
