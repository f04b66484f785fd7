// SPDX-License-Identifier: AGPL-3.0-or-later
// Column specs, log checks (unsorted time, gaps, NaN, clipping) and the
// monotone calibration table.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "palpa/acquire/log.hpp"

namespace palpa::acquire {
namespace {

const Dimension kForce[] = {Dimension::Force};
const Dimension kLaser[] = {Dimension::Voltage, Dimension::Length};

std::string ramp_log(const char* header, int rows, double dt = 0.01) {
  std::string s = std::string(header) + "\n";
  for (int i = 0; i < rows; ++i) s += fmt::format("{},{}\n", i * dt, 0.1 * i);
  return s;
}

TEST(ColumnSpec, ParsesNamesAndUnits) {
  const ColumnSpec a = parse_column_spec("force_N", "--force-columns");
  EXPECT_EQ(a.name, "force_N");
  EXPECT_EQ(a.unit, "");
  const ColumnSpec b = parse_column_spec(" Force : gf ", "--force-columns");
  EXPECT_EQ(b.name, "Force");
  EXPECT_EQ(b.unit, "gf");
  EXPECT_TRUE(test::throws_error([] { parse_column_spec("Force:furlong", "--force-columns"); }, ErrorKind::Input,
                                 {"--force-columns", "unknown unit 'furlong'"}));
  EXPECT_TRUE(test::throws_error([] { parse_column_specs("a,b,c", 2, "--laser-columns"); }, ErrorKind::Input,
                                 {"--laser-columns", "2 comma-separated"}));
}

TEST(Log, ReadsColumnsByNameBaseNameOrExplicitUnit) {
  test::ScratchDir dir;
  const auto a = dir.write("a.csv", ramp_log("time_ms,force_gf", 20, 10.0));
  const Log la = read_log(a, {"time", ""}, {"force", ""}, kForce, "force");
  EXPECT_EQ(la.time.name, "time_ms");
  EXPECT_NEAR(la.signal.t[3], 0.03, 1e-15);
  EXPECT_NEAR(la.signal.v[10], 1.0 * 9.80665e-3, 1e-15);
  EXPECT_NEAR(la.rate, 100.0, 1e-9);
  EXPECT_EQ(la.lines[0], 2u);
  const auto b = dir.write("b.csv", ramp_log("T,U", 20));
  const Log lb = read_log(b, {"T", "s"}, {"U", "mV"}, kLaser, "laser");
  EXPECT_EQ(lb.value.dimension, Dimension::Voltage);
  EXPECT_NEAR(lb.signal.v[10], 1e-3, 1e-15);
  EXPECT_TRUE(test::throws_error([&] { read_log(b, {"T", "s"}, {"U", ""}, kLaser, "laser"); }, ErrorKind::Input,
                                 {"b.csv", "column 'U' has no unit", "NAME:UNIT"}));
  EXPECT_TRUE(test::throws_error([&] { read_log(b, {"T", "s"}, {"U", "kPa"}, kLaser, "laser"); }, ErrorKind::Input,
                                 {"b.csv", "'kPa' is not a voltage or length"}));
  EXPECT_TRUE(test::throws_error([&] { read_log(a, {"time", ""}, {"load", ""}, kForce, "force"); }, ErrorKind::Input,
                                 {"a.csv", "no column 'load'", "time_ms, force_gf"}));
}

TEST(Log, RefusesUnsortedTimeGapsNanAndShortLogs) {
  test::ScratchDir dir;
  std::string unsorted = ramp_log("time_s,force_N", 20);
  unsorted.replace(unsorted.find("0.05,"), 5, "0.03,");
  const auto u = dir.write("u.csv", unsorted);
  EXPECT_TRUE(test::throws_error([&] { read_log(u, {"time", ""}, {"force", ""}, kForce, "force"); }, ErrorKind::Input,
                                 {"u.csv:7", "time 0.03 s is not after", "strictly increasing"}));
  std::string gap = "time_s,force_N\n";
  for (int i = 0; i < 30; ++i) gap += fmt::format("{},{}\n", i < 15 ? i * 0.01 : 0.2 + i * 0.01, i);
  const auto g = dir.write("g.csv", gap);
  EXPECT_TRUE(test::throws_error([&] { read_log(g, {"time", ""}, {"force", ""}, kForce, "force"); }, ErrorKind::Input,
                                 {"g.csv:17", "a gap of 0.21 s", "from 0.14 s to 0.35 s", "20 samples missing"}));
  std::string nan = ramp_log("time_s,force_N", 20);
  nan.replace(nan.find("0.05,0.5"), 8, "0.05,nan");
  const auto n = dir.write("n.csv", nan);
  EXPECT_TRUE(test::throws_error([&] { read_log(n, {"time", ""}, {"force", ""}, kForce, "force"); }, ErrorKind::Input,
                                 {"n.csv:7"}));
  const auto s = dir.write("s.csv", ramp_log("time_s,force_N", 5));
  EXPECT_TRUE(test::throws_error([&] { read_log(s, {"time", ""}, {"force", ""}, kForce, "force"); }, ErrorKind::Input,
                                 {"s.csv", "5 samples", "at least 10"}));
}

TEST(Log, RefusesASaturatedSensor) {
  test::ScratchDir dir;
  std::string s = "time_s,force_N\n";
  for (int i = 0; i < 100; ++i) s += fmt::format("{},{}\n", i * 0.01, std::min(i, 60) * 0.1 - (i > 80 ? 1.0 : 0.0));
  const auto f = dir.write("clip.csv", s);
  const Log log = read_log(f, {"time", ""}, {"force", ""}, kForce, "force");
  EXPECT_TRUE(test::throws_error([&] { check_not_clipped(log, Extreme::Max, 0.1); }, ErrorKind::Input,
                                 {"clip.csv:62", "column 'force_N'", "saturated", "21 samples in a row"}));
  EXPECT_NO_THROW(check_not_clipped(log, Extreme::Max, 0.3));
  EXPECT_NO_THROW(check_not_clipped(log, Extreme::Min, 0.1));
}

TEST(Calibration, InterpolatesExactlyAndEitherDirection) {
  const Calibration up({0.0, 1.0, 3.0}, {10e-3, 12e-3, 20e-3}, "cal.csv");
  EXPECT_DOUBLE_EQ(up(1.0, "x"), 12e-3);
  EXPECT_NEAR(up(2.0, "x"), 16e-3, 1e-15);
  EXPECT_NEAR(up(0.25, "x"), 10.5e-3, 1e-15);
  const Calibration down({3.0, 1.0, 0.0}, {20e-3, 12e-3, 10e-3}, "cal.csv");  // given in decreasing order
  EXPECT_NEAR(down(2.0, "x"), 16e-3, 1e-15);
  const Calibration falling({0.0, 1.0, 3.0}, {20e-3, 12e-3, 10e-3}, "cal.csv");  // distance falls with voltage
  EXPECT_NEAR(falling(2.0, "x"), 11e-3, 1e-15);
  EXPECT_TRUE(test::throws_error([&] { up(3.5, "laser.csv:9"); }, ErrorKind::Input,
                                 {"laser.csv:9", "outside the calibration table 'cal.csv'"}));
}

TEST(Calibration, RefusesANonMonotoneTable) {
  test::ScratchDir dir;
  const auto f = dir.write("cal.csv", "voltage_V,distance_mm\n0,10\n1,12\n2,11\n3,15\n");
  EXPECT_TRUE(test::throws_error(
      [&] { read_calibration(f, {"voltage", ""}, Dimension::Voltage, {"distance", ""}, Dimension::Length); },
      ErrorKind::Input, {"cal.csv:4", "not monotone", "output"}));
  const auto g = dir.write("cal2.csv", "voltage_V,distance_mm\n0,10\n1,12\n1,13\n");
  EXPECT_TRUE(test::throws_error(
      [&] { read_calibration(g, {"voltage", ""}, Dimension::Voltage, {"distance", ""}, Dimension::Length); },
      ErrorKind::Input, {"cal2.csv:4", "input 1 follows 1"}));
  const auto ok = dir.write("cal3.csv", "voltage_V,distance_mm\n0,10\n2,14\n");
  const Calibration c =
      read_calibration(ok, {"voltage", ""}, Dimension::Voltage, {"distance", ""}, Dimension::Length);
  EXPECT_NEAR(c(1.0, ""), 12e-3, 1e-15);
}

}  // namespace
}  // namespace palpa::acquire
