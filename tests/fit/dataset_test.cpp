// SPDX-License-Identifier: AGPL-3.0-or-later
// Dataset files: every test kind read with units converted and paths resolved
// against the dataset's folder; every bad dataset refused naming the file and
// field.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <tuple>

#include <filesystem>

#include "common/test_support.hpp"
#include "fit/bad_datasets.hpp"
#include "palpa/fit/dataset.hpp"

namespace palpa::fit {
namespace {

using palpa::test::ScratchDir;
using palpa::test::throws_error;

constexpr double kTight = 1e-15;  // relative: unit conversion is one multiplication

void expect_close(double actual, double expected, const char* what) {
  EXPECT_NEAR(actual, expected, kTight * std::abs(expected)) << what;
}

TEST(Dataset, IndentationWithOneDepthConvertsUnitsAndResolvesPaths) {
  ScratchDir dir;
  std::filesystem::create_directories(dir / "data" / "sub");
  dir.write("data/a3.csv", "# punch 3 mm\nindentation_mm,force_gf\n0,0\n0.5,10\n1.0,25\n1.5,45\n");
  dir.write("data/sub/a2.csv", "indentation_um,force_N\n100,0.002\n200,0.005\n300,0.009\n");
  const auto file = dir.write("data/dataset.json", R"({
    "palpa_dataset": 1, "sample": "phantom", "test": "indentation",
    "layer_depth": "1 cm", "lateral_size": "100 mm", "contact": "frictionless", "poisson": 0.4,
    "curves": [{"file": "a3.csv", "radius": "3 mm", "role": "train"},
               {"file": "sub/a2.csv", "radius": "2000 um", "role": "validate", "name": "small"}]})");
  const Dataset d = read_dataset(file);
  EXPECT_EQ(d.test, TestKind::Indentation);
  EXPECT_EQ(d.sample, "phantom");
  ASSERT_EQ(d.layer_depths.size(), 1u);
  expect_close(d.layer_depths[0], 0.01, "layer depth");
  EXPECT_FALSE(d.depth_search());
  ASSERT_TRUE(d.lateral_size.has_value());
  expect_close(*d.lateral_size, 0.1, "lateral size");
  EXPECT_EQ(d.contact, axisym::PunchContact::Frictionless);
  EXPECT_EQ(d.poisson, 0.4);
  ASSERT_EQ(d.curves.size(), 2u);
  EXPECT_EQ(d.count(CurveRole::Train), 1u);
  EXPECT_EQ(d.count(CurveRole::Validate), 1u);

  const MeasuredCurve& a = d.curves[0];
  EXPECT_EQ(a.file, dir / "data" / "a3.csv");
  EXPECT_EQ(a.name, "a3");
  EXPECT_EQ(a.role, CurveRole::Train);
  expect_close(a.radius, 3e-3, "radius");
  ASSERT_EQ(a.x.size(), 4u);
  expect_close(a.x[2], 1e-3, "indentation 1 mm");
  expect_close(a.y[3], 45 * 9.80665e-3, "force 45 gf");  // 1 gf = 9.80665 mN

  const MeasuredCurve& b = d.curves[1];
  EXPECT_EQ(b.file, dir / "data" / "sub" / "a2.csv");
  EXPECT_EQ(b.name, "small");
  EXPECT_EQ(b.role, CurveRole::Validate);
  expect_close(b.radius, 2e-3, "radius in um");
  expect_close(b.x[0], 1e-4, "indentation 100 um");
  expect_close(b.y[2], 0.009, "force in N");
}

TEST(Dataset, DepthRangeAndDepthListAreGuesses) {
  ScratchDir dir;
  dir.write("a.csv", fit::test::kGoodCurve);
  const auto range = dir.write(
      "range.json", fit::test::indentation_dataset(R"([{"file": "a.csv", "radius": "3 mm", "role": "train"}])",
                                                   R"("layer_depth": {"from": "3 mm", "to": "9 mm", "count": 7})"));
  const Dataset r = read_dataset(range);
  ASSERT_EQ(r.layer_depths.size(), 7u);
  EXPECT_TRUE(r.depth_search());
  for (int k = 0; k < 7; ++k) EXPECT_NEAR(r.layer_depths[static_cast<std::size_t>(k)], (3 + k) * 1e-3, 1e-15) << k;
  EXPECT_EQ(r.contact, axisym::PunchContact::Stick);
  EXPECT_EQ(r.poisson, 0.45);  // the default

  const auto list = dir.write(
      "list.json", fit::test::indentation_dataset(R"([{"file": "a.csv", "radius": "3 mm", "role": "train"}])",
                                                  R"("layer_depth": ["4 mm", "0.5 cm", "6mm"])"));
  const Dataset l = read_dataset(list);
  ASSERT_EQ(l.layer_depths.size(), 3u);
  EXPECT_NEAR(l.layer_depths[0], 4e-3, 1e-18);
  EXPECT_NEAR(l.layer_depths[1], 5e-3, 1e-18);
  EXPECT_NEAR(l.layer_depths[2], 6e-3, 1e-18);

  // Guesses must increase; a range needs at least 2 of them.
  const auto down = dir.write(
      "down.json", fit::test::indentation_dataset(R"([{"file": "a.csv", "radius": "3 mm", "role": "train"}])",
                                                  R"("layer_depth": ["5 mm", "4 mm"])"));
  EXPECT_TRUE(throws_error([&] { read_dataset(down); }, ErrorKind::Input, {"down.json", "layer_depth", "increasing"}));
  const auto one = dir.write(
      "one.json", fit::test::indentation_dataset(R"([{"file": "a.csv", "radius": "3 mm", "role": "train"}])",
                                                 R"("layer_depth": {"from": "3 mm", "to": "9 mm", "count": 1})"));
  EXPECT_TRUE(throws_error([&] { read_dataset(one); }, ErrorKind::Input, {"one.json", "layer_depth.count"}));
  // A depth, a punch or a sample over a metre is a slip of the unit (at
  // 1e308 mm the fit's mesh used to fail inside).
  for (const auto& [depth, curve, field] :
       {std::tuple{R"("layer_depth": "1e308 mm")", "3 mm", "layer_depth"},
        std::tuple{R"("layer_depth": ["5 mm", "2 m"])", "3 mm", "layer_depth"},
        std::tuple{R"("layer_depth": "5 mm")", "1e20 mm", "curves[0].radius"}}) {
    const auto huge = dir.write(
        "huge.json", fit::test::indentation_dataset(
                         fmt::format(R"([{{"file": "a.csv", "radius": "{}", "role": "train"}}])", curve), depth));
    EXPECT_TRUE(throws_error([&] { read_dataset(huge); }, ErrorKind::Input, {"huge.json", field, "at most 1 m"}))
        << depth;
  }
}

TEST(Dataset, CompressionUsesTheSampleGeometry) {
  ScratchDir dir;
  dir.write("c1.csv", "indentation_mm,force_N\n0,0\n1,2.5\n2,5.5\n3,9.0\n");
  const auto file = dir.write("dataset.json", R"({
    "palpa_dataset": 1, "test": "compression", "sample_radius": "25 mm", "sample_height": "30 mm",
    "contact": "bonded", "curves": [{"file": "c1.csv", "role": "train"}]})");
  const Dataset d = read_dataset(file);
  EXPECT_EQ(d.test, TestKind::Compression);
  ASSERT_EQ(d.layer_depths.size(), 1u);
  expect_close(d.layer_depths[0], 0.03, "sample height");
  expect_close(d.sample_radius, 0.025, "sample radius");
  EXPECT_EQ(d.contact, axisym::PunchContact::Stick);
  ASSERT_EQ(d.curves.size(), 1u);
  expect_close(d.curves[0].radius, 0.025, "curve radius = sample radius");
  expect_close(d.curves[0].x[3], 3e-3, "platen travel");
  EXPECT_EQ(d.curves[0].y[2], 5.5);
  // Compression has no layer depth.
  const auto wrong = dir.write("wrong.json", R"({
    "palpa_dataset": 1, "test": "compression", "sample_radius": "25 mm", "sample_height": "30 mm",
    "layer_depth": "30 mm", "contact": "bonded", "curves": [{"file": "c1.csv", "role": "train"}]})");
  EXPECT_TRUE(throws_error([&] { read_dataset(wrong); }, ErrorKind::Input, {"wrong.json", "layer_depth"}));
}

TEST(Dataset, HomogeneousCurvesReadStressInPascal) {
  ScratchDir dir;
  dir.write("u.csv", "stretch,stress_kPa\n0.8,-5.5\n1.0,0\n1.2,4.1\n1.5,9.0\n");
  dir.write("b.csv", "stretch,stress_MPa\n1.1,0.004\n1.2,0.009\n1.3,0.015\n");
  dir.write("s.csv", "shear,stress_Pa\n0.1,900\n0.2,1850\n0.3,2900\n");
  const auto file = dir.write("dataset.json", R"({
    "palpa_dataset": 1, "test": "homogeneous", "poisson": 0.49,
    "curves": [{"file": "u.csv", "load_case": "uniaxial", "role": "train"},
               {"file": "b.csv", "load_case": "equibiaxial", "role": "train"},
               {"file": "s.csv", "load_case": "shear", "role": "validate"}]})");
  const Dataset d = read_dataset(file);
  EXPECT_EQ(d.test, TestKind::Homogeneous);
  EXPECT_EQ(d.layer_depths, std::vector<double>{0.0});  // one fit, no geometry
  EXPECT_FALSE(d.depth_search());
  EXPECT_EQ(d.poisson, 0.49);
  ASSERT_EQ(d.curves.size(), 3u);
  EXPECT_EQ(d.curves[0].load_case, material::LoadCase::Uniaxial);
  EXPECT_EQ(d.curves[1].load_case, material::LoadCase::Equibiaxial);
  EXPECT_EQ(d.curves[2].load_case, material::LoadCase::SimpleShear);
  EXPECT_EQ(d.curves[0].x[0], 0.8);
  expect_close(d.curves[0].y[0], -5500.0, "negative (compressive) stress in kPa");
  expect_close(d.curves[1].y[1], 9000.0, "stress in MPa");
  expect_close(d.curves[2].x[2], 0.3, "shear");
  expect_close(d.curves[2].y[2], 2900.0, "stress in Pa");
  // A curve without load case, and an unknown one.
  const auto none = dir.write("none.json", R"({"palpa_dataset": 1, "test": "homogeneous",
    "curves": [{"file": "u.csv", "role": "train"}]})");
  EXPECT_TRUE(throws_error([&] { read_dataset(none); }, ErrorKind::Input, {"none.json", "curves[0].load_case", "missing"}));
  const auto bad = dir.write("bad.json", R"({"palpa_dataset": 1, "test": "homogeneous",
    "curves": [{"file": "u.csv", "load_case": "torsion", "role": "train"}]})");
  EXPECT_TRUE(throws_error([&] { read_dataset(bad); }, ErrorKind::Input, {"bad.json", "curves[0].load_case", "torsion"}));
}

TEST(Dataset, SmallNegativeForcesAreNoise) {
  // −1% of the largest force is within the 2% allowed for noise at contact.
  ScratchDir dir;
  dir.write("a.csv", "indentation_mm,force_N\n0,-0.0008\n0.5,0.03\n1.0,0.085\n");
  const auto file = dir.write("dataset.json", fit::test::indentation_dataset());
  const Dataset d = read_dataset(file);
  EXPECT_EQ(d.curves[0].y[0], -0.0008);
}

TEST(Dataset, EveryBadDatasetIsRefusedNamingTheFileAndField) {
  for (const auto& bad : fit::test::bad_datasets()) {
    ScratchDir dir;
    for (const auto& [name, text] : bad.files) dir.write(name, text);
    const auto file = dir.write("dataset.json", bad.dataset);
    EXPECT_TRUE(throws_error([&] { read_dataset(file); }, ErrorKind::Input, bad.fragments)) << bad.what;
  }
  // A dataset file that does not exist.
  ScratchDir dir;
  EXPECT_TRUE(throws_error([&] { read_dataset(dir / "missing.json"); }, ErrorKind::Input, {"missing.json"}));
}

}  // namespace
}  // namespace palpa::fit
