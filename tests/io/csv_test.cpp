// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/csv.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <random>

#include "common/test_support.hpp"
#include "io/io_test_support.hpp"

namespace palpa {
namespace {

constexpr double kGramForce = 9.80665e-3;  // N

TEST(Csv, ReadsQuantityColumnsInSi) {
  test::ScratchDir dir;
  const auto p = dir.write("curve.csv",
                           "time_s,indentation_mm,force_gf,pressure_kPa\n"
                           "0,0,0,0\n"
                           "0.5,0.25,12.5,1.5\n"
                           "1,2,100,-3\n");
  const CsvTable t = read_csv(p);
  ASSERT_EQ(t.rows(), 3u);
  ASSERT_EQ(t.column_count(), 4u);
  const auto d = t.quantity("indentation", Dimension::Length);
  const auto f = t.quantity("force", Dimension::Force);
  const auto s = t.quantity("time", Dimension::Time);
  const auto q = t.quantity("pressure", Dimension::Pressure);
  EXPECT_DOUBLE_EQ(d[1], 0.25e-3);
  EXPECT_DOUBLE_EQ(d[2], 2e-3);
  EXPECT_NEAR(f[1], 12.5 * kGramForce, 1e-15);
  EXPECT_NEAR(f[2], 100 * kGramForce, 1e-15);
  EXPECT_EQ(s[1], 0.5);
  EXPECT_DOUBLE_EQ(q[1], 1500.0);
  EXPECT_DOUBLE_EQ(q[2], -3000.0);
  // The same quantity in metres is returned unchanged.
  const auto p2 = dir.write("m.csv", "indentation_m\n0.00125\n");
  EXPECT_EQ(read_csv(p2).quantity("indentation", Dimension::Length)[0], 0.00125);
}

TEST(Csv, ReadsPlainColumnsByExactName) {
  test::ScratchDir dir;
  const auto p = dir.write("t.csv", "trial,stretch,depth_mm\n1,1.5,2\n2,1.25,3\n");
  const CsvTable t = read_csv(p);
  EXPECT_EQ(t.column("trial")[1], 2.0);
  EXPECT_EQ(t.column("stretch")[0], 1.5);
  EXPECT_EQ(t.column("depth_mm")[1], 3.0);  // exact name: values as stored (mm)
  EXPECT_TRUE(t.has_column("stretch"));
  EXPECT_FALSE(t.has_column("Stretch"));
  EXPECT_FALSE(t.find_quantity("force", Dimension::Force).has_value());
}

TEST(Csv, SkipsCommentsAndBlankLinesAcceptsCrlfBomAndQuotes) {
  test::ScratchDir dir;
  const auto p = dir.write("t.csv",
                           "\xEF\xBB\xBF# punch 4 mm\r\n"
                           "\r\n"
                           "\"time_s\", \"force_N\"\r\n"
                           "# a note between rows\r\n"
                           "0.1, 2\r\n"
                           "\r\n"
                           "0.2,+3.5e-1\r\n");
  const CsvTable t = read_csv(p);
  ASSERT_EQ(t.rows(), 2u);
  EXPECT_EQ(t.names()[0], "time_s");
  EXPECT_EQ(t.column("force_N")[1], 0.35);
  ASSERT_EQ(t.comments().size(), 2u);
  EXPECT_EQ(t.comments()[0], "punch 4 mm");
  EXPECT_EQ(t.line_of_row(0), 5u);
  EXPECT_EQ(t.line_of_row(1), 7u);
  const ErrorContext at = t.context_of(1, "force_N");
  EXPECT_EQ(at.line, 7u);
  EXPECT_EQ(at.column, 2u);
}

TEST(Csv, WriteReadRoundTripIsBitExact) {
  test::ScratchDir dir;
  auto rng = test::make_rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> e(-320, 300);
  std::vector<double> a;
  std::vector<double> b;
  for (int i = 0; i < 500; ++i) {
    const double mantissa = u(rng);
    a.push_back(mantissa * std::pow(10.0, e(rng)));  // includes subnormals and 0
    b.push_back(std::nextafter(u(rng), 2.0));
  }
  a.push_back(-0.0);
  b.push_back(std::numeric_limits<double>::max());
  a.push_back(std::numeric_limits<double>::denorm_min());
  b.push_back(0.1);
  CsvTable t;
  t.add_comment("round trip");
  t.add_column("x_m", a);
  t.add_column("n", b);
  const auto p = dir / "rt.csv";
  write_csv(p, t);
  const CsvTable r = read_csv(p);
  ASSERT_EQ(r.rows(), a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(std::bit_cast<std::uint64_t>(r.column("x_m")[i]), std::bit_cast<std::uint64_t>(a[i]))
        << "row " << i << ": " << a[i];
    ASSERT_EQ(std::bit_cast<std::uint64_t>(r.column("n")[i]), std::bit_cast<std::uint64_t>(b[i]));
  }
  EXPECT_EQ(r.comments(), t.comments());
  EXPECT_EQ(dir.entry_count(), 1u);  // no temporary file left
}

TEST(Csv, AddQuantityConvertsFromSi) {
  CsvTable t;
  t.add_quantity("force", "gf", Dimension::Force, {2 * kGramForce});
  t.add_quantity("indentation", "mm", Dimension::Length, {0.003});
  EXPECT_EQ(t.names()[0], "force_gf");
  EXPECT_NEAR(t.column("force_gf")[0], 2.0, 1e-14);
  EXPECT_NEAR(t.column("indentation_mm")[0], 3.0, 1e-14);
}

TEST(Csv, ReportsLineAndColumnOfNonNumericValue) {
  test::ScratchDir dir;
  const auto p = dir.write("bad.csv", "time_s,force_N\n0,1\n# note\n0.1,abc\n");
  EXPECT_TRUE(test::throws_error([&] { read_csv(p); }, ErrorKind::Input,
                                 {"bad.csv:4:2", "column 'force_N'", "'abc' is not a number"}));
}

TEST(Csv, RejectsNanAndInfinityNamingThePlace) {
  test::ScratchDir dir;
  for (const std::string v : {"nan", "NaN", "inf", "-Infinity", "1e999"}) {
    const auto p = dir.write("nan.csv", "time_s,force_N\n0,1\n" + v + ",2\n");
    EXPECT_TRUE(test::throws_error([&] { read_csv(p); }, ErrorKind::Input,
                                   {"nan.csv:3:1", "column 'time_s'", "is not a finite number"}))
        << v;
  }
  const auto p = dir.write("empty_field.csv", "time_s,force_N\n0,\n");
  EXPECT_TRUE(test::throws_error([&] { read_csv(p); }, ErrorKind::Input,
                                 {"empty_field.csv:2:2", "column 'force_N'", "empty value"}));
}

// A value that is finite as written but not in SI (1e300 GPa is 1e309 Pa) is
// refused at its line and column, not carried on as infinity.
TEST(Csv, RefusesAValueBeyondRangeInSi) {
  test::ScratchDir dir;
  const auto p = dir.write("far.csv", "time_s,pressure_GPa\n0,1\n1,1e300\n");
  const CsvTable raw = read_csv(p);
  EXPECT_TRUE(test::throws_error([&] { (void)csv_to_si(raw); }, ErrorKind::Input,
                                 {"far.csv:3:2", "column 'pressure_GPa'", "1e+300 GPa is beyond the range of a number in Pa"}));
}

// A NUL byte in a file is shown in the message, which goes on after it.
TEST(Csv, ANulByteIsShownInTheMessage) {
  test::ScratchDir dir;
  const auto p = dir.write("nul.csv", std::string("time_s,force_N\n0,1\n0.1,2\0" "3\n", 27));
  EXPECT_TRUE(test::throws_error([&] { read_csv(p); }, ErrorKind::Input,
                                 {"nul.csv:3:2", "column 'force_N'", "\\x00", "(expected a finite number)"}));
}

TEST(Csv, EmptyFileIsAnError) {
  test::ScratchDir dir;
  const auto p = dir.write("empty.csv", "");
  EXPECT_TRUE(test::throws_error([&] { read_csv(p); }, ErrorKind::Input, {"empty.csv", "empty"}));
  const auto q = dir.write("comments.csv", "# only a comment\n\n");
  EXPECT_TRUE(
      test::throws_error([&] { read_csv(q); }, ErrorKind::Input, {"comments.csv", "no header"}));
}

TEST(Csv, MissingFileIsAnError) {
  test::ScratchDir dir;
  EXPECT_TRUE(test::throws_error([&] { read_csv(dir / "nope.csv"); }, ErrorKind::Input,
                                 {"nope.csv", "file not found"}));
}

TEST(Csv, MissingHeaderIsAnError) {
  test::ScratchDir dir;
  const auto p = dir.write("nohead.csv", "# comment\n0,1\n2,3\n");
  EXPECT_TRUE(test::throws_error([&] { read_csv(p); }, ErrorKind::Input,
                                 {"nohead.csv:2", "missing header", "indentation_mm,force_N"}));
}

TEST(Csv, DuplicateAndEmptyColumnNamesAreErrors) {
  test::ScratchDir dir;
  const auto p = dir.write("dup.csv", "time_s,force_N,time_s\n0,1,2\n");
  EXPECT_TRUE(test::throws_error([&] { read_csv(p); }, ErrorKind::Input,
                                 {"dup.csv:1:3", "column 'time_s'", "duplicate", "column 1"}));
  const auto q = dir.write("blank.csv", "time_s,,force_N\n0,1,2\n");
  EXPECT_TRUE(
      test::throws_error([&] { read_csv(q); }, ErrorKind::Input, {"blank.csv:1:2", "empty name"}));
  const auto r = dir.write("semi.csv", "time_s;force_N\n0;1\n");
  EXPECT_TRUE(test::throws_error([&] { read_csv(r); }, ErrorKind::Input, {"semi.csv:1:1", "';'"}));
}

TEST(Csv, WrongFieldCountNamesTheLine) {
  test::ScratchDir dir;
  const auto p = dir.write("count.csv", "time_s,force_N\n0,1\n0.1,2,3\n");
  EXPECT_TRUE(test::throws_error(
      [&] { read_csv(p); }, ErrorKind::Input,
      {"count.csv:3", "row has 3 fields but the header has 2 columns (time_s, force_N)"}));
}

TEST(Csv, HeaderWithoutRowsIsAnError) {
  test::ScratchDir dir;
  const auto p = dir.write("head.csv", "time_s,force_N\n\n");
  EXPECT_TRUE(test::throws_error([&] { read_csv(p); }, ErrorKind::Input,
                                 {"head.csv:1", "not followed by any data row"}));
}

TEST(Csv, MissingColumnListsTheColumnsPresent) {
  test::ScratchDir dir;
  const auto p = dir.write("cols.csv", "time_s,depth_mm\n0,1\n");
  const CsvTable t = read_csv(p);
  EXPECT_TRUE(
      test::throws_error([&] { t.quantity("force", Dimension::Force); }, ErrorKind::Input,
                         {"cols.csv:1", "no column for force", "time_s, depth_mm", "force_N"}));
  EXPECT_TRUE(test::throws_error([&] { t.column("trial"); }, ErrorKind::Input,
                                 {"cols.csv:1", "no column 'trial'", "time_s, depth_mm"}));
  const auto q = dir.write("nounit.csv", "force\n1\n");
  EXPECT_TRUE(test::throws_error([&] { read_csv(q).quantity("force", Dimension::Force); },
                                 ErrorKind::Input, {"nounit.csv:1", "'force' has no unit"}));
}

TEST(Csv, UnknownUnitSuffixIsAnError) {
  test::ScratchDir dir;
  const auto p = dir.write("unit.csv", "time_s,indentation_furlong\n0,1\n");
  const CsvTable t = read_csv(p);
  EXPECT_TRUE(test::throws_error(
      [&] { t.quantity("indentation", Dimension::Length); }, ErrorKind::Input,
      {"unit.csv:1:2", "column 'indentation_furlong'", "unknown unit 'furlong'", "mm"}));
  const auto q = dir.write("case.csv", "pressure_KPA\n1\n");
  EXPECT_TRUE(test::throws_error([&] { read_csv(q).quantity("pressure", Dimension::Pressure); },
                                 ErrorKind::Input, {"case.csv:1:1", "did you mean 'kPa'"}));
}

TEST(Csv, UnitOfTheWrongKindIsAnError) {
  test::ScratchDir dir;
  const auto p = dir.write("kind.csv", "indentation_mm,force_kg\n0,1\n");
  const CsvTable t = read_csv(p);
  EXPECT_TRUE(test::throws_error(
      [&] { t.quantity("force", Dimension::Force); }, ErrorKind::Input,
      {"kind.csv:1:2", "column 'force_kg'", "'kg' is a mass unit, not a force unit"}));
}

TEST(Csv, TwoColumnsForOneQuantityAreAnError) {
  test::ScratchDir dir;
  const auto p = dir.write("two.csv", "force_N,force_gf\n1,2\n");
  EXPECT_TRUE(test::throws_error([&] { read_csv(p).quantity("force", Dimension::Force); },
                                 ErrorKind::Input, {"two.csv:1:2", "'force_N' and 'force_gf'"}));
}

TEST(Csv, ToSiRenamesAndConvertsEveryQuantityColumn) {
  test::ScratchDir dir;
  const auto p = dir.write("raw.csv",
                           "# site forearm\ntrial,time_ms,indentation_mm,force_gf,pressure_kPa\n"
                           "1,250,0.5,10,2\n");
  const CsvTable si = csv_to_si(read_csv(p));
  const std::vector<std::string> names = {"trial", "time_s", "indentation_m", "force_N",
                                          "pressure_Pa"};
  EXPECT_EQ(si.names(), names);
  EXPECT_EQ(si.column("trial")[0], 1.0);
  EXPECT_DOUBLE_EQ(si.column("time_s")[0], 0.25);
  EXPECT_DOUBLE_EQ(si.column("indentation_m")[0], 0.5e-3);
  EXPECT_NEAR(si.column("force_N")[0], 10 * kGramForce, 1e-15);
  EXPECT_DOUBLE_EQ(si.column("pressure_Pa")[0], 2000.0);
  EXPECT_EQ(si.comments().at(0), "site forearm");
  EXPECT_EQ(si.line_of_row(0), 3u);
}

TEST(Csv, ToSiRejectsUnknownAndWrongKindUnits) {
  test::ScratchDir dir;
  const auto p = dir.write("u.csv", "time_s,force_furlong\n0,1\n");
  EXPECT_TRUE(
      test::throws_error([&] { csv_to_si(read_csv(p)); }, ErrorKind::Input,
                         {"u.csv:1:2", "column 'force_furlong'", "unknown unit 'furlong'"}));
  const auto q = dir.write("k.csv", "time_s,force_kg\n0,1\n");
  EXPECT_TRUE(test::throws_error(
      [&] { csv_to_si(read_csv(q)); }, ErrorKind::Input,
      {"k.csv:1:2", "column 'force_kg'", "'kg' is a mass unit", "force is a force", "kgf"}));
  const auto r = dir.write("c.csv", "depth_mm,depth_cm\n0,1\n");
  EXPECT_TRUE(test::throws_error([&] { csv_to_si(read_csv(r)); }, ErrorKind::Input,
                                 {"c.csv:1:2", "depth_m"}));
}

TEST(Csv, WriterRefusesNanAndLeavesNoFile) {
  test::ScratchDir dir;
  CsvTable t;
  t.add_column("force_N", {1.0, std::nan("")});
  EXPECT_TRUE(test::throws_error([&] { write_csv(dir / "out.csv", t); }, ErrorKind::Internal,
                                 {"out.csv", "column 'force_N'", "row 2"}));
  EXPECT_EQ(dir.entry_count(), 0u);
}

TEST(Csv, SplitsQuantityNamesAtTheLastUnderscore) {
  const QuantityName q = split_quantity_name("punch_radius_mm");
  EXPECT_EQ(q.base, "punch_radius");
  EXPECT_EQ(q.suffix, "mm");
  ASSERT_NE(q.unit, nullptr);
  EXPECT_EQ(q.unit->to_si, 1e-3);
  EXPECT_EQ(split_quantity_name("trial").unit, nullptr);
  EXPECT_EQ(split_quantity_name("sample_id").unit, nullptr);
  EXPECT_EQ(expected_dimension_of("punch_radius"), Dimension::Length);
  EXPECT_EQ(expected_dimension_of("force"), Dimension::Force);
  EXPECT_FALSE(expected_dimension_of("trial").has_value());
}

}  // namespace
}  // namespace palpa
