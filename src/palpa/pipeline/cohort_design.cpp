// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/pipeline/cohort_design.hpp"

#include <fmt/format.h>

#include "palpa/core/error.hpp"

namespace palpa::pipeline {

namespace fs = std::filesystem;

Json cohort_design_scene(const std::vector<Subject>& subjects, const fs::path& results) {
  if (subjects.size() < 2) {
    throw Error(ErrorKind::Input,
                fmt::format("one support for a cohort needs two subjects or more, got {}", subjects.size()), {},
                "a cohort file listing the subjects");
  }
  for (const Subject& s : subjects) {
    if (fs::weakly_canonical(s.design) != fs::weakly_canonical(subjects.front().design)) {
      throw Error(ErrorKind::Input,
                  fmt::format("the subjects '{}' and '{}' have different design templates ({} and {}): one support "
                              "for all needs one template",
                              subjects.front().name, s.name, subjects.front().design.string(), s.design.string()));
    }
  }
  Json bodies = Json::array();
  for (const Subject& s : subjects) {
    const fs::path scene = fs::absolute(results / s.name / "body" / "design.json").lexically_normal();
    if (!fs::is_regular_file(scene)) {
      throw Error(ErrorKind::Input,
                  fmt::format("the subject '{}' has no body scene yet: {} is missing", s.name, scene.string()), {},
                  fmt::format("`palpa subject body {} --fits ... -o {}` first", s.file.string(),
                              scene.parent_path().string()));
    }
    bodies.push_back({{"name", s.name}, {"scene", scene.string()}});
  }
  // The first subject's design scene: the template's support, contact and
  // design settings, with its paths already absolute.
  const fs::path first = results / subjects.front().name / "body" / "design.json";
  Json doc = read_json_file(first);
  if (!doc.is_object()) JsonView(doc, first.string()).fail("not a JSON object", "a design scene");
  for (const char* key : {"body", "core", "baselines"}) doc.erase(key);
  if (doc.contains("design") && doc["design"].is_object()) doc["design"].erase("start");
  doc["bodies"] = bodies;
  // Begun on the negative image of the average body, the baseline a workshop
  // would make for them all, and each body's own design on its own.
  doc["cohort"] = {{"objective", "mean"}, {"single_designs", true}, {"start", "baseline"}};
  return doc;
}

}  // namespace palpa::pipeline
