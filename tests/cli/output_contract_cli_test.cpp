// SPDX-License-Identifier: AGPL-3.0-or-later
// The output contract, held by every command that writes a folder (its -o, or
// a folder of frames or plots beside a file), under what a user's file system
// may hold: the folder naming a file or under one, a file-size limit
// (ulimit -f), and a folder link inside an output folder that leads outside
// it. Whatever the outcome, nothing outside the output folder
// changes, and a failed run leaves no temporary file or lock behind.
// (A read-only parent is not among them: the suite runs as root in CI.)
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <sys/stat.h>

#include <filesystem>
#include <map>
#include <utility>
#include <string>
#include <vector>

#include "common/test_support.hpp"
#include "fit/bad_datasets.hpp"

namespace palpa {
namespace {

using test::ScratchDir;
using test::shell_quote;

struct Command {
  std::string name;
  std::map<std::string, std::string> inputs;  // file -> content
  std::string args;                           // with {out} for the output folder
  std::string subfolder;                      // one the command writes into
};

// A soft sphere resting on a box: the body, core and support of the rest and
// design scenes.
const std::string kSphereOnABox = R"(
    "body": {"generate": {"shape": "sphere", "length": "60 mm"}, "edge": "7 mm", "depth": "8 mm",
             "material": {"model": "neo-hookean", "parameters": {"E": "20 kPa", "nu": 0.4}},
             "position": ["0 mm", "0 mm", "31 mm"]},
    "core": {"mass": "0.5 kg", "free": ["z"]},
    "support": {"box": {"size": ["150 mm", "150 mm", "20 mm"], "divisions": 10}})";

std::string example(const std::string& file) { return test::read_text(test::source_path("examples/" + file)); }

std::vector<Command> commands() {
  return {
      {"fit",
       {{"a.csv", fit::test::kGoodCurve}, {"dataset.json", fit::test::indentation_dataset()}},
       "fit dataset.json --model neo-hookean --mesh-level 0 --steps 4 --max-iterations 2 -o {out}",
       "curves"},
      {"sim3d",
       {{"scene.json", R"({"palpa_scene": 1,
          "body": {"box": {"size": ["20 mm", "20 mm", "6 mm"], "cells": [4, 4, 2]},
                   "materials": [{"material": {"model": "neo-hookean", "parameters": {"E": "10 kPa", "nu": 0.3}}}],
                   "fixed": [{"set": "bottom"}]},
          "obstacles": [{"name": "ball", "shape": {"sphere": {"radius": "5 mm", "level": 1}},
                         "path": {"direction": [0, 0, -1], "depth": "0.5 mm"}}],
          "steps": 1})"}},
       "sim3d scene.json -o {out}",
       "frames"},
      {"rest",
       {{"rest.json", R"({"palpa_rest": 1, )" + kSphereOnABox + "}"}},
       "rest rest.json -o {out}",
       ""},  // (no folder of its own inside)
      {"design",
       {{"design.json", R"({"palpa_design": 1, )" + kSphereOnABox + R"(,
          "design": {"method": "cg", "iterations": 1,
                     "region": {"min": ["-60 mm", "-60 mm", "-5 mm"], "max": ["60 mm", "60 mm", "5 mm"]}}})"}},
       "design design.json --no-baselines -o {out}",
       ""},
      // Folders beside a file output: the poke's frames, the acquisition's plots.
      {"poke",
       {{"m.json", R"({"model": "neo-hookean", "parameters": {"E": "10 kPa", "nu": 0.45}})"}},
       "poke --material m.json --thickness 10mm --radius 3mm --depth 1mm --steps 2 --mesh-level 0 --vtu {out} "
       "-o curve.csv",
       ""},
      {"acquire pressure",
       {{"support.obj", example("acquire/pressure/support.obj")},
        {"locations.csv", example("acquire/pressure/locations.csv")},
        {"samples.csv", example("acquire/pressure/samples.csv")}},
       "acquire pressure --mesh support.obj --locations locations.csv --samples samples.csv --load 343N -o {out}",
       ""},
      {"acquire",
       {{"force.csv", example("acquire/poke/force.csv")},
        {"laser.csv", example("acquire/poke/laser.csv")},
        {"laser-calibration.csv", example("acquire/poke/laser-calibration.csv")}},
       "acquire poke --force force.csv --laser laser.csv --calibration laser-calibration.csv --plots {out} "
       "-o curve.csv",
       ""},
  };
}

// Every entry under `root` but those under `skip`: its size and time.
std::map<std::string, std::string> snapshot(const std::filesystem::path& root, const std::filesystem::path& skip) {
  std::map<std::string, std::string> s;
  for (auto it = std::filesystem::recursive_directory_iterator(root); it != std::filesystem::recursive_directory_iterator();
       ++it) {
    const std::filesystem::path p = it->path();
    if (p == skip) {
      it.disable_recursion_pending();
      continue;
    }
    std::error_code ec;
    if (it->is_symlink(ec)) {  // (its target's time may be anything's: a stream's)
      s[p.lexically_relative(root).string()] = "link to " + std::filesystem::read_symlink(p, ec).string();
      continue;
    }
    const auto size = it->is_regular_file(ec) ? it->file_size(ec) : 0;
    s[p.lexically_relative(root).string()] =
        fmt::format("{} {}", size, std::filesystem::last_write_time(p, ec).time_since_epoch().count());
  }
  return s;
}

// No temporary, staged file, lock, folder holding nothing but palpa's
// journal, or part of a checkpoint without the checkpoint under `out` (what
// is left there is a run that --resume continues).
void expect_nothing_left(const std::filesystem::path& out, const std::string& what) {
  std::error_code ec;
  if (!std::filesystem::exists(out, ec)) return;
  const auto holds_only_journals = [](const std::filesystem::path& dir) {
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
      const std::string n = e.path().filename().string();
      if (n != ".palpa-outputs" && n != ".palpa-outputs-previous") return false;
    }
    return true;
  };
  EXPECT_FALSE(holds_only_journals(out)) << what << ": left " << out << " with nothing but its journal";
  for (const auto& e : std::filesystem::recursive_directory_iterator(out)) {
    const std::string name = e.path().filename().string();
    EXPECT_EQ(name.find(".tmp-"), std::string::npos) << what << ": left " << e.path();
    EXPECT_NE(name, ".palpa-lock") << what << ": left the lock";
    if (e.is_directory()) EXPECT_FALSE(holds_only_journals(e.path())) << what << ": left " << e.path();
    if (name.find(".warm-") != std::string::npos) {
      EXPECT_TRUE(std::filesystem::exists(e.path().parent_path() / "checkpoint.json"))
          << what << ": left " << e.path() << " without its checkpoint";
    }
  }
}

void write_inputs(const ScratchDir& dir, const Command& c) {
  for (const auto& [file, content] : c.inputs) dir.write(file, content);
}

std::string args_for(const Command& c, const std::string& out) {
  std::string a = c.args;
  a.replace(a.find("{out}"), 5, out);
  return a;
}

TEST(OutputContract, AnOutputThatIsAFileOrUnderOneIsRefusedAndNothingChanges) {
  for (const Command& c : commands()) {
    for (const char* out : {"plain.txt", "plain.txt/out"}) {
      ScratchDir dir;
    write_inputs(dir, c);
      dir.write("plain.txt", "the user's file\n");
      const auto before = snapshot(dir.path(), dir / "none");
      const auto r = test::run_palpa(args_for(c, out), dir.path());
      EXPECT_EQ(r.exit_code, 2) << c.name << " -o " << out << "\n" << r.err;
      EXPECT_NE(r.err.find("plain.txt"), std::string::npos) << c.name << ": " << r.err;
      EXPECT_EQ(snapshot(dir.path(), dir / "none"), before) << c.name << " -o " << out;
    }
  }
}

// An empty path, or a link to nothing, is refused naming what it is.
TEST(OutputContract, AnEmptyPathOrALinkToNothingIsRefused) {
  for (const Command& c : commands()) {
    for (const auto& [out, says] : {std::pair{"''", "an empty path"}, std::pair{"dangling", "is a link to nothing"}}) {
      ScratchDir dir;
      write_inputs(dir, c);
      std::filesystem::create_symlink(dir / "nowhere", dir / "dangling");
      const auto before = snapshot(dir.path(), dir / "none");
      const auto r = test::run_palpa(args_for(c, out), dir.path());
      EXPECT_EQ(r.exit_code, 2) << c.name << " -o " << out << "\n" << r.err;
      EXPECT_NE(r.err.find(says), std::string::npos) << c.name << ": " << r.err;
      EXPECT_EQ(snapshot(dir.path(), dir / "none"), before) << c.name << " -o " << out;
    }
  }
}

// A folder that holds a file of the user's is refused unless --overwrite,
// and with it the user's file stays.
TEST(OutputContract, ANonEmptyFolderIsRefusedUnlessOverwriteAndTheUsersFilesStay) {
  std::vector<Command> all = commands();
  // Refused before its inputs are read.
  all.push_back({"subject body", {}, "subject body missing.json --fits fits -o {out}", ""});
  for (const Command& c : all) {
    ScratchDir dir;
    write_inputs(dir, c);
    dir.write("out/user.txt", "the user's file\n");
    const auto before = snapshot(dir.path(), dir / "none");
    const auto r = test::run_palpa(args_for(c, "out"), dir.path());
    EXPECT_EQ(r.exit_code, 2) << c.name << "\n" << r.err;
    EXPECT_NE(r.err.find("'out' is not empty"), std::string::npos) << c.name << ": " << r.err;
    EXPECT_EQ(snapshot(dir.path(), dir / "none"), before) << c.name;
    if (c.inputs.empty()) continue;
    const auto again = test::run_palpa(args_for(c, "out") + " --overwrite", dir.path());
    EXPECT_EQ(again.exit_code, 0) << c.name << "\n" << again.err;
    EXPECT_EQ(test::read_text(dir / "out" / "user.txt"), "the user's file\n") << c.name;
  }
}

// A pipe, or a link to a stream, named as the output is refused before
// anything runs, and stays what it was.
TEST(OutputContract, APipeOrAStreamAsTheOutputIsRefusedAndKept) {
  std::vector<Command> all = commands();
  all.push_back({"material", {}, "material --model neo-hookean --E 10kPa --nu 0.45 -o {out}", ""});
  all.push_back({"subject plan", {}, "subject plan missing.json -o {out}", ""});
  for (const Command& c : all) {
    for (const char* out : {"fifo", "stdout"}) {
      ScratchDir dir;
      write_inputs(dir, c);
      ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
      std::filesystem::create_symlink("/proc/self/fd/1", dir / "stdout");
      const auto before = snapshot(dir.path(), dir / "none");
      const auto r = test::run_palpa(args_for(c, out), dir.path());
      EXPECT_EQ(r.exit_code, 2) << c.name << " -o " << out << "\n" << r.err;
      EXPECT_NE(r.err.find("a device, a pipe or a stream"), std::string::npos) << c.name << ": " << r.err;
      EXPECT_EQ(snapshot(dir.path(), dir / "none"), before) << c.name << " -o " << out;
      EXPECT_TRUE(std::filesystem::is_fifo(dir / "fifo")) << c.name;
    }
  }
}

// Quiet, the message fits under the limit; with the logs, stderr (a file
// here) meets the limit too, and the exit code alone says what happened. A
// limit of 512 bytes stops the first file, 10 kB a later one (a report).
TEST(OutputContract, AFileSizeLimitFailsTheRunCleanly) {
  for (const Command& c : commands()) {
    for (const auto& [blocks, quiet] : {std::pair{1, true}, std::pair{1, false}, std::pair{20, true}}) {
      ScratchDir dir;
      write_inputs(dir, c);
      const auto before = snapshot(dir.path(), dir / "out");
      const auto r = test::run_shell(fmt::format("ulimit -f {}; {} {}{}", blocks, shell_quote(test::palpa_binary()),
                                                 quiet ? "-q " : "", args_for(c, "out")),
                                     dir.path());
      EXPECT_EQ(r.exit_code, 2) << c.name << " at " << blocks << (quiet ? " -q" : "") << "\n" << r.err;
      if (quiet) EXPECT_NE(r.err.find("writing failed"), std::string::npos) << c.name << ": " << r.err;
      EXPECT_EQ(snapshot(dir.path(), dir / "out"), before) << c.name;
      expect_nothing_left(dir / "out", c.name);
    }
  }
}

TEST(OutputContract, AFolderLinkInsideTheOutputIsNeverWrittenThrough) {
  for (const Command& c : commands()) {
    if (c.subfolder.empty()) continue;
    ScratchDir dir;
    write_inputs(dir, c);
    std::filesystem::create_directories(dir / "elsewhere");
    dir.write("elsewhere/keep.txt", "outside\n");
    std::filesystem::create_directories(dir / "out");
    std::filesystem::create_directory_symlink(dir / "elsewhere", dir / "out" / c.subfolder);
    const auto before = snapshot(dir / "elsewhere", dir / "none");
    const auto r = test::run_palpa(args_for(c, "out") + " --overwrite", dir.path());
    EXPECT_EQ(r.exit_code, 2) << c.name << "\n" << r.err;
    EXPECT_NE(r.err.find(fmt::format("'{}' in the output folder is a link", c.subfolder)), std::string::npos)
        << c.name << ": " << r.err;
    EXPECT_EQ(snapshot(dir / "elsewhere", dir / "none"), before) << c.name;
    expect_nothing_left(dir / "out", c.name);
  }
}

}  // namespace
}  // namespace palpa
