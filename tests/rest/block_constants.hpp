// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The resting block of the rest tests: 40 × 40 × 20 mm of density 1000 kg/m³
// under standard gravity.

namespace palpa::rest::test {

inline constexpr double kRho = 1000.0;  // kg/m³
inline constexpr double kG = 9.81;      // m/s²
inline constexpr double kH = 0.02;      // block height [m]
inline constexpr double kW = 0.04;      // block width [m]

}  // namespace palpa::rest::test
