// SPDX-License-Identifier: AGPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "common/test_support.hpp"
#include "palpa/core/json.hpp"

namespace palpa {
namespace {

TEST(Json, SyntaxErrorNamesLineAndColumn) {
  test::ScratchDir dir;
  const auto p = dir.write("m.json", "{\n  \"E\": \"10 kPa\",\n  \"nu\": ,\n}\n");
  EXPECT_TRUE(test::throws_error([&] { read_json_file(p); }, ErrorKind::Input,
                                 {"m.json:3:", "invalid JSON"}));
}

// Found by fuzzing: a number beyond a double's range escaped as another
// exception and aborted the program.
TEST(Json, NumbersBeyondADoublesRangeAreRefused) {
  test::ScratchDir dir;
  const auto p = dir.write("big.json", "{\"E\": 1111111111111111e1111111111}");
  EXPECT_TRUE(test::throws_error([&] { read_json_file(p); }, ErrorKind::Input,
                                 {"big.json", "invalid JSON", "number overflow", "range of a double"}));
}

// The parser would keep the last of two values silently.
TEST(Json, AKeyTwiceInOneObjectIsRefusedByName) {
  test::ScratchDir dir;
  const auto top = dir.write("top.json", R"({"E": "10 kPa", "nu": 0.3, "E": "20 kPa"})");
  EXPECT_TRUE(test::throws_error([&] { read_json_file(top); }, ErrorKind::Input,
                                 {"top.json", "\"E\" appears twice at the top level"}));
  const auto nested =
      dir.write("nested.json", R"({"curves": [{"file": "a.csv"}, {"file": "b.csv", "role": "x", "file": "c.csv"}]})");
  EXPECT_TRUE(test::throws_error([&] { read_json_file(nested); }, ErrorKind::Input,
                                 {"nested.json", "\"file\" appears twice in curves[1]"}));
  // The same key in different objects is fine.
  const auto fine = dir.write("fine.json", R"({"a": {"x": 1}, "b": {"x": 2}, "c": [{"x": 3}, {"x": 4}]})");
  EXPECT_EQ(read_json_file(fine)["c"][1]["x"], 4);
}

TEST(Json, EmptyAndMissingFilesAreErrors) {
  test::ScratchDir dir;
  const auto p = dir.write("empty.json", "  \n");
  EXPECT_TRUE(test::throws_error([&] { read_json_file(p); }, ErrorKind::Input, {"empty"}));
  EXPECT_TRUE(test::throws_error([&] { read_json_file(dir / "none.json"); }, ErrorKind::Input,
                                 {"none.json", "file not found"}));
}

TEST(Json, ViewReportsFieldPaths) {
  const Json j = Json::parse(R"({"parameters": {"E": "12 kPa", "nu": 0.45, "bad": "12", "n": [1, 2]}})");
  const JsonView root(j, "m.json");
  EXPECT_DOUBLE_EQ(root.at("parameters").at("E").as_quantity(Dimension::Pressure), 12000.0);
  EXPECT_DOUBLE_EQ(root.at("parameters").at("nu").as_quantity(Dimension::Dimensionless), 0.45);
  EXPECT_TRUE(test::throws_error(
      [&] { root.at("parameters").at("bad").as_quantity(Dimension::Pressure); }, ErrorKind::Input,
      {"m.json", "field 'parameters.bad'", "no unit"}));
  EXPECT_TRUE(test::throws_error([&] { root.at("parameters").at("mu"); }, ErrorKind::Input,
                                 {"field 'parameters.mu'", "missing"}));
  EXPECT_TRUE(test::throws_error([&] { root.at("parameters").at("n").at(5); }, ErrorKind::Input,
                                 {"parameters.n"}));
  EXPECT_TRUE(test::throws_error([&] { root.at("parameters").at("nu").as_string(); },
                                 ErrorKind::Input, {"parameters.nu", "a string"}));
  EXPECT_TRUE(test::throws_error([&] { root.at("parameters").expect_only({"E", "nu"}); },
                                 ErrorKind::Input, {"parameters.bad", "not a known field"}));
}

TEST(Json, WriteIsAtomicAndRoundTrips) {
  test::ScratchDir dir;
  const Json j = {{"model", "neo-hookean"}, {"E", "10 kPa"}};
  write_json_file(dir / "m.json", j);
  EXPECT_EQ(read_json_file(dir / "m.json"), j);
  EXPECT_EQ(dir.entry_count(), 1u);
}

// JSON has no NaN or infinity (nlohmann would write null): an output holding
// one is refused by file and field, and nothing is written; null on purpose
// stays null.
TEST(Json, ANonFiniteValueIsRefusedByFieldAndNothingIsWritten) {
  test::ScratchDir dir;
  Json j = {{"curves", Json::array({Json{{"force", 1.5}}, Json{{"force", std::nan("")}}})}};
  EXPECT_TRUE(test::throws_error([&] { write_json_file(dir / "r.json", j); }, ErrorKind::Internal,
                                 {"r.json", "curves[1].force", "not a finite number"}));
  EXPECT_EQ(dir.entry_count(), 0u);
  j["curves"][1]["force"] = -std::numeric_limits<double>::infinity();
  EXPECT_TRUE(test::throws_error([&] { (void)format_json(j, "s.json"); }, ErrorKind::Internal, {"curves[1].force"}));
  j["curves"][1]["force"] = nullptr;
  j["top"] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(test::throws_error([&] { (void)format_json(j, "s.json"); }, ErrorKind::Internal, {"field 'top'"}));
  j.erase("top");
  EXPECT_EQ(format_json(j, "s.json"), j.dump(2) + "\n");
}

}  // namespace
}  // namespace palpa
