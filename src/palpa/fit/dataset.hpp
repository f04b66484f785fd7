// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Measurement datasets for material fitting (`palpa fit`, thesis ch. 6).
//
// A dataset file (JSON) names the sample, the test geometry, the layer depth (a
// value, or guesses to search) and the measured curves:
//
// {
//   "palpa_dataset": 1,
//   "sample": "foam, 10x10x1 cm",
//   "test": "indentation",             // "indentation" | "compression" | "homogeneous"
//   "layer_depth": "10 mm",            // or {"from": "3 mm", "to": "9 mm", "count": 7}
//                                      //    or ["4 mm", "5 mm", "6 mm"]
//   "lateral_size": "100 mm",          // optional: width of the sample block
//   "contact": "frictionless",         // indentation: "stick" | "frictionless";
//                                      // compression: "bonded" | "frictionless"
//   "poisson": 0.45,                   // optional: ν of the Young's-modulus stage
//   "curves": [
//     {"file": "r5.06mm.csv", "radius": "5.06 mm", "role": "train"},
//     {"file": "r1.03mm.csv", "radius": "1.03 mm", "role": "validate"}
//   ]
// }
//
// Compression (a cylinder between two plates): "sample_radius", "sample_height"
// instead of "layer_depth"/"lateral_size", curves without "radius". Homogeneous
// stress–stretch curves: each curve has "load_case" ("uniaxial", "equibiaxial",
// "shear"); no geometry.
//
// Curve files are CSV (io/csv.hpp). Indentation and compression: columns
// `indentation_<length unit>` and `force_<force unit>` (the platen travel of a
// compression test is its indentation). Homogeneous: `stretch` (or `shear` for
// simple shear, γ) and `stress_<pressure unit>`, the nominal (first
// Piola–Kirchhoff) stress, negative in compression. Relative paths resolve
// against the dataset file's folder.
//
// Checks (each error names the file and field or line): the format tag, unknown
// members, units, at least 3 points per curve, strictly increasing indentation
// starting at or above 0, no force below −2% of the curve's largest force (a
// sign error, not noise), a punch radius below half the lateral size and below
// the outer radius the layer model uses, at least one training curve.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "palpa/axisym/poke.hpp"
#include "palpa/material/homogeneous.hpp"

namespace palpa::fit {

enum class TestKind { Indentation, Compression, Homogeneous };
std::string_view to_string(TestKind t) noexcept;

enum class CurveRole { Train, Validate };
std::string_view to_string(CurveRole r) noexcept;

struct MeasuredCurve {
  std::filesystem::path file;      // as resolved
  std::string name;                // file name without extension ("r5.06mm")
  CurveRole role = CurveRole::Train;
  double radius = 0.0;             // punch radius a [m] (indentation)
  material::LoadCase load_case = material::LoadCase::Uniaxial;  // homogeneous
  std::vector<double> x;           // indentation [m], or stretch / shear γ
  std::vector<double> y;           // force [N], or nominal stress [Pa]
};

struct Dataset {
  std::filesystem::path file;
  std::string sample;
  TestKind test = TestKind::Indentation;
  // Candidate layer depths D [m]: one value when the depth is known, several
  // (increasing) when it is searched. Compression: the sample height.
  // Homogeneous: {0} (no geometry; one fit).
  std::vector<double> layer_depths;
  std::optional<double> lateral_size;  // [m]
  double sample_radius = 0.0;          // compression [m]
  axisym::PunchContact contact = axisym::PunchContact::Stick;
  double poisson = 0.45;
  std::vector<MeasuredCurve> curves;

  bool depth_search() const noexcept { return layer_depths.size() > 1; }
  std::size_t count(CurveRole r) const noexcept;
};

// Reads and checks a dataset; throws palpa::Error (Input) naming the file and
// field (or the curve file and line) for every problem listed above.
Dataset read_dataset(const std::filesystem::path& path);

}  // namespace palpa::fit
