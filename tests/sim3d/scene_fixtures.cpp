// SPDX-License-Identifier: AGPL-3.0-or-later
#include "scene_fixtures.hpp"

#include <fmt/format.h>

namespace palpa::sim3d::test {

std::string punch_scene_json(const PunchScene& p) {
  return fmt::format(R"({{
  "palpa_scene": 1,
  "body": {{
    {}{},
    "materials": [{{"material": {}, "density": "1000 kg/m^3"}}],
    "fixed": {}
  }},
  "obstacles": [{{"name": "punch", "shape": {}, "path": {{"direction": [0, 0, -1], "depth": "{}"}}}}],
  "steps": {},
  "contact": {}{}
}})",
                     p.body.empty() ? fmt::format(R"("box": {{"size": {}, "cells": {}}})", p.size_mm, p.cells) : p.body,
                     p.element,
                     p.material, p.fixed, p.shape, p.depth, p.steps, p.contact, p.extra);
}

std::filesystem::path write_punch_scene(const palpa::test::ScratchDir& dir, const PunchScene& p,
                                        const std::string& name) {
  return dir.write(name, punch_scene_json(p));
}

}  // namespace palpa::sim3d::test
