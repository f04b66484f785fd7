// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/material/checks.hpp"

#include <fmt/format.h>

#include <cmath>

#include "palpa/core/error.hpp"
#include "palpa/material/homogeneous.hpp"

namespace palpa::material {

MaterialCheck check_material(const Material& m, double lo, double hi) {
  MaterialCheck c;
  c.rest_stress = m.dpsi_dlambda(Vec3::Ones()).cwiseAbs().maxCoeff();
  c.small_strain = small_strain_constants(m);
  const double mu = c.small_strain.mu;
  if (!(mu > 0.0)) {
    c.problems.push_back(fmt::format("shear modulus at rest is {:.4g} Pa (must be > 0)", mu));
  }
  if (!(c.small_strain.bulk() > 0.0)) {
    c.problems.push_back(
        fmt::format("bulk modulus at rest is {:.4g} Pa (must be > 0)", c.small_strain.bulk()));
  }
  if (c.rest_stress > 1e-8 * std::max(std::abs(mu), 1.0)) {
    c.problems.push_back(fmt::format("rest state is not stress-free (|dPsi/dlambda| = {:.4g} Pa)",
                                     c.rest_stress));
  }
  if (!c.problems.empty()) return c;

  constexpr int kPoints = 61;
  const auto check_path = [&](LoadCase lc, double from, double to, const char* name) {
    try {
      const auto curve = homogeneous_curve(m, lc, from, to, kPoints);
      for (std::size_t i = 1; i < curve.size(); ++i) {
        if (!(curve[i].nominal > curve[i - 1].nominal)) {
          c.problems.push_back(fmt::format(
              "{}: nominal stress does not increase between {:.4g} and {:.4g} (unstable)", name,
              curve[i - 1].load, curve[i].load));
          return;
        }
      }
    } catch (const Error& e) {
      c.problems.push_back(fmt::format("{}: {}", name, e.what()));
    }
  };
  check_path(LoadCase::Uniaxial, lo, hi, "uniaxial");
  check_path(LoadCase::Equibiaxial, std::max(lo, 1.0 / std::sqrt(hi)), std::min(hi, 1.0 / std::sqrt(lo)),
             "equibiaxial");
  check_path(LoadCase::SimpleShear, -(hi - 1.0), hi - 1.0, "simple shear");
  return c;
}

double uniaxial_compression_limit(const Material& m, double floor) {
  // Down from rest one point at a time, each from its neighbour's lateral
  // stretch; a state that cannot be solved ends the search (what was found
  // before it stands).
  const int count = static_cast<int>(std::lround((1.0 - floor) / 0.005));
  try {
    CurvePoint last = homogeneous_point(m, LoadCase::Uniaxial, 1.0);
    for (int i = 1; i <= count; ++i) {
      const CurvePoint next = homogeneous_point(m, LoadCase::Uniaxial, 1.0 - 0.005 * i, last.lateral);
      if (!(next.nominal < last.nominal)) return last.load;
      last = next;
    }
  } catch (const Error&) {
    // no homogeneous state from here on: nothing more to say
  }
  return 0.0;
}

}  // namespace palpa::material
