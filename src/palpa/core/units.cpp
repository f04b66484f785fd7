// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/units.hpp"

#include <fmt/format.h>

#include <array>
#include <charconv>
#include <cmath>

#include "palpa/core/text.hpp"

namespace palpa {

namespace {

constexpr double kGravity = 9.80665;  // standard gravity, for gram-force
constexpr double kPi = 3.14159265358979323846;

// Order within a dimension matters for format_quantity(): the display units are
// the ones flagged in kDisplay below.
constexpr std::array kUnits = {
    Unit{"m", Dimension::Length, 1.0},
    Unit{"cm", Dimension::Length, 1e-2},
    Unit{"mm", Dimension::Length, 1e-3},
    Unit{"um", Dimension::Length, 1e-6},
    Unit{"µm", Dimension::Length, 1e-6},
    Unit{"nm", Dimension::Length, 1e-9},
    Unit{"m^2", Dimension::Area, 1.0},
    Unit{"m2", Dimension::Area, 1.0},
    Unit{"cm^2", Dimension::Area, 1e-4},
    Unit{"cm2", Dimension::Area, 1e-4},
    Unit{"mm^2", Dimension::Area, 1e-6},
    Unit{"mm2", Dimension::Area, 1e-6},
    Unit{"Pa", Dimension::Pressure, 1.0},
    Unit{"hPa", Dimension::Pressure, 1e2},
    Unit{"kPa", Dimension::Pressure, 1e3},
    Unit{"MPa", Dimension::Pressure, 1e6},
    Unit{"GPa", Dimension::Pressure, 1e9},
    Unit{"N/m^2", Dimension::Pressure, 1.0},
    Unit{"N/m2", Dimension::Pressure, 1.0},
    Unit{"N/cm^2", Dimension::Pressure, 1e4},
    Unit{"N/cm2", Dimension::Pressure, 1e4},
    Unit{"N/mm^2", Dimension::Pressure, 1e6},
    Unit{"N/mm2", Dimension::Pressure, 1e6},
    Unit{"mmHg", Dimension::Pressure, 133.322387415},
    Unit{"psi", Dimension::Pressure, 6894.757293168},
    Unit{"bar", Dimension::Pressure, 1e5},
    Unit{"mbar", Dimension::Pressure, 1e2},
    Unit{"N", Dimension::Force, 1.0},
    Unit{"mN", Dimension::Force, 1e-3},
    Unit{"kN", Dimension::Force, 1e3},
    Unit{"gf", Dimension::Force, 1e-3 * kGravity},
    Unit{"kgf", Dimension::Force, kGravity},
    Unit{"lbf", Dimension::Force, 4.4482216152605},
    Unit{"s", Dimension::Time, 1.0},
    Unit{"ms", Dimension::Time, 1e-3},
    Unit{"us", Dimension::Time, 1e-6},
    Unit{"µs", Dimension::Time, 1e-6},
    Unit{"min", Dimension::Time, 60.0},
    Unit{"h", Dimension::Time, 3600.0},
    Unit{"kg", Dimension::Mass, 1.0},
    Unit{"g", Dimension::Mass, 1e-3},
    Unit{"mg", Dimension::Mass, 1e-6},
    Unit{"kg/m^3", Dimension::Density, 1.0},
    Unit{"kg/m3", Dimension::Density, 1.0},
    Unit{"g/cm^3", Dimension::Density, 1e3},
    Unit{"g/cm3", Dimension::Density, 1e3},
    Unit{"Hz", Dimension::Frequency, 1.0},
    Unit{"kHz", Dimension::Frequency, 1e3},
    Unit{"V", Dimension::Voltage, 1.0},
    Unit{"mV", Dimension::Voltage, 1e-3},
    Unit{"rad", Dimension::Angle, 1.0},
    Unit{"deg", Dimension::Angle, kPi / 180.0},
    Unit{"°", Dimension::Angle, kPi / 180.0},
    Unit{"N/m", Dimension::Stiffness, 1.0},
    Unit{"N/mm", Dimension::Stiffness, 1e3},
    Unit{"kN/m", Dimension::Stiffness, 1e3},
    Unit{"N*m", Dimension::Torque, 1.0},
    Unit{"N.m", Dimension::Torque, 1.0},
    Unit{"Nm", Dimension::Torque, 1.0},
    Unit{"N*mm", Dimension::Torque, 1e-3},
    Unit{"Nmm", Dimension::Torque, 1e-3},
    Unit{"m/s^2", Dimension::Acceleration, 1.0},
    Unit{"m/s2", Dimension::Acceleration, 1.0},
    Unit{"1/Pa", Dimension::Compliance, 1.0},
    Unit{"1/kPa", Dimension::Compliance, 1e-3},
    Unit{"1/MPa", Dimension::Compliance, 1e-6},
    Unit{"1/GPa", Dimension::Compliance, 1e-9},
    Unit{"Pa/m", Dimension::PressurePerLength, 1.0},
    Unit{"kPa/mm", Dimension::PressurePerLength, 1e6},
    Unit{"MPa/m", Dimension::PressurePerLength, 1e6},
    Unit{"GPa/m", Dimension::PressurePerLength, 1e9},
};

struct DisplayUnits {
  Dimension dimension;
  std::array<std::string_view, 4> symbols;  // largest first; empty = unused
};

constexpr std::array kDisplay = {
    DisplayUnits{Dimension::Length, {"m", "mm", "um", ""}},
    DisplayUnits{Dimension::Area, {"m^2", "mm^2", "", ""}},
    DisplayUnits{Dimension::Pressure, {"GPa", "MPa", "kPa", "Pa"}},
    DisplayUnits{Dimension::Force, {"kN", "N", "mN", ""}},
    DisplayUnits{Dimension::Time, {"s", "ms", "us", ""}},
    DisplayUnits{Dimension::Mass, {"kg", "g", "mg", ""}},
    DisplayUnits{Dimension::Density, {"kg/m^3", "", "", ""}},
    DisplayUnits{Dimension::Frequency, {"kHz", "Hz", "", ""}},
    DisplayUnits{Dimension::Voltage, {"V", "mV", "", ""}},
    DisplayUnits{Dimension::Angle, {"rad", "", "", ""}},
    DisplayUnits{Dimension::Stiffness, {"kN/m", "N/m", "", ""}},
    DisplayUnits{Dimension::Torque, {"N*m", "N*mm", "", ""}},
    DisplayUnits{Dimension::Acceleration, {"m/s^2", "", "", ""}},
    DisplayUnits{Dimension::Compliance, {"1/Pa", "1/kPa", "1/MPa", ""}},
    DisplayUnits{Dimension::PressurePerLength, {"GPa/m", "MPa/m", "Pa/m", ""}},
};

}  // namespace

std::string_view dimension_name(Dimension d) noexcept {
  switch (d) {
    case Dimension::Dimensionless: return "dimensionless number";
    case Dimension::Length: return "length";
    case Dimension::Area: return "area";
    case Dimension::Pressure: return "pressure";
    case Dimension::Force: return "force";
    case Dimension::Time: return "time";
    case Dimension::Mass: return "mass";
    case Dimension::Density: return "density";
    case Dimension::Frequency: return "frequency";
    case Dimension::Voltage: return "voltage";
    case Dimension::Angle: return "angle";
    case Dimension::Stiffness: return "stiffness (force per length)";
    case Dimension::Torque: return "torque";
    case Dimension::Acceleration: return "acceleration";
    case Dimension::Compliance: return "compliance (inverse pressure)";
    case Dimension::PressurePerLength: return "pressure per length";
  }
  return "quantity";
}

std::string_view si_unit(Dimension d) noexcept {
  switch (d) {
    case Dimension::Dimensionless: return "";
    case Dimension::Length: return "m";
    case Dimension::Area: return "m^2";
    case Dimension::Pressure: return "Pa";
    case Dimension::Force: return "N";
    case Dimension::Time: return "s";
    case Dimension::Mass: return "kg";
    case Dimension::Density: return "kg/m^3";
    case Dimension::Frequency: return "Hz";
    case Dimension::Voltage: return "V";
    case Dimension::Angle: return "rad";
    case Dimension::Stiffness: return "N/m";
    case Dimension::Torque: return "N*m";
    case Dimension::Acceleration: return "m/s^2";
    case Dimension::Compliance: return "1/Pa";
    case Dimension::PressurePerLength: return "Pa/m";
  }
  return "";
}

std::string dimension_example(Dimension d) {
  switch (d) {
    case Dimension::Dimensionless: return "a plain number such as 0.45";
    case Dimension::Length: return "a length with its unit, such as 2 mm or 0.002 m";
    case Dimension::Area: return "an area with its unit, such as 1 cm^2";
    case Dimension::Pressure: return "a pressure with its unit, such as 12 kPa or 1.2e4 Pa";
    case Dimension::Force: return "a force with its unit, such as 5 N or 200 mN";
    case Dimension::Time: return "a time with its unit, such as 2 s or 10 ms";
    case Dimension::Mass: return "a mass with its unit, such as 70 kg";
    case Dimension::Density: return "a density with its unit, such as 1000 kg/m^3";
    case Dimension::Frequency: return "a frequency with its unit, such as 10 Hz";
    case Dimension::Voltage: return "a voltage with its unit, such as 2.5 V";
    case Dimension::Angle: return "an angle with its unit, such as 15 deg or 0.26 rad";
    case Dimension::Stiffness: return "a stiffness with its unit, such as 300 N/m";
    case Dimension::Torque: return "a torque with its unit, such as 2 N*m";
    case Dimension::Acceleration: return "an acceleration with its unit, such as 9.81 m/s^2";
    case Dimension::Compliance: return "a compliance with its unit, such as 2e-6 1/Pa or 0.002 1/kPa";
    case Dimension::PressurePerLength: return "a pressure per depth with its unit, such as 50 MPa/m or 50 kPa/mm";
  }
  return "a quantity with its unit";
}

const Unit* find_unit(std::string_view symbol) noexcept {
  for (const Unit& u : kUnits) {
    if (u.symbol == symbol) return &u;
  }
  return nullptr;
}

std::span<const Unit> known_units() noexcept { return kUnits; }

namespace {

// For a symbol that is no unit: a case slip ("KPA", "Mm") is the usual cause,
// so name the unit of `expected` it was meant to be ("; did you mean 'kPa'?"),
// or nothing.
std::string case_slip_hint(std::string_view symbol, Dimension expected) {
  for (const Unit& u : kUnits) {
    if (u.dimension == expected && to_lower(u.symbol) == to_lower(symbol)) {
      return fmt::format("; did you mean '{}'?", u.symbol);
    }
  }
  return {};
}

}  // namespace

double parse_unit(std::string_view symbol, Dimension expected, const ErrorContext& where) {
  const Unit* unit = find_unit(trim(symbol));
  const std::string expect = fmt::format("a {} unit such as {}", dimension_name(expected), si_unit(expected));
  if (unit == nullptr) {
    throw_input_error(fmt::format("'{}' is not a unit{}", symbol, case_slip_hint(trim(symbol), expected)), where,
                      expect);
  }
  if (unit->dimension != expected) {
    throw_input_error(fmt::format("'{}' is a unit of {}, not of {}", symbol, dimension_name(unit->dimension),
                                  dimension_name(expected)),
                      where, expect);
  }
  return unit->to_si;
}

double parse_quantity(std::string_view text, Dimension expected, const ErrorContext& where) {
  const std::string_view s = trim(text);
  const std::string shown(text);
  if (s.empty()) {
    throw_input_error("empty value", where, dimension_example(expected));
  }
  // The number is the longest prefix from_chars accepts; a leading '+' is allowed.
  std::string_view num = s;
  if (num.front() == '+') num.remove_prefix(1);
  double value = 0.0;
  const auto [ptr, ec] =
      std::from_chars(num.data(), num.data() + num.size(), value, std::chars_format::general);
  if (ec != std::errc() || ptr == num.data()) {
    throw_input_error(fmt::format("'{}' does not start with a number", shown), where,
                      dimension_example(expected));
  }
  if (!std::isfinite(value)) {
    throw_input_error(fmt::format("'{}' is not a finite number", shown), where,
                      dimension_example(expected));
  }
  const std::string_view unit_text = trim(std::string_view(ptr, num.data() + num.size() - ptr));

  if (unit_text.empty()) {
    if (expected == Dimension::Dimensionless) return value;
    throw_input_error(fmt::format("'{}' has no unit", shown), where, dimension_example(expected));
  }
  if (expected == Dimension::Dimensionless && unit_text == "%") return value / 100.0;

  const Unit* unit = find_unit(unit_text);
  if (unit == nullptr) {
    throw_input_error(fmt::format("unknown unit '{}' in '{}'{}", unit_text, shown, case_slip_hint(unit_text, expected)),
                      where, dimension_example(expected));
  }
  if (unit->dimension != expected) {
    throw_input_error(fmt::format("'{}' is a {}, not a {}", shown, dimension_name(unit->dimension),
                                  dimension_name(expected)),
                      where, dimension_example(expected));
  }
  return value * unit->to_si;
}

double si_to_unit(double value_si, std::string_view unit, Dimension d) {
  const Unit* u = find_unit(unit);
  if (u == nullptr || u->dimension != d) {
    throw Error(ErrorKind::Internal,
                fmt::format("unit '{}' is not a unit of {}", unit, dimension_name(d)));
  }
  return value_si / u->to_si;
}

std::string format_quantity(double value_si, Dimension d) {
  if (d == Dimension::Dimensionless) return fmt::format("{:.6g}", value_si);
  const auto factor = [](std::string_view sym) {
    const Unit* u = find_unit(sym);
    return u != nullptr ? u->to_si : 1.0;
  };
  for (const DisplayUnits& display : kDisplay) {
    if (display.dimension != d) continue;
    std::string_view chosen;
    for (std::string_view sym : display.symbols) {
      if (sym.empty()) break;
      chosen = sym;
      if (std::abs(value_si) >= factor(sym)) break;
    }
    if (value_si == 0.0) chosen = si_unit(d);
    return fmt::format("{:.6g} {}", value_si / factor(chosen), chosen);
  }
  return fmt::format("{:.6g} {}", value_si, si_unit(d));
}

}  // namespace palpa
