// SPDX-License-Identifier: AGPL-3.0-or-later
// `palpa subject`: a subject file checked (every bad input named by subject,
// location and file), its plan, a location's dataset, and the body carrying
// the fits (depth and modulus samples, the common shape, the scenes, which
// `palpa rest` then solves with per-tet moduli).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "common/test_support.hpp"

namespace palpa {
namespace {

using test::run_palpa;
using test::ScratchDir;

// A generated thigh (its underside at z = −61 mm in the scan's frame), two
// locations with ready curves, one with an ultrasound summary's depth.
constexpr const char* kSubject = R"({
  "palpa_subject": 1,
  "name": "t01",
  "body": {"generate": {"shape": "thigh", "length": "400 mm", "width": "160 mm", "height": "140 mm"},
           "edge": "15 mm", "position": ["0 mm", "0 mm", "72 mm"]},
  "locations": [
    {"name": "back", "position": ["-100 mm", "0 mm", "-61 mm"],
     "pokes": [{"radius": "2 mm", "curve": "r2.csv"}, {"radius": "6 mm", "curve": "r6.csv"}],
     "depth_search": {"from": "15 mm", "to": "25 mm", "count": 3}},
    {"name": "front", "position": ["100 mm", "0 mm", "-61 mm"],
     "pokes": [{"radius": "6 mm", "force": "force.csv", "laser": "laser.csv", "calibration": "cal.csv",
                "options": {"cutoff": "4 Hz", "no_tare": true}}],
     "ultrasound": {"force": "us-force.csv", "interfaces": [{"name": "fat", "picks": "fat.csv"},
                                                          {"name": "bone", "picks": "bone.csv"}]}}
  ],
  "fit": {"model": "neo-hookean", "poisson": 0.45, "lateral_size": "100 mm", "mesh_level": 1, "steps": 8},
  "design": "design.json"
})";

constexpr const char* kDesign = R"({
  "palpa_design": 1,
  "core": {"mass": "5 kg", "free": ["z"]},
  "support": {"box": {"size": ["600 mm", "300 mm", "50 mm"], "divisions": 30}},
  "design": {"region": {"min": ["-280 mm", "-130 mm", "-10 mm"], "max": ["280 mm", "130 mm", "10 mm"]},
             "iterations": 2}
})";

void write_inputs(const ScratchDir& dir, const std::string& subject = kSubject) {
  dir.write("subject.json", subject);
  dir.write("design.json", kDesign);
  for (const char* f : {"r2.csv", "r6.csv", "force.csv", "laser.csv", "cal.csv", "us-force.csv",
                        "fat.csv", "bone.csv"}) {
    dir.write(f, "# a log\n");
  }
}

// A location's fit as palpa fit leaves it: the material and the report.
void write_fit(const ScratchDir& dir, const std::string& location, double young_kpa, double depth_m,
               double rms) {
  dir.write(fmt::format("fits/{}/material.json", location),
            fmt::format(R"({{"palpa_material": 1, "model": "neo-hookean",
                            "parameters": {{"E": "{} kPa", "nu": 0.45}},
                            "provenance": {{"created_by": "test", "method": "test", "objective": null}}}})",
                        young_kpa));
  dir.write(fmt::format("fits/{}/report.json", location),
            fmt::format(R"({{"layer_depth_m": {}, "depth_search": true, "termination": "converged",
                            "curves": [{{"role": "train", "rms_error_fitted": {}, "largest_measured": 1.0}}]}})",
                        depth_m, rms));
}

TEST(SubjectCli, PlansWritesDatasetsAndMakesTheBodyCarryTheFits) {
  ScratchDir dir;
  write_inputs(dir);
  const auto check = run_palpa("subject check subject.json", dir.path());
  ASSERT_EQ(check.exit_code, 0) << check.err;
  EXPECT_NE(
      check.out.find(
          "subject t01: 2 locations on the body, 3 pokes, 1 with ultrasound depths, 1 searched"),
      std::string::npos)
      << check.out;

  const auto plan = run_palpa("subject plan subject.json -o plan.json", dir.path());
  ASSERT_EQ(plan.exit_code, 0) << plan.err;
  const auto p = nlohmann::json::parse(test::read_text(dir / "plan.json"))["subjects"][0];
  EXPECT_EQ(p["subject"], "t01");
  ASSERT_EQ(p["locations"].size(), 2u);
  EXPECT_EQ(p["locations"][0]["pokes"][0]["tag"], "r2mm");
  EXPECT_EQ(p["locations"][0]["pokes"][0]["curve"], (dir / "r2.csv").string());
  const auto acquire = p["locations"][1]["pokes"][0]["acquire"].get<std::vector<std::string>>();
  const std::vector<std::string> expected = {
      "--force",       (dir / "force.csv").string(), "--laser",  (dir / "laser.csv").string(),
      "--calibration", (dir / "cal.csv").string(),   "--cutoff", "4 Hz",
      "--no-tare"};
  EXPECT_EQ(acquire, expected);
  const auto us = p["locations"][1]["ultrasound"]["acquire"].get<std::vector<std::string>>();
  EXPECT_EQ(us.back(), "bone");  // the deepest interface gives the depth by default
  EXPECT_EQ(p["fit"],
            nlohmann::json({"--model", "neo-hookean", "--mesh-level", "1", "--steps", "8"}));

  // Datasets: the searched depths; the ultrasound's rest depth of the bone.
  dir.write("curves/back/r2mm.csv", "x\n");
  dir.write("curves/back/r6mm.csv", "x\n");
  dir.write("curves/front/r6mm.csv", "x\n");
  dir.write("depths/front.json", R"({"rest_depth": {"fat_m": 0.008, "bone_m": 0.021}})");
  auto r = run_palpa(
      "subject dataset subject.json --location back --curves curves/back -o fits/back.json",
      dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto back = nlohmann::json::parse(test::read_text(dir / "fits/back.json"));
  EXPECT_EQ(back["layer_depth"]["count"], 3);
  EXPECT_EQ(back["curves"][1]["file"], "../curves/back/r6mm.csv");
  EXPECT_EQ(back["poisson"], 0.45);
  // A dataset written over one of the curves it lists is refused, the curve kept.
  r = run_palpa("subject dataset subject.json --location back --curves curves/back -o curves/back/r6mm.csv",
                dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("r6mm.csv"), std::string::npos) << r.err;
  EXPECT_EQ(test::read_text(dir / "curves/back/r6mm.csv"), "x\n");
  r = run_palpa(
      "subject dataset subject.json --location front --curves curves/front --ultrasound "
      "depths/front.json "
      "-o fits/front.json",
      dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(test::read_text(dir / "fits/front.json"))["layer_depth"],
            "0.021 m");

  // The body: the shape from the better fit (front), each location's E and depth.
  write_fit(dir, "back", 20.0, 0.015, 0.05);
  write_fit(dir, "front", 60.0, 0.021, 0.01);
  // An output under a regular file: an input error naming it, nothing written.
  dir.write("plain.txt", "a file\n");
  for (const char* args : {"subject body subject.json --fits fits -o plain.txt/body",
                           "subject dataset subject.json --location back --curves curves/back -o plain.txt/d.json"}) {
    r = run_palpa(args, dir.path());
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("plain.txt"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("not a folder"), std::string::npos) << r.err;
  }
  EXPECT_EQ(test::read_text(dir / "plain.txt"), "a file\n");
  r = run_palpa("subject body subject.json --fits fits -o body", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto fields = nlohmann::json::parse(test::read_text(dir / "body/fields.json"));
  EXPECT_EQ(fields["shape_from"], "front");
  EXPECT_NEAR(fields["locations"][0]["youngs_modulus_Pa"].get<double>(), 20e3, 1e-6);
  EXPECT_NE(test::read_text(dir / "body/moduli.csv")
                .find("x_m,y_m,z_m,youngs_modulus_Pa\n-0.1,0,-0.061,"),
            std::string::npos);
  EXPECT_NE(test::read_text(dir / "body/depths.csv").find("0.1,0,-0.061,0.021"), std::string::npos);
  EXPECT_NE(test::read_text(dir / "body/material.json").find("60 kPa"), std::string::npos);
  const auto design = nlohmann::json::parse(test::read_text(dir / "body/design.json"));
  EXPECT_EQ(design["body"]["material"], "material.json");
  EXPECT_EQ(design["design"]["iterations"], 2);
  const auto rest = nlohmann::json::parse(test::read_text(dir / "body/rest.json"));
  EXPECT_EQ(rest["palpa_rest"], 1);
  EXPECT_FALSE(rest.contains("design"));

  // The body rests with the moduli over its skin: 20 to 60 kPa.
  r = run_palpa("rest body/rest.json -o rest", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto summary = nlohmann::json::parse(test::read_text(dir / "rest/summary.json"));
  EXPECT_NEAR(summary["body"]["youngs_modulus_Pa"]["min"].get<double>(), 20e3, 0.01 * 20e3);
  EXPECT_NEAR(summary["body"]["youngs_modulus_Pa"]["max"].get<double>(), 60e3, 0.01 * 60e3);
  EXPECT_GT(summary["body"]["materials"].get<int>(), 100);
}

void expect_subject_refused(const std::string& subject, const std::vector<std::string>& words,
                            const std::string& command = "check") {
  ScratchDir dir;
  write_inputs(dir, subject);
  const auto r = run_palpa(fmt::format("subject {} subject.json", command), dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  for (const std::string& w : words)
    EXPECT_NE(r.err.find(w), std::string::npos) << w << "\n" << r.err;
}

std::string subject_with(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

TEST(SubjectCli, BadSubjectsAreNamedBySubjectLocationAndFile) {
  // A location off the body.
  expect_subject_refused(
      subject_with(kSubject, R"(["100 mm", "0 mm", "-61 mm"])", R"(["100 mm", "0 mm", "-80 mm"])"),
      {"locations[1].position", "subject 't01', location 'front'",
       "from the skin of generated thigh", "within 5 mm"});
  // A location without pokes.
  expect_subject_refused(
      subject_with(
          kSubject,
          R"("pokes": [{"radius": "2 mm", "curve": "r2.csv"}, {"radius": "6 mm", "curve": "r6.csv"}])",
          R"("pokes": [])"),
      {"locations[0].pokes", "subject 't01', location 'back': no pokes"});
  // A radius's file missing.
  expect_subject_refused(
      subject_with(kSubject, R"("curve": "r6.csv")", R"("curve": "r6mm.csv")"),
      {"locations[0].pokes[1].curve", "location 'back', 6 mm poke: no file", "r6mm.csv"});
  // Two locations of one name.
  expect_subject_refused(subject_with(kSubject, R"("name": "front")", R"("name": "back")"),
                         {"locations[1].name", "a second location 'back'"});
  // Two pokes of one radius.
  expect_subject_refused(subject_with(kSubject, R"({"radius": "2 mm", "curve": "r2.csv"})",
                                      R"({"radius": "6 mm", "curve": "r2.csv"})"),
                         {"locations[0].pokes[1].radius", "a second poke of radius 6 mm"});
  // No depth: neither ultrasound nor a search.
  expect_subject_refused(subject_with(kSubject, R"(,
     "depth_search": {"from": "15 mm", "to": "25 mm", "count": 3})",
                                      ""),
                         {"locations[0]", "location 'back': no layer depth", "\"depth_search\""});
  // The body's material is the fits'.
  expect_subject_refused(
      subject_with(kSubject, R"("edge": "15 mm",)", R"("edge": "15 mm", "material": "m.json",)"),
      {"body.material", "the body's material comes from the fits"});
  // An option acquire poke does not have.
  expect_subject_refused(subject_with(kSubject, R"("no_tare": true)", R"("no_tear": true)"),
                         {"no_tear"});
  // What palpa fit and acquire would refuse only when the workflow runs them.
  const std::string fit = R"("model": "neo-hookean")";
  expect_subject_refused(subject_with(kSubject, fit, R"("model": "rubber")"), {"fit.model", "rubber"});
  expect_subject_refused(subject_with(kSubject, fit, R"("model": "neo-hookean", "fix": ["--overwrite"])"),
                         {"fit.fix[0]", "'--overwrite'", "a parameter name"});
  expect_subject_refused(subject_with(kSubject, fit, R"("model": "neo-hookean", "depth_from": "half")"),
                         {"fit.depth_from", "half"});
  expect_subject_refused(subject_with(kSubject, R"("mesh_level": 1)", R"("mesh_level": 9)"),
                         {"fit.mesh_level", "from 0 to 7"});
  expect_subject_refused(subject_with(kSubject, R"("no_tare": true)", R"("no_tare": "yes")"),
                         {"no_tare", "true or false"});
  expect_subject_refused(subject_with(kSubject, R"("cutoff": "4 Hz")", R"("cutoff": true)"),
                         {"cutoff", "--cutoff as text or a number"});
  // Where the body stands and the design it goes into, as rest and design read them.
  expect_subject_refused(subject_with(kSubject, R"("position": ["0 mm", "0 mm", "72 mm"])",
                                      R"("position": [0, 0, 72])"),
                         {"body.position[0]", "has no unit"});
  expect_subject_refused(subject_with(kSubject, R"("position": ["0 mm", "0 mm", "72 mm"])",
                                      R"("position": ["0 mm", "0 mm", "72 mm"], "rotation": {"axis": [0, 0, 0], "angle": "90 deg"})"),
                         {"body.rotation.axis", "zero axis"});
  // How its layer is made, as rest reads it.
  for (const auto& [key, says] : {std::pair{R"("edge": "nan mm")", "body.edge"},
                                  std::pair{R"("edge": "-16 mm")", "body.edge"},
                                  std::pair{R"("edge": "15 mm", "density": "16 parsecs")", "body.density"},
                                  std::pair{R"("edge": "15 mm", "core_offset": "bogus")", "body.core_offset"},
                                  std::pair{R"("edge": "15 mm", "element": "brick")", "body.element"}}) {
    expect_subject_refused(subject_with(kSubject, R"("edge": "15 mm")", key), {says});
  }
  expect_subject_refused(subject_with(kSubject, R"("design": "design.json")", R"("design": "r2.csv")"),
                         {"field 'design'", "its design scene cannot be read", "r2.csv"});
  expect_subject_refused(subject_with(kSubject, R"("design": "design.json")", R"("design": "subject.json")"),
                         {"field 'design'", "is not a design scene"});
}

TEST(SubjectCli, AFailedFitIsNamedAndNothingIsWritten) {
  ScratchDir dir;
  write_inputs(dir);
  write_fit(dir, "back", 20.0, 0.015, 0.05);
  const auto r = run_palpa("subject body subject.json --fits fits -o body", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("subject 't01', location 'front': its fit has no material.json"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "body/moduli.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir / "body")) << "a failed run leaves no folder it created";
}

// Results that are not what palpa wrote (a key missing, a number as text) are
// input errors naming the file, and no report is written.
TEST(SubjectCli, AReportOnMalformedResultsNamesTheFile) {
  struct Bad {
    const char* file;
    const char* text;
  };
  for (const Bad& b : {Bad{"results/body/fields.json", R"({"locations": [{"name": 3}]})"},
                       Bad{"results/rest/summary.json", R"({"pressure_map": {}})"},
                       Bad{"results/design/summary.json", R"({"objective": "low"})"}}) {
    ScratchDir dir;
    write_inputs(dir);
    dir.write(b.file, b.text);
    const auto r = run_palpa("subject report subject.json --results results -o report.html", dir.path());
    EXPECT_EQ(r.exit_code, 2) << b.file << "\n" << r.err;
    EXPECT_NE(r.err.find(b.file), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("is not the result palpa writes there"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "report.html")) << b.file;
  }
}

}  // namespace
}  // namespace palpa

namespace palpa {
namespace {

TEST(SubjectCli, ACohortPlansEverySubjectAndRefusesADuplicateName) {
  ScratchDir dir;
  write_inputs(dir);
  dir.write("b/subject.json", subject_with(kSubject, R"("name": "t01")", R"("name": "t02")"));
  dir.write("b/design.json", kDesign);
  for (const char* f : {"r2.csv", "r6.csv", "force.csv", "laser.csv", "cal.csv", "us-force.csv",
                        "fat.csv", "bone.csv"}) {
    dir.write(std::string("b/") + f, "# a log\n");
  }
  dir.write("cohort.json",
            R"({"palpa_cohort": 1, "subjects": ["subject.json", "b/subject.json"]})");
  const auto r = run_palpa("subject plan cohort.json", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto p = nlohmann::json::parse(r.out);
  ASSERT_EQ(p["subjects"].size(), 2u);
  EXPECT_EQ(p["subjects"][1]["subject"], "t02");
  EXPECT_EQ(p["subjects"][1]["locations"][0]["pokes"][0]["curve"], (dir / "b/r2.csv").string());

  dir.write("b/subject.json", kSubject);
  const auto dup = run_palpa("subject plan cohort.json", dir.path());
  EXPECT_EQ(dup.exit_code, 2);
  EXPECT_NE(dup.err.find("subjects[1]"), std::string::npos) << dup.err;
  EXPECT_NE(dup.err.find("subject 't01' of " + (dir / "b/subject.json").string() +
                         " has the name of " + (dir / "subject.json").string()),
            std::string::npos)
      << dup.err;
}

// `palpa subject cohort`: the scene of one support for every subject, from
// their bodies' scenes; a missing body scene, a lone subject and subjects of
// different design templates are refused by name, writing nothing.
TEST(SubjectCli, ACohortSceneHoldsEveryBodyOnTheTemplatesSupport) {
  ScratchDir dir;
  write_inputs(dir);
  dir.write("b/subject.json", subject_with(kSubject, R"("name": "t01")", R"("name": "t02")"));
  dir.write("b/design.json", kDesign);
  for (const char* f : {"r2.csv", "r6.csv", "force.csv", "laser.csv", "cal.csv", "us-force.csv", "fat.csv", "bone.csv"}) {
    dir.write(std::string("b/") + f, "# a log\n");
  }
  dir.write("cohort.json", R"({"palpa_cohort": 1, "subjects": ["subject.json", "b/subject.json"]})");
  // Another template for the second subject: refused, both named.
  const auto other = run_palpa("subject cohort cohort.json --results out -o scene.json", dir.path());
  EXPECT_EQ(other.exit_code, 2);
  EXPECT_NE(other.err.find("'t01' and 't02' have different design templates"), std::string::npos) << other.err;
  // One template: the bodies' scenes must be there.
  dir.write("b/subject.json", subject_with(subject_with(kSubject, R"("name": "t01")", R"("name": "t02")"),
                                           R"("design": "design.json")", R"("design": "../design.json")"));
  const auto missing = run_palpa("subject cohort cohort.json --results out -o scene.json", dir.path());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("the subject 't01' has no body scene yet"), std::string::npos) << missing.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "scene.json"));
  for (const char* name : {"t01", "t02"}) {
    auto design = nlohmann::json::parse(kDesign);
    design["body"] = {{"material", "material.json"}};
    dir.write(fmt::format("out/{}/body/design.json", name), design.dump());
  }
  const auto r = run_palpa("subject cohort cohort.json --results out -o scene.json", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto scene = nlohmann::json::parse(test::read_text(dir / "scene.json"));
  ASSERT_EQ(scene["bodies"].size(), 2u);
  EXPECT_EQ(scene["bodies"][1]["name"], "t02");
  EXPECT_EQ(scene["bodies"][1]["scene"], (dir / "out/t02/body/design.json").string());
  EXPECT_FALSE(scene.contains("body"));
  EXPECT_EQ(scene["support"], nlohmann::json::parse(kDesign)["support"]);
  EXPECT_TRUE(scene["cohort"]["single_designs"].get<bool>());
  EXPECT_EQ(scene["cohort"]["start"], "baseline");
  // A lone subject has no cohort.
  const auto lone = run_palpa("subject cohort subject.json --results out -o lone.json", dir.path());
  EXPECT_EQ(lone.exit_code, 2);
  EXPECT_NE(lone.err.find("two subjects or more"), std::string::npos) << lone.err;
}

}  // namespace
}  // namespace palpa
