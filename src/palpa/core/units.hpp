// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Quantities with units at the edges of palpa. Inside, every value is SI
// (metres, pascals, newtons, seconds, kilograms). Text from users and files
// carries its unit ("2 mm", "10kPa", "3.01e-3 m", "5 N") and is converted here;
// a number without a unit where one is required is an error, never a guess.

#include <span>
#include <string>
#include <string_view>

#include "palpa/core/error.hpp"

namespace palpa {

enum class Dimension {
  Dimensionless,  // ratios, Poisson's ratio, stretches
  Length,         // m
  Area,           // m^2
  Pressure,       // Pa (stress, Young's modulus, contact pressure)
  Force,          // N
  Time,           // s
  Mass,           // kg
  Density,        // kg/m^3
  Frequency,      // Hz
  Voltage,        // V
  Angle,          // rad
  Stiffness,      // N/m (force per length: contact penalty, F/d)
  Torque,         // N m
  Acceleration,   // m/s^2
  Compliance,     // 1/Pa (volumetric compliance D1 of Abaqus-style models)
  PressurePerLength,  // Pa/m (surface contact stiffness: pressure per depth)
};

// "length", "pressure", ... for messages.
std::string_view dimension_name(Dimension d) noexcept;
// The SI unit symbol of a dimension ("m", "Pa", "" for dimensionless).
std::string_view si_unit(Dimension d) noexcept;
// A few accepted spellings, for "expected ..." in messages: "a length such as 2 mm".
std::string dimension_example(Dimension d);

struct Unit {
  std::string_view symbol;
  Dimension dimension;
  double to_si;  // value_si = value * to_si
};

// The unit with exactly this symbol (case-sensitive: "mm" but not "MM"), or
// nullptr.
const Unit* find_unit(std::string_view symbol) noexcept;

// All known units, for help texts.
std::span<const Unit> known_units() noexcept;

// Parses "<number> [unit]" and returns the SI value. The unit must be of the
// expected dimension; for Dimension::Dimensionless a bare number is accepted
// (and "%" divides by 100). Throws palpa::Error (kind Input) naming `where`.
double parse_quantity(std::string_view text, Dimension expected, const ErrorContext& where);

// The SI value of one `symbol` (a unit's symbol alone, "mm"), which must be a
// unit of the expected dimension. Throws palpa::Error (kind Input) naming
// `where` otherwise ("'0 mm' is not a unit").
double parse_unit(std::string_view symbol, Dimension expected, const ErrorContext& where);

// Converts an SI value to `unit` (which must exist and have dimension `d`).
double si_to_unit(double value_si, std::string_view unit, Dimension d);

// A readable rendering of an SI value in a unit suited to its magnitude:
// 12000 Pa -> "12 kPa", 0.00301 m -> "3.01 mm".
std::string format_quantity(double value_si, Dimension d);

}  // namespace palpa
