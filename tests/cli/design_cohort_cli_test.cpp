// SPDX-License-Identifier: AGPL-3.0-or-later
// `palpa design` on a cohort: one support for several bodies, each body's
// maps and the cohort's spread from scratch, resuming after SIGKILL, bad
// cohort scenes refused.
#include <gtest/gtest.h>

#include <csignal>
#include <functional>
#include <vector>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/test_support.hpp"
#include "report/pressure_map_check.hpp"

namespace palpa {
namespace {

using test::run_palpa;
using test::ScratchDir;

nlohmann::json read_json(const std::filesystem::path& p) { return nlohmann::json::parse(test::read_text(p)); }

// The bundled cohort of three soft spheres on a seat.
TEST(DesignCohortCli, OneSupportLowersEveryBodysScoreAndDrawsEachBody) {
  ScratchDir dir;
  const std::string scene = test::shell_quote(test::source_path("examples/design/cohort/scene.json"));
  const auto r = run_palpa("design " + scene + " -o out --iterations 4", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::filesystem::path out = dir / "out";
  for (const char* f : {"support.obj", "support_mm.stl", "cohort.csv", "cohort.svg", "score.svg", "report.html",
                        "summary.json", "checkpoint.json"}) {
    EXPECT_TRUE(std::filesystem::exists(out / f)) << f;
  }
  const auto s = read_json(out / "summary.json");
  EXPECT_EQ(s["cohort"]["objective"], "mean");
  ASSERT_EQ(s["bodies"].size(), 3u);
  EXPECT_TRUE(s["every_body_lower"].get<bool>());
  double mean = 0.0, objective = 0.0;
  for (const auto& b : s["bodies"]) {
    const std::string name = b["name"].get<std::string>();
    // Every body feels less than on the flat seat, from scratch.
    const double ratio = b["zeta_body_ratio"].get<double>();
    EXPECT_LT(ratio, 0.85) << name;
    EXPECT_NEAR(ratio, b["final"]["zeta_body"].get<double>() / b["initial"]["zeta_body"].get<double>(), 1e-12) << name;
    EXPECT_GT(b["body_peak_ratio"].get<double>(), 1.0) << name;
    // Each body's load carried on the one support; its map on the flat seat
    // sums to it.
    EXPECT_LT(b["final"]["balance_error"].get<double>(), 0.005) << name;
    const double load = b["initial"]["pressure_map_force_N"]["load"].get<double>();
    EXPECT_NEAR(b["initial"]["pressure_map_force_N"]["body"].get<double>(), load, 0.05 * load) << name;
    mean += ratio / 3.0;
    objective += b["zeta_ratio"].get<double>() / 3.0;
    // Its maps: the initial support beside the cohort's, the captions' map
    // force its own.
    const std::filesystem::path folder = out / b["folder"].get<std::string>();
    for (const char* f : {"body_before.vtu", "body_after.vtu", "skin_after.ply", "support_after.vtu", "summary.json"}) {
      EXPECT_TRUE(std::filesystem::exists(folder / f)) << name << ": " << f;
    }
    const std::string svg = test::read_text(folder / "body_pressure.svg");
    const auto pic = test::read_pressure_map_picture(svg);
    ASSERT_TRUE(pic.doc.ok()) << name << ": " << pic.doc.error;
    EXPECT_EQ(pic.frames.size(), 2u) << name;
    EXPECT_NE(svg.find("the body &apos;" + name + "&apos;"), std::string::npos) << name;
    const double force = b["initial"]["pressure_map"]["body"]["force_N"].get<double>();
    EXPECT_NEAR(test::number_after(pic.caption_text(), "map force "), force, 5e-3 * force) << pic.caption_text();
  }
  EXPECT_NEAR(s["mean_zeta_body_ratio"].get<double>(), mean, 1e-12);
  // Each body's own design beside it (the scene asks for them): the price of
  // one support for all, each figure from scratch.
  double own = 0.0;
  for (const auto& b : s["bodies"]) {
    const double alone = b["own_design"]["zeta_body_ratio"].get<double>();
    EXPECT_LT(alone, 0.85) << b["name"];
    EXPECT_EQ(b["own_design"]["iterations"], 4) << b["name"];
    own += alone / 3.0;
  }
  EXPECT_NEAR(s["own_designs"]["mean_zeta_body_ratio"].get<double>(), own, 1e-12);
  EXPECT_NEAR(s["own_designs"]["price_of_one_support"].get<double>(), mean / own, 1e-12);
  // The negative image of the average body, scored alike for every body; the
  // summary names each body that feels less on it than on the cohort's
  // support, and says whether it wins on the mean.
  EXPECT_TRUE(std::filesystem::exists(out / "baseline_average_negative_image.obj"));
  double hollow = 0.0;
  nlohmann::json better_on_it = nlohmann::json::array();
  for (const auto& b : s["bodies"]) {
    const double on_it = b["average_negative_image"]["zeta_body_ratio"].get<double>();
    EXPECT_GT(on_it, 0.0) << b["name"];
    EXPECT_LT(on_it, 1.0) << b["name"] << ": a hollow under the bodies lowers their score too";
    if (on_it < b["zeta_body_ratio"].get<double>()) better_on_it.push_back(b["name"]);
    hollow += on_it / 3.0;
  }
  EXPECT_NEAR(s["baseline"]["mean_zeta_body_ratio"].get<double>(), hollow, 1e-12);
  EXPECT_EQ(s["worse_than_baseline_for"], better_on_it);
  EXPECT_EQ(s["worse_than_baseline_on_mean"].get<bool>(), hollow < mean);
  std::printf("[cohort] the negative image of the average body: mean ζ_body ratio %.3f, better for %s\n", hollow,
              better_on_it.dump().c_str());
  EXPECT_NEAR(s["objective_final"].get<double>(), objective, 1e-12);
  // The optimizer's view and the solves from scratch agree within 5%.
  EXPECT_EQ(s["cohort"]["start"], "negative image of the average body");
  EXPECT_NEAR(s["optimizer"]["objective_final"].get<double>() / s["optimizer"]["objective_final_from_scratch"].get<double>(),
              1.0, 0.05);
  // The table across the cohort, one row per body, named in its comments.
  const std::string csv = test::read_text(out / "cohort.csv");
  EXPECT_NE(csv.find("zeta_body_ratio_own_design,zeta_body_ratio_average_negative_image"), std::string::npos) << csv;
  EXPECT_NE(csv.find("# bodies: 1 small, 2 medium, 3 large"), std::string::npos) << csv;
  EXPECT_NE(csv.find("body,zeta_body_initial,zeta_body_final,zeta_body_ratio,peak_initial_kPa"), std::string::npos)
      << csv;
  EXPECT_NE(csv.find("\n3,"), std::string::npos) << csv;
  const std::string spread = test::read_text(out / "cohort.svg");
  EXPECT_NE(spread.find("body (1 small, 2 medium, 3 large)"), std::string::npos);
  EXPECT_NE(spread.find(fmt::format("mean {:.3f}", mean)), std::string::npos);
  EXPECT_NE(test::read_text(out / "report.html").find("The body 'large'"), std::string::npos);
  EXPECT_NE(r.err.find("one support for 3 bodies (mean objective"), std::string::npos) << r.err;
  std::printf("[cohort] mean ζ_body ratio %.3f (each: %.3f %.3f %.3f) after %d iterations; their own designs %.3f "
              "(one support costs %+.1f%%)\n",
              mean, s["bodies"][0]["zeta_body_ratio"].get<double>(), s["bodies"][1]["zeta_body_ratio"].get<double>(),
              s["bodies"][2]["zeta_body_ratio"].get<double>(), s["iterations"].get<int>(), own, 100.0 * (mean / own - 1.0));
}

// Two of the cohort, shaped with the thesis's ladder (deterministic: a
// resumed run ends where an uninterrupted one ends).
std::string two_body_scene() {
  auto doc = read_json(test::source_path("examples/design/cohort/scene.json"));
  doc["bodies"].erase(2);
  doc["cohort"] = {{"objective", "max"}, {"sharpness", 0.1}};
  doc["design"]["method"] = "cg";
  doc["design"]["iterations"] = 2;
  return doc.dump(2);
}

// Killed with SIGKILL once its first iteration is checkpointed, the cohort
// design resumes from each body's saved state to the uninterrupted result,
// to the last bit.
TEST(DesignCohortCli, ResumesAfterSigkillToTheSameResult) {
  ScratchDir dir;
  dir.write("scene.json", two_body_scene());
  ASSERT_EQ(run_palpa("design scene.json -o straight", dir.path()).exit_code, 0);
  const auto straight = read_json(dir / "straight" / "summary.json");
  const auto reached = [&] {
    try {
      return read_json(dir / "killed" / "checkpoint.json")["iteration"].get<int>() >= 1;
    } catch (const std::exception&) {
      return false;
    }
  };
  const int code = test::run_palpa_signalled_when("design scene.json -o killed", dir.path(), reached, SIGKILL);
  EXPECT_EQ(code, 128 + SIGKILL) << "the kill should land inside the run";
  EXPECT_FALSE(std::filesystem::exists(dir / "killed" / "summary.json"));
  const auto checkpoint = read_json(dir / "killed" / "checkpoint.json");
  ASSERT_EQ(checkpoint["bodies"].size(), 2u);
  EXPECT_EQ(checkpoint["bodies"][1]["name"], "medium");
  const auto r = run_palpa("design scene.json -o killed --resume", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("resuming after iteration"), std::string::npos) << r.err;
  const auto resumed = read_json(dir / "killed" / "summary.json");
  EXPECT_EQ(resumed["objective_final"].get<double>(), straight["objective_final"].get<double>());
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(resumed["bodies"][i]["final"]["zeta_body"].get<double>(),
              straight["bodies"][i]["final"]["zeta_body"].get<double>());
  }
  EXPECT_EQ(straight["cohort"]["sharpness"].get<double>(), 0.1);
}

// Spread over two processes with MPI (body i on rank i mod 2), the design is
// the one process's to the last bit: every number of the summary but the
// times, and the shape to make.
TEST(DesignCohortCli, TwoProcessesGiveTheSameDesignToTheLastBit) {
  ScratchDir dir;
  auto doc = read_json(test::source_path("examples/design/cohort/scene.json"));
  doc["bodies"].erase(2);
  ASSERT_TRUE(doc["cohort"]["single_designs"].get<bool>());  // each on its own rank too
  dir.write("cohort.json", doc.dump());
  const std::string scene = "cohort.json";
  const auto one = run_palpa("design " + scene + " -o one --iterations 1", dir.path());
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const auto two = test::run_palpa_mpi(2, "design " + scene + " -o two --iterations 1", dir.path());
  ASSERT_EQ(two.exit_code, 0) << two.out << two.err;
  EXPECT_NE(two.err.find("over 2 processes"), std::string::npos) << two.err;
  EXPECT_EQ(test::read_text(dir / "two" / "support.obj"), test::read_text(dir / "one" / "support.obj"));
  EXPECT_EQ(test::read_text(dir / "two" / "cohort.csv"), test::read_text(dir / "one" / "cohort.csv"));
  // Every figure but the times.
  const std::function<void(const nlohmann::json&, const nlohmann::json&, const std::string&)> same =
      [&](const nlohmann::json& a, const nlohmann::json& b, const std::string& at) {
        if (a.is_object()) {
          for (const auto& [k, v] : a.items()) {
            if (k.find("seconds") != std::string::npos || k == "iteration_per_equilibrium") continue;
            ASSERT_TRUE(b.contains(k)) << at << "." << k;
            same(v, b[k], at + "." + k);
          }
        } else if (a.is_array()) {
          ASSERT_EQ(a.size(), b.size()) << at;
          for (std::size_t i = 0; i < a.size(); ++i) same(a[i], b[i], fmt::format("{}[{}]", at, i));
        } else {
          EXPECT_EQ(a, b) << at;
        }
      };
  same(read_json(dir / "one" / "summary.json"), read_json(dir / "two" / "summary.json"), "");
  // More processes than bodies: refused, said once.
  dir.write("one-body.json", R"({"palpa_design": 1,
    "body": {"generate": {"shape": "sphere", "length": "60 mm"}, "edge": "7 mm", "depth": "8 mm",
             "material": {"model": "neo-hookean", "parameters": {"E": "20 kPa", "nu": 0.4}},
             "position": ["0 mm", "0 mm", "31 mm"]},
    "core": {"mass": "0.5 kg", "free": ["z"]},
    "support": {"box": {"size": ["150 mm", "150 mm", "20 mm"], "divisions": 30}}})");
  const auto refused = test::run_palpa_mpi(2, "design one-body.json -o three", dir.path());
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  const std::string said = "2 processes for 1 body";
  const auto at = refused.err.find(said);
  EXPECT_NE(at, std::string::npos) << refused.err;
  EXPECT_EQ(refused.err.find(said, at + 1), std::string::npos) << refused.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "three"));
}

// The Slurm example, with srun standing in as mpirun over the job's tasks:
// it runs the design over them, and submitted again it finds the run
// finished and leaves it as it is.
TEST(DesignCohortCli, TheSlurmExampleRunsUnderSrunAndResumes) {
  ScratchDir dir;
  auto doc = read_json(test::source_path("examples/design/cohort/scene.json"));
  doc["bodies"].erase(2);
  doc["design"]["iterations"] = 1;
  dir.write("cohort.json", doc.dump());
  std::filesystem::create_directories(dir / "bin");
  dir.write("bin/srun", "#!/bin/sh\nexec mpirun --oversubscribe -np \"$SLURM_NTASKS\" \"$@\"\n");
  std::filesystem::permissions(dir / "bin" / "srun", std::filesystem::perms::owner_all);
  const std::string job = fmt::format(
      "cd {} && PATH={}:$PATH PALPA={} SLURM_NTASKS=2 SLURM_CPUS_PER_TASK=1 OMPI_ALLOW_RUN_AS_ROOT=1 "
      "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 bash {} cohort.json designed",
      test::shell_quote(dir.path()), test::shell_quote(dir / "bin"), test::shell_quote(test::palpa_binary()),
      test::shell_quote(test::source_path("workflow/slurm/cohort-design.sbatch")));
  const auto first = test::run_shell(job, dir.path());
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_NE(first.err.find("over 2 processes"), std::string::npos) << first.err;
  const auto s = read_json(dir / "designed" / "summary.json");
  EXPECT_EQ(s["bodies"].size(), 2u);
  EXPECT_EQ(s["iterations"], 1);
  const auto again = test::run_shell(job, dir.path());
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.err.find("is finished (1 iterations"), std::string::npos) << again.err;
}

TEST(DesignCohortCli, RefusesBadCohortsWithoutWritingAnything) {
  ScratchDir dir;
  const auto base = read_json(test::source_path("examples/design/cohort/scene.json"));
  dir.write("medium.json", nlohmann::json{{"palpa_design", 1}, {"body", base["bodies"][1]["body"]}}.dump());
  struct Case {
    std::string name;
    std::function<void(nlohmann::json&)> change;
    std::vector<std::string> fragments;
  };
  const std::vector<Case> cases{
      {"no body", [](auto& d) { d["bodies"] = nlohmann::json::array(); }, {"'bodies'", "at least one body"}},
      {"twice", [](auto& d) { d["bodies"][1]["name"] = "small"; }, {"'bodies[1].name'", "a second body named 'small'"}},
      {"both", [](auto& d) { d["bodies"][0]["scene"] = "medium.json"; }, {"'bodies[0]'", "either scene or body"}},
      {"no scene", [](auto& d) { d["bodies"][0] = {{"name", "gone"}, {"scene", "gone.json"}}; }, {"gone.json"}},
      {"objective", [](auto& d) { d["cohort"] = {{"objective", "median"}}; }, {"'cohort.objective'", "median"}},
      {"quantile", [](auto& d) { d["cohort"] = {{"quantile", 0.9}}; }, {"'cohort.quantile'", "\"objective\": \"quantile\""}},
      {"beside", [](auto& d) { d["body"] = d["bodies"][0]["body"]; }, {"'body'", "beside \"bodies\""}},
      {"start", [](auto& d) { d["cohort"]["start"] = "mould"; }, {"'cohort.start'", "unknown start 'mould'"}},
      {"no baseline", [](auto& d) { d["cohort"] = {{"start", "baseline"}, {"baseline", false}}; },
       {"'cohort.start'", "a baseline to start on"}},
      {"baselines", [](auto& d) { d["baselines"] = nlohmann::json::array(); }, {"'baselines'", "cohort"}},
      {"member", [](auto& d) { d["bodies"][2]["body"]["edge"] = "-1 mm"; }, {"the cohort's body 'large'", "edge"}},
      {"one body", [](auto& d) { d["body"] = d["bodies"][0]["body"]; d.erase("bodies"); }, {"'cohort'", "one body"}},
  };
  for (const Case& c : cases) {
    auto doc = base;
    c.change(doc);
    dir.write("bad.json", doc.dump());
    const auto r = run_palpa("design bad.json -o out", dir.path());
    EXPECT_EQ(r.exit_code, 2) << c.name << ": " << r.err;
    for (const std::string& f : c.fragments) EXPECT_NE(r.err.find(f), std::string::npos) << c.name << ": " << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out")) << c.name;
  }
  // A body from a scene file: its body and core, the cohort's support.
  auto doc = base;
  doc["bodies"][1] = {{"name", "medium"}, {"scene", "medium.json"}, {"core", base["bodies"][1]["core"]}};
  doc["bodies"].erase(2);
  doc["design"]["iterations"] = 0;
  dir.write("from-file.json", doc.dump());
  const auto r = run_palpa("design from-file.json -o out", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto s = read_json(dir / "out" / "summary.json");
  EXPECT_NE(s["bodies"][1]["source"].get<std::string>().find("medium.json"), std::string::npos);
}

}  // namespace
}  // namespace palpa
