// SPDX-License-Identifier: AGPL-3.0-or-later
// Sample files: positions and values in SI from any units, and bad files
// refused naming the file and column.
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "palpa/mesh/samples.hpp"

namespace palpa::mesh {
namespace {

using test::ScratchDir;
using test::throws_error;

TEST(Samples, ReadsTable31StyleColumnsInAnyUnit) {
  ScratchDir dir;
  const auto file = dir.write("depths.csv",
                              "# arm, side A\nx_mm,y_mm,z_cm,fat_depth_mm,bone_distance_mm\n"
                              "1,2,3,8.033,24.3\n4,5,6,6.621,33.71\n");
  const Samples s = read_samples(file, "bone_distance", Dimension::Length);
  ASSERT_EQ(s.values.size(), 2);
  EXPECT_DOUBLE_EQ(s.values(1), 33.71e-3);
  EXPECT_DOUBLE_EQ(s.positions(1, 2), 0.06);
  EXPECT_DOUBLE_EQ(s.positions(0, 0), 1e-3);
  EXPECT_EQ(s.labels[1], "the sample on line 4");
  EXPECT_EQ(s.field, "bone_distance_mm");
  const Samples fat = read_samples(file, "fat_depth", Dimension::Length);
  EXPECT_DOUBLE_EQ(fat.values(0), 8.033e-3);
}

TEST(Samples, BadFilesNameTheColumn) {
  ScratchDir dir;
  const auto no_z = dir.write("a.csv", "x_mm,y_mm,depth_mm\n1,2,3\n");
  EXPECT_TRUE(throws_error([&] { read_samples(no_z, "depth", Dimension::Length); },
                           ErrorKind::Input, {"a.csv", "z"}));
  const auto wrong_unit = dir.write("b.csv", "x_mm,y_mm,z_mm,youngs_modulus_mm\n1,2,3,4\n");
  EXPECT_TRUE(throws_error(
      [&] { read_samples(wrong_unit, "youngs_modulus", Dimension::Pressure); }, ErrorKind::Input,
      {"b.csv", "youngs_modulus_mm"}));
}

}  // namespace
}  // namespace palpa::mesh
