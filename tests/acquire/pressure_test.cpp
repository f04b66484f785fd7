// SPDX-License-Identifier: AGPL-3.0-or-later
// Pressure maps: trimmed statistics, posture compensation, exact
// reproduction of constant and linear fields, the load normalization, and
// every bad input named.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "common/test_support.hpp"
#include "palpa/acquire/pressure.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/sim3d/shapes.hpp"
#include "synthetic.hpp"

namespace palpa::acquire {
namespace {

std::vector<Eigen::Vector3d> scattered_locations() {
  // 12 locations on the 10 cm plate, at vertices of both test plates (8 and 16
  // cells): the interpolation attaches each location to its nearest vertex, so
  // a linear field is reproduced exactly when the locations are vertices.
  std::vector<Eigen::Vector3d> p;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 4; ++i) p.emplace_back(-0.0375 + 0.025 * i, -0.025 + 0.025 * j + (i == 2 ? 0.0125 : 0.0), 0.0);
  }
  return p;
}

struct PressureFiles {
  std::filesystem::path locations, samples;
};

PressureFiles write_files(const test::ScratchDir& dir, const test::SyntheticPressure& s) {
  return {dir.write("locations.csv", test::pressure_locations_csv(s)),
          dir.write("samples.csv", test::pressure_samples_csv(s))};
}

TEST(TrimmedStats, DropsTheExtremesOnEachSide) {
  const std::vector<double> v{10, 1, 9, 2, 8, 3, 7, 4, 6, 5, 100, -50};
  const TrimmedStats s = trimmed_stats(v, 3);  // keeps 3..8
  EXPECT_EQ(s.kept, 6u);
  EXPECT_DOUBLE_EQ(s.mean, 5.5);
  EXPECT_NEAR(s.std, std::sqrt(17.5 / 5.0), 1e-15);
}

TEST(AcquirePressure, CompensatesPostureAndReproducesALinearFieldExactly) {
  test::ScratchDir dir;
  test::SyntheticPressure s;
  s.positions = scattered_locations();
  s.ratio = [](const Eigen::Vector3d& x) { return 2.0 + 10.0 * x.x() - 7.0 * x.y(); };  // 1.3 .. 2.7
  const PressureFiles f = write_files(dir, s);
  const SurfaceMesh mesh = test::plate(16, 0.1);
  PressureOptions o;
  o.load = 350.0;
  o.interpolation.clamp_to_sample_range = false;
  o.reach = 1.0;  // the whole plate was measured
  const PressureMap m = pressure_map(mesh, f.locations, f.samples, o);
  ASSERT_TRUE(m.compensated);
  // The posture factors cancel: location i reads C·ratio(x_i).
  for (const SensorLocation& loc : m.locations) {
    EXPECT_NEAR(loc.pressure, m.constant * s.ratio(loc.position), 1e-9 * loc.pressure) << loc.id;
    EXPECT_EQ(loc.samples, 600u);
    EXPECT_EQ(loc.reading.kept, 500u);
  }
  // The linear ratio is reproduced at every vertex by the biharmonic interpolation.
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
    EXPECT_NEAR(m.pressure(v), m.constant * s.ratio(mesh.V.row(v).transpose()), 1e-9 * m.constant) << v;
  }
  // The net force is the load, normal to the plate.
  EXPECT_NEAR(m.net_force.norm(), 350.0, 1e-9);
  EXPECT_NEAR(std::abs(m.net_force.z()), 350.0, 1e-9);
  // ∫ ratio dA over the centred square = 2 × area (the linear parts integrate to 0).
  EXPECT_NEAR(m.constant, 350.0 / (2.0 * 0.01), 1e-6 * m.constant);
  EXPECT_NEAR(m.contact_area, 0.01, 1e-12);
  // Standard deviations: the ripple's ten levels ±1% (60 samples each) keep 10,
  // 8×60 and 10 samples after trimming 50 on each side: Σ level² = 20 + 60·42/20.25.
  const double relative_std = 0.01 * std::sqrt((20.0 + 60.0 * 42.0 / 20.25) / 499.0);
  for (const SensorLocation& loc : m.locations) {
    EXPECT_NEAR(loc.pressure_std / loc.pressure, relative_std, 1e-9) << loc.id;
  }
}

TEST(AcquirePressure, AConstantFieldIsTheLoadOverTheArea) {
  for (auto method : {geometry::SurfaceInterpolation::Biharmonic, geometry::SurfaceInterpolation::Harmonic}) {
    test::ScratchDir dir;
    test::SyntheticPressure s;
    s.positions = scattered_locations();
    s.ratio = [](const Eigen::Vector3d&) { return 3.0; };
    const PressureFiles f = write_files(dir, s);
    PressureOptions o;
    o.load = 100.0;
    o.interpolation.method = method;
    o.reach = 1.0;  // the whole plate was measured
    const PressureMap m = pressure_map(test::plate(8, 0.1), f.locations, f.samples, o);
    for (Eigen::Index v = 0; v < m.pressure.size(); ++v) EXPECT_NEAR(m.pressure(v), 100.0 / 0.01, 1e-7);
  }
}

TEST(AcquirePressure, TheMapEndsWhereTheSensorsDoAndCarriesTheLoad) {
  // A seat: a 20 × 20 × 4 cm box of 5 mm cells, a mat of 5 × 5 sensors 2.5 cm
  // apart over the middle 10 × 10 cm of its top, reading a constant.
  const SurfaceMesh seat = sim3d::make_box_surface({0.2, 0.2, 0.04}, Eigen::Vector3i(40, 40, 8));
  test::ScratchDir dir;
  test::SyntheticPressure s;
  for (int j = 0; j < 5; ++j) {
    for (int i = 0; i < 5; ++i) s.positions.emplace_back(-0.05 + 0.025 * i, -0.05 + 0.025 * j, 0.04);
  }
  s.ratio = [](const Eigen::Vector3d&) { return 3.0; };
  const PressureFiles f = write_files(dir, s);
  PressureOptions o;
  o.load = 100.0;
  const PressureMap m = pressure_map(seat, f.locations, f.samples, o);
  EXPECT_DOUBLE_EQ(m.reach, 0.025);  // the sensors' spacing
  const Eigen::VectorXd areas = geometry::vertex_areas(seat);
  double carried = 0.0;
  for (Eigen::Index v = 0; v < seat.V.rows(); ++v) {
    const Eigen::Vector3d x = seat.V.row(v).transpose();
    carried += m.pressure(v) * areas(v);
    if (x.z() < 0.04 - 1e-9) {
      EXPECT_EQ(m.pressure(v), 0.0) << "a side or the bottom: " << x.transpose();
    } else if (x.head<2>().cwiseAbs().maxCoeff() <= 0.05 + 1e-9) {
      EXPECT_GT(m.pressure(v), 0.0) << "under the mat: " << x.transpose();
    } else if (x.head<2>().cwiseAbs().minCoeff() > 0.075 + 1e-9) {
      EXPECT_EQ(m.pressure(v), 0.0) << "beyond the mat: " << x.transpose();
    }
  }
  // All on the flat top: the map's own force Σ p·A is the load.
  EXPECT_NEAR(carried, 100.0, 1e-9);
  EXPECT_NEAR(m.net_force.z(), 100.0, 1e-9);
  EXPECT_GT(m.covered_area, 0.1 * 0.1);
  EXPECT_LT(m.covered_area, 0.15 * 0.15);
  // Spread over the whole box, the sides and the bottom would push back: the
  // net force is still the load, the map's own force far above it.
  o.reach = 1.0;
  const PressureMap everywhere = pressure_map(seat, f.locations, f.samples, o);
  EXPECT_NEAR(everywhere.net_force.norm(), 100.0, 1e-9);
  EXPECT_GT(everywhere.pressure.dot(areas), 2.0 * 100.0);
}

TEST(AcquirePressure, WithoutAReferenceTheReadingsAreUsedAsTheyAre) {
  test::ScratchDir dir;
  test::SyntheticPressure s;
  s.positions = scattered_locations();
  s.ratio = [](const Eigen::Vector3d&) { return 3.0; };
  const PressureFiles f = write_files(dir, s);
  const CsvTable t = read_csv(f.samples);
  std::string text = "location,reading_V\n";
  for (std::size_t r = 0; r < t.rows(); ++r) {
    text += fmt::format("{},{}\n", t.column("location")[r], t.column("reading_V")[r]);
  }
  const auto plain = dir.write("plain.csv", text);
  PressureOptions o;
  o.load = 100.0;
  const PressureMap m = pressure_map(test::plate(8, 0.1), f.locations, plain, o);
  EXPECT_FALSE(m.compensated);
  // Location i read 3·posture_i; without compensation the posture stays in.
  const double p0 = m.locations[0].pressure, p1 = m.locations[1].pressure;
  EXPECT_NEAR(p1 / p0, (1.0 + 0.2 * std::sin(1.7)) / 1.0, 1e-9);
}

TEST(AcquirePressure, RefusesBadInputNamingTheLocation) {
  test::ScratchDir dir;
  test::SyntheticPressure s;
  s.positions = scattered_locations();
  s.ratio = [](const Eigen::Vector3d&) { return 3.0; };
  const PressureFiles f = write_files(dir, s);
  const SurfaceMesh mesh = test::plate(8, 0.1);
  PressureOptions o;
  o.load = 100.0;
  // A location 2 cm above the plate.
  test::SyntheticPressure off = s;
  off.positions[6].z() = 0.02;
  const auto off_locations = dir.write("off.csv", test::pressure_locations_csv(off));
  EXPECT_TRUE(test::throws_error([&] { pressure_map(mesh, off_locations, f.samples, o); }, ErrorKind::Input,
                                 {"location 7", "off.csv:9"}));
  // Saturation: location 3 clips at its 20 largest readings, in a row.
  const CsvTable t = read_csv(f.samples);
  std::string clipped = "location,reading_V,reference_V\n";
  for (std::size_t r = 0; r < t.rows(); ++r) {
    const bool clip = t.column("location")[r] == 3.0 && r >= 1300 && r < 1320;
    clipped += fmt::format("{},{},{}\n", t.column("location")[r], clip ? 9.9 : t.column("reading_V")[r],
                           t.column("reference_V")[r]);
  }
  const auto c = dir.write("clipped.csv", clipped);
  EXPECT_TRUE(test::throws_error([&] { pressure_map(mesh, f.locations, c, o); }, ErrorKind::Input,
                                 {"clipped.csv:1302", "saturated at location 3", "20 samples in a row"}));
  // An unknown location, too few samples, a missing column, no load.
  const auto unknown = dir.write("unknown.csv", "location,reading,reference\n99,1,1\n");
  EXPECT_TRUE(test::throws_error([&] { pressure_map(mesh, f.locations, unknown, o); }, ErrorKind::Input,
                                 {"unknown.csv:2", "location 99 is not in the locations file"}));
  o.trim = 400;
  EXPECT_TRUE(test::throws_error([&] { pressure_map(mesh, f.locations, f.samples, o); }, ErrorKind::Input,
                                 {"location 1 has 600 samples", "at least 802"}));
  o.trim = 50;
  o.reading_column = "volts";
  EXPECT_TRUE(test::throws_error([&] { pressure_map(mesh, f.locations, f.samples, o); }, ErrorKind::Input,
                                 {"samples.csv", "no column 'volts'"}));
  o.reading_column = "reading";
  o.load = 0.0;
  EXPECT_TRUE(test::throws_error([&] { pressure_map(mesh, f.locations, f.samples, o); }, ErrorKind::Input,
                                 {"--load"}));
}

}  // namespace
}  // namespace palpa::acquire
