// SPDX-License-Identifier: AGPL-3.0-or-later
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "palpa/core/units.hpp"

namespace palpa {
namespace {

const ErrorContext kWhere{"", 0, 0, "option --depth"};

TEST(Units, ParsesTheDocumentedForms) {
  EXPECT_DOUBLE_EQ(parse_quantity("2 mm", Dimension::Length, kWhere), 2e-3);
  EXPECT_DOUBLE_EQ(parse_quantity("10kPa", Dimension::Pressure, kWhere), 1e4);
  EXPECT_DOUBLE_EQ(parse_quantity("3.01e-3 m", Dimension::Length, kWhere), 3.01e-3);
  EXPECT_DOUBLE_EQ(parse_quantity("5 N", Dimension::Force, kWhere), 5.0);
  EXPECT_DOUBLE_EQ(parse_quantity("  +1.5 cm ", Dimension::Length, kWhere), 1.5e-2);
  EXPECT_DOUBLE_EQ(parse_quantity("-2 mm", Dimension::Length, kWhere), -2e-3);
  EXPECT_DOUBLE_EQ(parse_quantity("1e3mm", Dimension::Length, kWhere), 1.0);
  EXPECT_DOUBLE_EQ(parse_quantity("0.45", Dimension::Dimensionless, kWhere), 0.45);
  EXPECT_DOUBLE_EQ(parse_quantity("45%", Dimension::Dimensionless, kWhere), 0.45);
  EXPECT_NEAR(parse_quantity("100 gf", Dimension::Force, kWhere), 0.980665, 1e-12);
  EXPECT_NEAR(parse_quantity("90 deg", Dimension::Angle, kWhere), 1.5707963267948966, 1e-15);
  EXPECT_NEAR(parse_quantity("750 mmHg", Dimension::Pressure, kWhere), 99991.79, 0.01);
  EXPECT_DOUBLE_EQ(parse_quantity("1 g/cm^3", Dimension::Density, kWhere), 1000.0);
  EXPECT_DOUBLE_EQ(parse_quantity("2 N/mm", Dimension::Stiffness, kWhere), 2000.0);
}

TEST(Units, NumberWithoutUnitIsAnError) {
  EXPECT_TRUE(test::throws_error([] { parse_quantity("2", Dimension::Length, kWhere); },
                                 ErrorKind::Input, {"option --depth", "'2' has no unit", "2 mm"}));
}

TEST(Units, UnknownUnitIsAnErrorWithAHint) {
  EXPECT_TRUE(test::throws_error([] { parse_quantity("10 furlongs", Dimension::Length, kWhere); },
                                 ErrorKind::Input, {"unknown unit 'furlongs'"}));
  EXPECT_TRUE(test::throws_error([] { parse_quantity("10 KPA", Dimension::Pressure, kWhere); },
                                 ErrorKind::Input, {"did you mean 'kPa'"}));
}

// A unit alone (a mesh file's "unit": "mm"): a quantity is not a unit.
TEST(Units, AUnitAloneIsParsedByItsSymbol) {
  EXPECT_DOUBLE_EQ(parse_unit("mm", Dimension::Length, kWhere), 1e-3);
  EXPECT_DOUBLE_EQ(parse_unit(" kPa ", Dimension::Pressure, kWhere), 1e3);
  EXPECT_TRUE(test::throws_error([] { parse_unit("0 mm", Dimension::Length, kWhere); }, ErrorKind::Input,
                                 {"'0 mm' is not a unit", "a length unit such as m"}));
  EXPECT_TRUE(test::throws_error([] { parse_unit("MM", Dimension::Length, kWhere); }, ErrorKind::Input,
                                 {"'MM' is not a unit; did you mean 'mm'?"}));
  EXPECT_TRUE(test::throws_error([] { parse_unit("kPa", Dimension::Length, kWhere); }, ErrorKind::Input,
                                 {"'kPa' is a unit of pressure, not of length"}));
}

TEST(Units, UnitOfTheWrongKindIsAnError) {
  EXPECT_TRUE(test::throws_error([] { parse_quantity("5 kg", Dimension::Length, kWhere); },
                                 ErrorKind::Input, {"'5 kg' is a mass, not a length"}));
  EXPECT_TRUE(test::throws_error([] { parse_quantity("5 mm", Dimension::Dimensionless, kWhere); },
                                 ErrorKind::Input, {"length"}));
}

TEST(Units, NonNumbersAndNonFiniteValuesAreErrors) {
  for (const char* bad : {"", "   ", "mm", "abc mm", "nan mm", "inf Pa", "1e999 Pa", "--2 mm"}) {
    EXPECT_TRUE(test::throws_error([&] { parse_quantity(bad, Dimension::Length, kWhere); },
                                   ErrorKind::Input, {"option --depth"}))
        << "input '" << bad << "'";
  }
}

TEST(Units, FormatPicksAReadableUnit) {
  EXPECT_EQ(format_quantity(12000.0, Dimension::Pressure), "12 kPa");
  EXPECT_EQ(format_quantity(0.00301, Dimension::Length), "3.01 mm");
  EXPECT_EQ(format_quantity(2.5, Dimension::Force), "2.5 N");
  EXPECT_EQ(format_quantity(0.0, Dimension::Length), "0 m");
  EXPECT_EQ(format_quantity(0.45, Dimension::Dimensionless), "0.45");
}

TEST(Units, RoundTripThroughEveryUnit) {
  for (const Unit& u : known_units()) {
    const double si = 3.25 * u.to_si;
    const std::string text = "3.25 " + std::string(u.symbol);
    EXPECT_NEAR(parse_quantity(text, u.dimension, kWhere), si, 1e-12 * std::abs(si)) << text;
    EXPECT_NEAR(si_to_unit(si, u.symbol, u.dimension), 3.25, 1e-12) << text;
  }
}

}  // namespace
}  // namespace palpa
