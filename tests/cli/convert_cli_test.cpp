// SPDX-License-Identifier: AGPL-3.0-or-later
// `palpa convert` end to end: conversions that work, and every kind of bad
// input failing with exit code 2, a message naming the file and the place, and
// nothing (not even a temporary file) left in the output folder.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/test_support.hpp"

namespace palpa {
namespace {

using test::shell_quote;

using test::read_text;

// The path quoted for the shell.
// A triangle and a quad in millimetres.
constexpr const char* kObjMm =
    "v 0 0 0\nv 10 0 0\nv 10 20 0\nv 0 20 0\nv 5 5 5\nf 1 2 5\nf 1 2 3 4\n";

class ConvertCli : public ::testing::Test {
 protected:
  test::ScratchDir in;   // inputs
  test::ScratchDir out;  // outputs: must stay empty after a failure

  // Runs `palpa convert ARGS`, expects exit code 2 and every fragment in
  // stderr, and an untouched output folder.
  void expect_failure(const std::string& args, const std::vector<std::string>& fragments) {
    const test::CommandResult r = test::run_palpa("convert " + args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    for (const std::string& f : fragments) {
      EXPECT_NE(r.err.find(f), std::string::npos) << "stderr lacks '" << f << "':\n" << r.err;
    }
    EXPECT_EQ(r.err.rfind("palpa: error: ", 0), 0u) << r.err;
    EXPECT_EQ(out.entry_count(), 0u) << "the output folder is not empty";
  }

  // A binary file made by palpa itself from kObjMm.
  std::filesystem::path binary_from_obj(const std::string& name) {
    const auto obj = in.write("src.obj", kObjMm);
    const auto p = in / name;
    const test::CommandResult r = test::run_palpa("convert " + shell_quote(obj) + " " + shell_quote(p));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return p;
  }
};

TEST_F(ConvertCli, ConvertsAMeshToMetres) {
  const auto src = in.write("part.obj", kObjMm);
  const test::CommandResult r =
      test::run_palpa("convert " + shell_quote(src) + " " + shell_quote(out / "part.off") + " --unit mm");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("5 vertices, 3 triangles"), std::string::npos) << r.err;
  EXPECT_EQ(read_text(out / "part.off"),
            "OFF\n5 3 0\n0 0 0\n0.01 0 0\n0.01 0.02 0\n0 0.02 0\n0.005 0.005 0.005\n"
            "3 0 1 4\n3 0 1 2\n3 0 2 3\n");
  // A length as the unit: inches.
  const test::CommandResult inch =
      test::run_palpa("convert " + shell_quote(src) + " " + shell_quote(out / "inch.obj") + " --unit '25.4 mm'");
  ASSERT_EQ(inch.exit_code, 0) << inch.err;
  EXPECT_NE(read_text(out / "inch.obj").find("v 0.254 0 0\n"), std::string::npos);
  EXPECT_EQ(out.entry_count(), 2u);
}

TEST_F(ConvertCli, ConvertsThroughBinaryFormatsAndBack) {
  const auto ply = binary_from_obj("m.ply");
  const auto stl = in / "m.stl";
  ASSERT_EQ(test::run_palpa("convert " + shell_quote(ply) + " " + shell_quote(stl)).exit_code, 0);
  const test::CommandResult r = test::run_palpa("convert " + shell_quote(stl) + " " + shell_quote(out / "m.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string obj = read_text(out / "m.obj");
  EXPECT_NE(obj.find("v 10 20 0\n"), std::string::npos) << obj;
  EXPECT_NE(obj.find("f 1 2 3\n"), std::string::npos) << obj;
}

TEST_F(ConvertCli, KeepsOneObjGroup) {
  const auto src = in.write("body.obj",
                            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 9 9 9\n"
                            "g helper\nf 4 2 3\ng body\nf 1 2 3\n");
  const test::CommandResult r = test::run_palpa("convert " + shell_quote(src) + " " + shell_quote(out / "b.off") +
                                                " --obj-group body --unit '0.1 m'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_text(out / "b.off"), "OFF\n3 1 0\n0 0 0\n0.1 0 0\n0 0.1 0\n3 0 1 2\n");
  const auto stl = in.write("x.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  const test::CommandResult bad =
      test::run_palpa("convert " + shell_quote(stl) + " " + shell_quote(out / "x.obj") + " --obj-group body");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("option --obj-group"), std::string::npos) << bad.err;
  EXPECT_EQ(out.entry_count(), 1u);
}

TEST_F(ConvertCli, RewritesCsvColumnsInSi) {
  const auto src = in.write("raw.csv",
                            "# forearm\ntime_ms,indentation_mm,force_gf,trial\n"
                            "0,0,0,1\n500,1.5,1000,1\n");
  const test::CommandResult r = test::run_palpa("convert " + shell_quote(src) + " " + shell_quote(out / "si.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_text(out / "si.csv"),
            "# forearm\ntime_s,indentation_m,force_N,trial\n0,0,0,1\n0.5,0.0015,9.80665,1\n");
}

TEST_F(ConvertCli, HelpShowsAnExampleForEachUse) {
  const test::CommandResult r = test::run_palpa("convert --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("--unit mm"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("raw.csv"), std::string::npos);
  EXPECT_NE(r.out.find(".msh"), std::string::npos);
}

TEST_F(ConvertCli, RefusesToOverwriteItsInput) {
  const auto src = in.write("part.obj", kObjMm);
  const std::string again = (in / "." / "part.obj").string();
  for (const std::string& target : {src.string(), again}) {
    const test::CommandResult r =
        test::run_palpa("convert " + shell_quote(src) + " " + shell_quote(target) + " --unit mm");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("is the same file as IN"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("would overwrite its input"), std::string::npos) << r.err;
    EXPECT_EQ(read_text(src), kObjMm);
  }
}

TEST_F(ConvertCli, WarnsOfAMeshInTheWrongUnit) {
  const auto src = in.write("part.obj", kObjMm);
  const test::CommandResult r = test::run_palpa("convert " + shell_quote(src) + " " + shell_quote(out / "part.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("the mesh is 20 m across: if its coordinates are in millimetres"), std::string::npos) << r.err;
  const test::CommandResult ok =
      test::run_palpa("convert " + shell_quote(src) + " " + shell_quote(out / "ok.ply") + " --unit mm");
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(ok.err.find("across"), std::string::npos) << ok.err;
  const test::CommandResult tiny =
      test::run_palpa("convert " + shell_quote(src) + " " + shell_quote(out / "tiny.ply") + " --unit '0.01 mm'");
  ASSERT_EQ(tiny.exit_code, 0) << tiny.err;
  EXPECT_NE(tiny.err.find("0.2 mm across: if its coordinates are already in metres"), std::string::npos) << tiny.err;
}

TEST_F(ConvertCli, EmptyFileFails) {
  const auto csv = in.write("empty.csv", "");
  expect_failure(shell_quote(csv) + " " + shell_quote(out / "o.csv"), {"empty.csv", "file is empty"});
  const auto obj = in.write("empty.obj", "");
  expect_failure(shell_quote(obj) + " " + shell_quote(out / "o.ply"), {"empty.obj", "file is empty"});
}

TEST_F(ConvertCli, MissingFileFails) {
  expect_failure(shell_quote(in / "nope.stl") + " " + shell_quote(out / "o.ply"), {"nope.stl", "file not found"});
}

TEST_F(ConvertCli, CsvMissingHeaderFails) {
  const auto csv = in.write("nohead.csv", "# note\n0,1\n1,2\n");
  expect_failure(shell_quote(csv) + " " + shell_quote(out / "o.csv"), {"nohead.csv:2", "missing header"});
}

TEST_F(ConvertCli, CsvWrongColumnNamesFail) {
  const auto unknown = in.write("unit.csv", "time_s,indentation_furlong\n0,1\n");
  expect_failure(shell_quote(unknown) + " " + shell_quote(out / "o.csv"),
                 {"unit.csv:1:2", "column 'indentation_furlong'", "unknown unit 'furlong'"});
  const auto dup = in.write("dup.csv", "time_s,force_N,time_s\n0,1,2\n");
  expect_failure(shell_quote(dup) + " " + shell_quote(out / "o.csv"),
                 {"dup.csv:1:3", "column 'time_s'", "duplicate column name"});
  const auto wrong_kind = in.write("kind.csv", "indentation_mm,force_kg\n0,1\n");
  expect_failure(shell_quote(wrong_kind) + " " + shell_quote(out / "o.csv"),
                 {"kind.csv:1:2", "column 'force_kg'", "'kg' is a mass unit", "kgf"});
}

TEST_F(ConvertCli, CsvNonNumericValueFails) {
  const auto csv = in.write("text.csv", "time_s,force_N\n0,1\n0.1,abc\n");
  expect_failure(shell_quote(csv) + " " + shell_quote(out / "o.csv"),
                 {"text.csv:3:2", "column 'force_N'", "'abc' is not a number"});
}

TEST_F(ConvertCli, CsvNanAndInfinityFail) {
  const auto nan = in.write("nan.csv", "time_s,force_N\n0,1\nNaN,2\n");
  expect_failure(shell_quote(nan) + " " + shell_quote(out / "o.csv"),
                 {"nan.csv:3:1", "column 'time_s'", "'NaN' is not a finite number"});
  const auto inf = in.write("inf.csv", "time_s,force_N\n0,inf\n");
  expect_failure(shell_quote(inf) + " " + shell_quote(out / "o.csv"),
                 {"inf.csv:2:2", "column 'force_N'", "'inf' is not a finite number"});
}

TEST_F(ConvertCli, TruncatedBinaryPlyFails) {
  const auto ply = binary_from_obj("cut.ply");
  std::filesystem::resize_file(ply, std::filesystem::file_size(ply) - 7);
  expect_failure(shell_quote(ply) + " " + shell_quote(out / "o.obj"), {"cut.ply", "face[2]", "truncated"});
}

TEST_F(ConvertCli, TruncatedBinaryStlFails) {
  const auto stl = binary_from_obj("cut.stl");
  std::filesystem::resize_file(stl, 84 + 50 + 20);
  expect_failure(shell_quote(stl) + " " + shell_quote(out / "o.obj"),
                 {"cut.stl", "triangle[1]", "truncated", "promises 3 triangles"});
}

TEST_F(ConvertCli, ObjIndexOutOfRangeFails) {
  const auto obj = in.write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n");
  expect_failure(shell_quote(obj) + " " + shell_quote(out / "o.ply"),
                 {"range.obj:5", "vertex index 4 is out of range"});
  const auto zero = in.write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  expect_failure(shell_quote(zero) + " " + shell_quote(out / "o.ply"), {"zero.obj:4", "vertex index 0"});
}

TEST_F(ConvertCli, ObjNegativeIndexOutOfRangeFails) {
  const auto obj = in.write("neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -3\nf -1 -2 -5\n");
  expect_failure(shell_quote(obj) + " " + shell_quote(out / "o.ply"),
                 {"neg.obj:5", "relative vertex index -5", "only 3 vertices"});
}

TEST_F(ConvertCli, MeshWithZeroFacesFails) {
  const auto obj = in.write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  expect_failure(shell_quote(obj) + " " + shell_quote(out / "o.ply"), {"points.obj", "no faces"});
  const auto off = in.write("none.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
  expect_failure(shell_quote(off) + " " + shell_quote(out / "o.obj"), {"none.off", "no faces"});
}

TEST_F(ConvertCli, NonNumericCoordinateFails) {
  const auto obj = in.write("coord.obj", "v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n");
  expect_failure(shell_quote(obj) + " " + shell_quote(out / "o.ply"),
                 {"coord.obj:2", "vertex 2 y", "'x' is not a number"});
}

TEST_F(ConvertCli, UnknownUnitFails) {
  const auto obj = in.write("m.obj", kObjMm);
  expect_failure(shell_quote(obj) + " " + shell_quote(out / "o.ply") + " --unit furlong",
                 {"option --unit", "unknown unit 'furlong'"});
}

TEST_F(ConvertCli, UnitOfTheWrongKindFails) {
  const auto obj = in.write("m.obj", kObjMm);
  expect_failure(shell_quote(obj) + " " + shell_quote(out / "o.ply") + " --unit kg",
                 {"option --unit", "'kg' is a mass unit, not a length unit"});
  expect_failure(shell_quote(obj) + " " + shell_quote(out / "o.ply") + " --unit '5 kg'",
                 {"option --unit", "'5 kg' is a mass, not a length"});
  const auto csv = in.write("curve.csv", "time_s,force_N\n0,1\n");
  expect_failure(shell_quote(csv) + " " + shell_quote(out / "o.csv") + " --unit mm",
                 {"option --unit", "CSV columns carry their own units"});
}

TEST_F(ConvertCli, UnknownExtensionAndKindMismatchFail) {
  const auto obj = in.write("m.obj", kObjMm);
  expect_failure(shell_quote(obj) + " " + shell_quote(out / "o.xyz"), {"o.xyz", "unknown mesh extension '.xyz'"});
  expect_failure(shell_quote(obj) + " " + shell_quote(out / "o.msh"), {"o.msh", "holds a surface"});
  expect_failure(shell_quote(obj) + " " + shell_quote(out / "o.csv"), {"a CSV table converts only to a CSV table"});
}

}  // namespace
}  // namespace palpa
