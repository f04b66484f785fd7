// SPDX-License-Identifier: AGPL-3.0-or-later
// Benchmark of body meshing (palpa::mesh::make_layer): a generated thigh
// surface of about 50k triangles (at the largest level) meshed into a soft
// layer of about 100k tets, with 60 depth samples and 60 stiffness samples
// (as in the thesis's §7.3.1) interpolated biharmonically. Prints one JSON
// line per figure (see BENCHMARKS.md).
//
// Per level (edge lengths 6, 4.2, 3 mm):
//  - stage: wall seconds of each stage of make_layer (repair, remesh, depth,
//    inner_surface, tetrahedralize, core, stiffness), and the whole;
//  - reference: the TetGen stage itself (the floor any layer mesher built on
//    TetGen pays), and the ratio whole / reference;
//  - accuracy: tets, min dihedral angle, max radius-edge ratio, inverted tets,
//    and the layer volume's relative difference from (outer − core) volume.
// Finally the fitted exponent of the whole time against the tet count.
//
// Options: --quick (the smallest level only).

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "palpa/mesh/bodies.hpp"
#include "palpa/mesh/layer.hpp"
#include "palpa/mesh/surface_check.hpp"
#include "palpa/mesh/tetrahedralize.hpp"

namespace {

using namespace palpa;
using palpa::bench::emit;
using palpa::bench::seconds_since;
using clock_type = std::chrono::steady_clock;

constexpr int kSamples = 60;
constexpr double kDegree = std::numbers::pi / 180.0;

// kSamples points on the thigh's skin (a fixed seed) with values in [lo, hi].
mesh::Samples samples_on(const SurfaceMesh& surface, double lo, double hi, unsigned seed,
                         const std::string& name) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<Eigen::Index> vertex(0, surface.V.rows() - 1);
  std::uniform_real_distribution<double> value(lo, hi);
  mesh::Samples s;
  s.source = name;
  s.positions.resize(kSamples, 3);
  s.values.resize(kSamples);
  for (int i = 0; i < kSamples; ++i) {
    s.positions.row(i) = surface.V.row(vertex(rng));
    s.values(i) = value(rng);
    s.labels.push_back(fmt::format("sample {}", i));
  }
  return s;
}

struct LevelResult {
  double tets = 0.0;
  double seconds = 0.0;
};

LevelResult run_level(double edge) {
  mesh::BodyOptions b;
  b.shape = mesh::BodyShape::Thigh;
  b.edge_length = edge;
  auto t0 = clock_type::now();
  const SurfaceMesh skin = mesh::make_body(b);
  const double body_seconds = seconds_since(t0);

  mesh::DepthSpec depth;
  depth.samples = samples_on(skin, 5e-3, 9e-3, 1, "depths");
  const mesh::Samples stiffness = samples_on(skin, 5e3, 15e3, 2, "moduli");
  mesh::LayerOptions o;
  o.edge_length = edge;
  // No volume bound: the tets grade from the surfaces' size inward.
  o.quality.max_volume = 1.0;
  std::map<std::string, double> stage_seconds;
  std::string current;
  auto stage_start = clock_type::now();
  o.on_stage = [&](std::string_view stage) {
    if (!current.empty()) stage_seconds[current] = seconds_since(stage_start);
    current = stage;
    stage_start = clock_type::now();
  };
  t0 = clock_type::now();
  const mesh::LayerMesh layer = mesh::make_layer(skin, depth, stiffness, o);
  const double whole = seconds_since(t0);
  stage_seconds[current] = seconds_since(stage_start);

  // The reference: the TetGen call itself (hole points included), the floor
  // any layer mesher built on TetGen pays.
  const double reference_seconds = stage_seconds.at("tetrahedralize");
  const mesh::LayerSummary s = mesh::summarize_layer(layer, layer.quality);
  nlohmann::json stages = nlohmann::json::object();
  for (const auto& [name, sec] : stage_seconds) stages[name] = sec;
  emit({{"bench", "mesh_layer"},
        {"edge_mm", edge * 1e3},
        {"skin_triangles", skin.F.rows()},
        {"outer_triangles", s.outer_triangles},
        {"core_triangles", s.core_triangles},
        {"tets", s.quality.tets},
        {"body_generation_s", body_seconds},
        {"stage_s", stages},
        {"whole_s", whole},
        {"reference_tetgen_s", reference_seconds},
        {"ratio_whole_to_reference", whole / reference_seconds},
        {"min_dihedral_deg", s.quality.min_dihedral / kDegree},
        {"max_radius_edge", s.quality.max_radius_edge},
        {"inverted_tets", s.quality.inverted},
        {"layer_volume_rel_error",
         std::abs(s.layer_volume - (s.outer_volume - s.core_volume)) / s.layer_volume},
        {"thickness_mm", {s.thickness_min * 1e3, s.thickness_mean * 1e3, s.thickness_max * 1e3}}});
  return {double(s.quality.tets), whole};
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  std::vector<double> edges = {6e-3, 4.2e-3, 3e-3};
  if (quick) edges.resize(1);
  std::vector<LevelResult> results;
  for (double e : edges) results.push_back(run_level(e));
  if (results.size() >= 2) {
    // Least-squares slope of log(seconds) against log(tets).
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (const auto& r : results) {
      const double x = std::log(r.tets), y = std::log(r.seconds);
      sx += x;
      sy += y;
      sxx += x * x;
      sxy += x * y;
    }
    const double n = double(results.size());
    emit({{"bench", "mesh_layer_scaling"},
          {"levels", results.size()},
          {"exponent_seconds_vs_tets", (n * sxy - sx * sy) / (n * sxx - sx * sx)}});
  }
  return 0;
}
