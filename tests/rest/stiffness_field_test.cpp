// SPDX-License-Identifier: AGPL-3.0-or-later
// A body that carries a stiffness field: a block whose halves hold the same
// material's shape at two moduli (as two poke locations' fits would), read
// from a layer file's per-tet youngs_modulus_Pa, rests on a flat support
// with its core free to sink and to pitch. At ν = 0 every column of the block
// compresses on its own (no lateral stretch), so the block is a bed of
// independent springs in series with the contact's penalty: the core's sink
// and pitch follow from force and moment balance over that bed, and the
// softer half sinks more. The same block with one modulus does not pitch.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "common/test_support.hpp"
#include "palpa/io/vtu.hpp"
#include "palpa/rest/scene.hpp"
#include "palpa/tet/material_field.hpp"
#include "palpa/tet/mesh.hpp"
#include "rest/block_constants.hpp"

namespace palpa::rest {
namespace {

constexpr double kLength = 0.08;               // along x: the halves x < 0 and x > 0
constexpr double kGap = 5e-4;                  // between the block and the support at the start
constexpr double kSoft = 20e3, kStiff = 60e3;  // [Pa]
constexpr double kCoreForce = 0.3;             // [N], down, at the top face's centre

struct Layer {
  tet::BoxMesh box;
  Eigen::VectorXd young;  // per tet
};

// An 80 × 40 × 20 mm block, its top face the core, its halves at two moduli.
Layer two_region_block(double soft, double stiff) {
  using test::kH;
  using test::kW;
  Layer l;
  l.box = tet::make_box_mesh(Eigen::Vector3d(-kLength / 2, -kW / 2, kGap),
                             Eigen::Vector3d(kLength / 2, kW / 2, kH + kGap),
                             Eigen::Vector3i(16, 8, 4));
  const TetMesh& m = l.box.mesh;
  l.young.resize(m.T.rows());
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
    double x = 0.0;
    for (int a = 0; a < 4; ++a) x += m.V(m.T(t, a), 0) / 4.0;
    l.young[t] = x < 0.0 ? soft : stiff;
  }
  return l;
}

void write_layer(const Layer& l, const std::filesystem::path& file) {
  UnstructuredGrid g;
  g.points = l.box.mesh.V;
  g.cells.push_back(CellBlock{VtkCellType::Tetra, l.box.mesh.T});
  Eigen::VectorXd attached = Eigen::VectorXd::Zero(g.points.rows());
  for (int v : l.box.vertex_sets.at("top")) attached[v] = 1.0;
  g.point_data.push_back(DataArray{"attached", attached});
  g.cell_data.push_back(DataArray{"youngs_modulus_Pa", l.young});
  write_vtu(file, g);
}

std::string scene(const std::string& stiffness) {
  return fmt::format(R"({{
  "palpa_rest": 1,
  "body": {{"layer": "block.vtu", {}
            "material": {{"model": "neo-hookean", "parameters": {{"E": "1 kPa", "nu": 0}}}},
            "density": "1000 kg/m^3", "element": "linear"}},
  "core": {{"free": ["z", "ry"], "force": ["0 N", "0 N", "-{} N"]}},
  "support": {{"box": {{"size": ["200 mm", "200 mm", "20 mm"], "divisions": 40}}}}
}})",
                     stiffness, kCoreForce);
}

struct Bed {
  double sink = 0.0;   // at x = 0 [m]
  double slope = 0.0;  // d(sink)/dx
};

// Force and moment balance over a bed of columns under the block's bottom
// faces: column i of modulus E_i, area A_i at x_i carries
//   p_i = (s(x_i) + ρgH²/(2E_i)) / (H/E_i + 1/k)
// for a sink s(x) = a + b x of the core (its own compression, its weight
// compressing it by half as much as a load on top would, and the contact's
// penetration p/k).
Bed winkler_bed(const TetMesh& mesh, const std::vector<int>& bottom,
                const Eigen::VectorXd& young_per_vertex, double k, double load) {
  using test::kG;
  using test::kH;
  using test::kRho;
  // The bottom face's vertices on a regular grid: each carries a share of the
  // area (a quarter cell per cell it touches).
  const double dx = kLength / 16, dy = test::kW / 8;
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  for (int v : bottom) {
    const double x = mesh.V(v, 0), y = mesh.V(v, 1);
    const bool x_edge = std::abs(std::abs(x) - kLength / 2) < 1e-9,
               y_edge = std::abs(std::abs(y) - test::kW / 2) < 1e-9;
    const double area = dx * dy * (x_edge ? 0.5 : 1.0) * (y_edge ? 0.5 : 1.0);
    const double E = young_per_vertex[v];
    const double c = area / (kH / E + 1.0 / k);
    const double g = kRho * kG * kH * kH / (2.0 * E);
    A += c * Eigen::Matrix2d{{1.0, x}, {x, x * x}};
    rhs -= c * g * Eigen::Vector2d(1.0, x);
  }
  rhs += Eigen::Vector2d(load, 0.0);
  const Eigen::Vector2d ab = A.ldlt().solve(rhs);
  return {ab[0], ab[1]};
}

struct Solved {
  RestResult result;
  Bed bed;       // predicted
  Bed observed;  // from the core's pose
  std::size_t materials = 0;
};

Solved rest_two_region(double soft, double stiff) {
  palpa::test::ScratchDir dir;
  const Layer l = two_region_block(soft, stiff);
  write_layer(l, dir / "block.vtu");
  dir.write("scene.json", scene(R"("stiffness": "layer",)"));
  RestScene s = read_rest_scene(dir / "scene.json");
  RestSimulation sim(std::move(s.body), s.support, s.options);
  Solved out;
  out.materials = sim.model().materials().size();
  out.result = sim.solve();
  const RestResult& r = out.result;
  // Each bottom vertex's modulus: that of its side (on the interface, the mean).
  Eigen::VectorXd Ev(l.box.mesh.V.rows());
  for (Eigen::Index v = 0; v < Ev.size(); ++v) {
    const double x = l.box.mesh.V(v, 0);
    Ev[v] = std::abs(x) < 1e-9 ? 0.5 * (soft + stiff) : (x < 0.0 ? soft : stiff);
  }
  out.bed =
      winkler_bed(l.box.mesh, l.box.vertex_sets.at("bottom"), Ev, r.stiffness, r.contact_force.z());
  // The core's sink at x (down positive) beyond the gap: −(t_z + R_zx x) − gap.
  out.observed = {-r.core_translation.z() - kGap, -r.core_rotation(2, 0)};
  return out;
}

TEST(StiffnessField, TwoRegionBlockSinksAndPitchesAsItsHalvesPredict) {
  const Solved s = rest_two_region(kSoft, kStiff);
  ASSERT_EQ(s.materials, 2u);  // the shape at the two moduli
  const double weight = test::kRho * kLength * test::kW * test::kH * test::kG;
  EXPECT_NEAR(s.result.contact_force.z(), weight + kCoreForce, 5e-3 * (weight + kCoreForce));
  // The soft half (x < 0) sinks more: the core pitches down toward it.
  ASSERT_LT(s.bed.slope, 0.0);
  ASSERT_LT(s.observed.slope, 0.0) << "sink grows toward the soft side (x < 0)";
  EXPECT_NEAR(s.observed.sink, s.bed.sink, 0.02 * s.bed.sink);
  EXPECT_NEAR(s.observed.slope, s.bed.slope, 0.03 * std::abs(s.bed.slope));
}

TEST(StiffnessField, OneModulusDoesNotPitch) {
  const Solved s = rest_two_region(kSoft, kSoft);
  ASSERT_EQ(s.materials, 1u);
  EXPECT_NEAR(s.observed.sink, s.bed.sink, 0.02 * s.bed.sink);
  // The mesh's diagonals alone tilt it: its ends sink within 1% alike
  // (the two-region block's differ by 50%).
  EXPECT_LT(std::abs(s.observed.slope) * kLength / 2, 0.01 * s.observed.sink);
}

}  // namespace
}  // namespace palpa::rest
