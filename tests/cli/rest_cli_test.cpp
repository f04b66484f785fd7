// SPDX-License-Identifier: AGPL-3.0-or-later
// `palpa rest` end to end: outputs and bad scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/test_support.hpp"
#include "report/pressure_map_check.hpp"

namespace palpa {
namespace {

using test::run_palpa;
using test::ScratchDir;

constexpr const char* kRestScene = R"({
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
  dir.write("scene.json", kRestScene);
  const auto r = run_palpa("rest scene.json -o out", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"body.vtu", "skin.ply", "support.vtu", "support.ply", "pressure_histogram.svg",
                        "body_pressure.svg", "support_pressure.svg", "summary.json"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / f)) << f;
  }
  const std::string summary = test::read_text(dir / "out" / "summary.json");
  EXPECT_NE(summary.find("\"balance_error\""), std::string::npos);
  EXPECT_NE(test::read_text(dir / "out" / "skin.ply").find("pressure_Pa"), std::string::npos);
  EXPECT_NE(r.err.find("rest: contact force"), std::string::npos) << r.err;
  // The body's element by default: the stabilized nodal-pressure tet.
  const auto element = nlohmann::json::parse(summary)["body"]["element"];
  EXPECT_EQ(element["element"], "nodal-pressure") << element.dump();
  EXPECT_EQ(element["stabilization"], 0.1) << element.dump();
  // Each side's map as a picture: coloured polygons, the colour bar up to
  // the summary's peak, the caption with the map's force.
  const auto s = nlohmann::json::parse(summary);
  for (const auto& [file, side] : {std::pair{"body_pressure.svg", "body"}, std::pair{"support_pressure.svg", "support"}}) {
    const std::string svg = test::read_text(dir / "out" / file);
    EXPECT_NE(svg.find(std::string(side) + " side"), std::string::npos) << file;
    const auto pic = test::read_pressure_map_picture(svg);
    ASSERT_TRUE(pic.doc.ok()) << file << ": " << pic.doc.error;
    EXPECT_EQ(pic.frames.size(), 1u) << file;
    const auto coloured = std::count_if(pic.polygons.begin(), pic.polygons.end(),
                                        [](const auto& q) { return !test::is_no_contact_grey(q.fill); });
    EXPECT_GT(coloured, 10) << file;
    const auto& map = s["pressure_map"][side];
    const double peak_kpa = map["peak_Pa"].get<double>() * 1e-3, force = map["force_N"].get<double>();
    ASSERT_FALSE(pic.bar_labels.empty()) << file;
    EXPECT_NEAR(std::stod(pic.bar_labels.back()), peak_kpa, 5e-3 * peak_kpa) << file;
    EXPECT_NEAR(test::number_after(pic.caption_text(), "map force "), force, 5e-3 * force) << pic.caption_text();
  }
}

TEST(RestCli, ComparesTheBodySideWithATemplateAndTakesTheElement) {
  // The sphere on the nodal-pressure tet, its body-side map against a round
  // template on a 5 mm grid (a disc of pressure, highest at its centre).
  ScratchDir dir;
  std::string grid;
  for (int r = 0; r < 12; ++r) {
    for (int c = 0; c < 12; ++c) {
      const double d2 = (r - 5.5) * (r - 5.5) + (c - 5.5) * (c - 5.5);
      grid += fmt::format("{}{:.1f}", c == 0 ? "" : ",", d2 < 25.0 ? 10.0 * (1.0 - d2 / 25.0) : 0.0);
    }
    grid += "\n";
  }
  dir.write("disc.csv", grid);
  std::string scene = kRestScene;
  scene.replace(scene.find("\"position\""), 0, "\"element\": \"nodal-pressure\", \"stabilization\": 0, ");
  scene.replace(scene.rfind('}'), 0, R"(, "template": {"grid": "disc.csv", "unit": "kPa", "pixel": "5 mm", "title": "a disc"})");
  dir.write("scene.json", scene);
  const auto r = run_palpa("rest scene.json -o out", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto s = nlohmann::json::parse(test::read_text(dir / "out" / "summary.json"));
  EXPECT_EQ(s["body"]["element"]["stabilization"], 0.0) << s["body"].dump();
  EXPECT_GT(s["template"]["correlation"].get<double>(), 0.8) << s["template"].dump();
  EXPECT_EQ(s["template"]["title"], "a disc");
  const std::string svg = test::read_text(dir / "out" / "template_comparison.svg");
  EXPECT_NE(svg.find("a disc"), std::string::npos);
  EXPECT_NE(svg.find("correlation r = "), std::string::npos);
  // Bad grids and elements are refused before anything is written.
  dir.write("bad.csv", "0,1\n2\n");
  std::string bad = scene;
  bad.replace(bad.find("disc.csv"), 8, "bad.csv");
  dir.write("bad.json", bad);
  const auto b = run_palpa("rest bad.json -o bad", dir.path());
  EXPECT_EQ(b.exit_code, 2);
  EXPECT_NE(b.err.find("bad.csv"), std::string::npos) << b.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad"));
  std::string element = scene;
  element.replace(element.find("nodal-pressure"), 14, "quadratic");
  dir.write("element.json", element);
  const auto e = run_palpa("rest element.json -o element", dir.path());
  EXPECT_EQ(e.exit_code, 2);
  EXPECT_NE(e.err.find("body.element"), std::string::npos) << e.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "element"));
}

TEST(RestCli, RefusesABodyInsideTheSupportAndUnknownDofs) {
  ScratchDir dir;
  std::string inside = kRestScene;
  inside.replace(inside.find("\"31 mm\""), 7, "\"20 mm\"");
  dir.write("inside.json", inside);
  const auto a = run_palpa("rest inside.json -o out", dir.path());
  EXPECT_EQ(a.exit_code, 2);
  EXPECT_NE(a.err.find("starts inside"), std::string::npos) << a.err;
  std::string dof = kRestScene;
  dof.replace(dof.find("[\"z\"]"), 5, "[\"up\"]");
  dir.write("dof.json", dof);
  const auto b = run_palpa("rest dof.json -o out", dir.path());
  EXPECT_EQ(b.exit_code, 2);
  EXPECT_NE(b.err.find("unknown DOF 'up'"), std::string::npos) << b.err;
  std::string shape = kRestScene;
  shape.replace(shape.find("\"sphere\""), 8, "\"blob\"");
  dir.write("shape.json", shape);
  const auto c = run_palpa("rest shape.json -o out", dir.path());
  EXPECT_EQ(c.exit_code, 2);
  EXPECT_NE(c.err.find("shape.json: field 'body.generate.shape': unknown body shape 'blob'"), std::string::npos)
      << c.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

TEST(RestCli, ANegativeImageSupportSpreadsThePressure) {
  // The same sphere on a flat box and on the box with its negative image
  // (pressed 10 mm in): the hollow carries the same load with a lower peak.
  ScratchDir dir;
  dir.write("flat.json", kRestScene);
  std::string hollow = kRestScene;
  const std::string box = R"({"box": {"size": ["150 mm", "150 mm", "20 mm"], "divisions": 30}})";
  hollow.replace(hollow.find(box), box.size(),
                 R"({"negative_image": {"box": {"size": ["150 mm", "150 mm", "40 mm"], "divisions": 15},
                     "press": "10 mm", "edge": "5 mm", "smoothing": 5, "band": "10 mm"}})");
  dir.write("hollow.json", hollow);
  const auto a = run_palpa("rest flat.json -o flat", dir.path());
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto b = run_palpa("rest hollow.json -o hollow", dir.path());
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const auto flat = nlohmann::json::parse(test::read_text(dir / "flat" / "summary.json"));
  const auto neg = nlohmann::json::parse(test::read_text(dir / "hollow" / "summary.json"));
  EXPECT_NE(neg["support"]["source"].get<std::string>().find("negative image"), std::string::npos);
  EXPECT_LT(neg["balance_error"].get<double>(), 5e-3);
  EXPECT_NEAR(neg["contact_force_N"][2].get<double>(), flat["contact_force_N"][2].get<double>(),
              1e-3 * flat["contact_force_N"][2].get<double>());
  EXPECT_LT(neg["peak_pressure_Pa"]["body"].get<double>(), 0.7 * flat["peak_pressure_Pa"]["body"].get<double>());
  EXPECT_GT(neg["contacts"]["body_vertices"].get<int>(), 2 * flat["contacts"]["body_vertices"].get<int>());
  // Any closed support can be hollowed: the box given as a support is the
  // same box.
  std::string general = hollow;
  const std::string inner = R"({"box": {"size": ["150 mm", "150 mm", "40 mm"], "divisions": 15},)";
  general.replace(general.find(inner), inner.size(),
                  R"({"support": {"box": {"size": ["150 mm", "150 mm", "40 mm"], "divisions": 15}},)");
  dir.write("general.json", general);
  const auto c = run_palpa("rest general.json -o general", dir.path());
  ASSERT_EQ(c.exit_code, 0) << c.err;
  const auto same = nlohmann::json::parse(test::read_text(dir / "general" / "summary.json"));
  EXPECT_EQ(same["peak_pressure_Pa"]["body"], neg["peak_pressure_Pa"]["body"]);
  EXPECT_EQ(same["contacts"]["body_vertices"], neg["contacts"]["body_vertices"]);
}

TEST(RestCli, RefusesImpossibleSupportsAndBodyCuts) {
  ScratchDir dir;
  const std::string box = R"({"box": {"size": ["150 mm", "150 mm", "20 mm"], "divisions": 30}})";
  const auto with_support = [&](const std::string& support) {
    std::string s = kRestScene;
    s.replace(s.find(box), box.size(), support);
    return s;
  };
  dir.write("deep.json", with_support(R"({"negative_image": {"box": {"size": ["150 mm", "150 mm", "20 mm"]},
                                           "press": "30 mm"}})"));
  const auto a = run_palpa("rest deep.json -o out", dir.path());
  EXPECT_EQ(a.exit_code, 2);
  EXPECT_NE(a.err.find("cut through"), std::string::npos) << a.err;
  // A negative image takes a box or another support, one of them, and not
  // a negative image again.
  dir.write("both.json", with_support(R"({"negative_image": {"box": {"size": ["150 mm", "150 mm", "20 mm"]},
                                           "support": {"box": {"size": ["150 mm", "150 mm", "20 mm"]}}}})"));
  const auto both = run_palpa("rest both.json -o out", dir.path());
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_NE(both.err.find("give either box or support"), std::string::npos) << both.err;
  dir.write("nested.json", with_support(R"({"negative_image": {"support": {"negative_image": {
                                             "box": {"size": ["150 mm", "150 mm", "20 mm"]}}}}})"));
  const auto nested = run_palpa("rest nested.json -o out", dir.path());
  EXPECT_EQ(nested.exit_code, 2);
  EXPECT_NE(nested.err.find("\"negative_image\" inside a negative image"), std::string::npos) << nested.err;
  dir.write("bevel.json", with_support(R"({"box": {"size": ["150 mm", "150 mm", "20 mm"],
                                           "bevel": {"radius": "30 mm", "side": "+x"}}})"));
  const auto b = run_palpa("rest bevel.json -o out", dir.path());
  EXPECT_EQ(b.exit_code, 2);
  EXPECT_NE(b.err.find("bevel.radius"), std::string::npos) << b.err;
  dir.write("fine.json", with_support(R"({"box": {"size": ["150 mm", "150 mm", "20 mm"], "divisions": 1000}})"));
  const auto fine = run_palpa("rest fine.json -o out", dir.path());
  EXPECT_EQ(fine.exit_code, 2);
  EXPECT_NE(fine.err.find("support.box.divisions': 1000 × 1000 × 1000 divisions, 1.2e+07 triangles"),
            std::string::npos) << fine.err;
  std::string cut = kRestScene;
  const std::string edge = "\"edge\": \"7 mm\"";
  cut.replace(cut.find(edge), edge.size(),
              R"("cut": [{"min": ["0 mm", "0 mm", "0 mm"], "max": ["0 mm", "1 mm", "1 mm"]}], "edge": "7 mm")");
  dir.write("cut.json", cut);
  const auto c = run_palpa("rest cut.json -o out", dir.path());
  EXPECT_EQ(c.exit_code, 2);
  EXPECT_NE(c.err.find("min is not below max"), std::string::npos) << c.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  std::string coarse = kRestScene;
  coarse.replace(coarse.find(edge), edge.size(), R"("edge": "20 mm")");
  dir.write("coarse.json", coarse);
  const auto e = run_palpa("rest coarse.json -o out", dir.path());
  EXPECT_EQ(e.exit_code, 2);
  EXPECT_NE(e.err.find("field 'body.edge': an edge of 20 mm for a sphere whose smallest feature is 30 mm"),
            std::string::npos) << e.err;
  // Clip boxes without volume (once a segfault), and boxes that miss the
  // body (once silently ignored), are refused by name.
  const auto with_body_key = [&](const std::string& key) {
    std::string scene = kRestScene;
    scene.replace(scene.find(edge), edge.size(), key + ", " + edge);
    return scene;
  };
  struct Case {
    const char* key;
    const char* says;
  };
  for (const Case& k : {
           Case{R"("clip": {"min": ["-40 mm", "-40 mm", "0 mm"], "max": ["40 mm", "40 mm", "0 mm"]})", "min is not below max"},
           Case{R"("clip": {"min": ["5 mm", "5 mm", "5 mm"], "max": ["5 mm", "5 mm", "5 mm"]})", "min is not below max"},
           Case{R"("clip": {"min": ["500 mm", "500 mm", "500 mm"], "max": ["600 mm", "600 mm", "600 mm"]})",
                "does not overlap the body"},
           Case{R"("cut": [{"min": ["500 mm", "500 mm", "500 mm"], "max": ["600 mm", "600 mm", "600 mm"]}])",
                "does not overlap the body"},
           // Keys that mean nothing for a generated body (once silently ignored).
           Case{R"("scale": 0)", "field 'body.scale': applies to a surface file, not to a generated body"},
           Case{R"("scale": 1e300)", "field 'body.scale': applies to a surface file"},
           Case{R"("unit": "mm")", "field 'body.unit': applies to a surface file"},
           // A refinement finer than the body's edge, at a distance ≥ 0.
           Case{R"("refine": {"edge": "7 mm", "within": "5 mm"})",
                "field 'body.refine.edge': 7 mm is not below the body's edge 7 mm"},
           Case{R"("refine": {"edge": "3 mm", "within": "-5 mm"})", "field 'body.refine.within': a negative distance"},
           Case{R"("refine": {"edge": "3 mm", "size": "5 mm"})", "field 'body.refine.size': is not a known field"},
           Case{R"("refine": {"edge": "3 mm", "within": "0.5 mm"})",
                "field 'body.refine.within': no part of the body is within 500 um of the support (the nearest is 1 mm"},
       }) {
    dir.write("box.json", with_body_key(k.key));
    const auto r = run_palpa("rest box.json -o out", dir.path());
    EXPECT_EQ(r.exit_code, 2) << k.key << "\n" << r.err;
    EXPECT_NE(r.err.find(k.says), std::string::npos) << k.key << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  }
  // A negative image is made from the body: the body cannot be refined
  // toward it. Pressure definitions and recoveries palpa does not have are
  // refused by name (it reports the traction per deformed area only).
  std::string refined = with_support(R"({"negative_image": {"box": {"size": ["150 mm", "150 mm", "20 mm"]}}})");
  refined.replace(refined.find(edge), edge.size(), R"("refine": {"edge": "3 mm", "within": "5 mm"}, )" + edge);
  std::string nominal = kRestScene;
  nominal.replace(nominal.find("\"core\""), 6, R"("pressure": "nominal", "core")");
  std::string recovery = kRestScene;
  recovery.replace(recovery.find("\"core\""), 6, R"("contact": {"recovery": "lumped"}, "core")");
  for (const auto& [scene, says] : {std::pair{refined, "field 'body.refine': a negative image is made from the body"},
                                    std::pair{nominal, "field 'pressure': is not a known field"},
                                    std::pair{recovery, "field 'contact.recovery': is not a known field"}}) {
    dir.write("scene.json", scene);
    const auto r = run_palpa("rest scene.json -o out", dir.path());
    EXPECT_EQ(r.exit_code, 2) << says << "\n" << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << says << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  }
}

}  // namespace
}  // namespace palpa
