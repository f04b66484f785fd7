// SPDX-License-Identifier: AGPL-3.0-or-later
// Catmull–Rom splines on exact cases; synthetic ultrasound picks give back the
// known rest depths, clock offset and depth-vs-force.
#include <gtest/gtest.h>

#include <cmath>

#include "common/test_support.hpp"
#include "palpa/acquire/ultrasound.hpp"
#include "synthetic.hpp"

namespace palpa::acquire {
namespace {

TEST(CatmullRom, InterpolatesThePointsAndReproducesLinesAndEvenParabolas) {
  const std::vector<double> t{0.0, 0.3, 0.5, 1.2, 1.3};
  std::vector<double> line;
  for (double x : t) line.push_back(2.0 - 3.0 * x);
  const CatmullRom l(t, line);
  for (double x = -0.5; x <= 1.8; x += 0.01) EXPECT_NEAR(l(x), 2.0 - 3.0 * x, 1e-12) << x;
  std::vector<double> even, parabola;
  for (int i = 0; i <= 6; ++i) {
    even.push_back(0.25 * i);
    parabola.push_back(1.0 + even.back() - 2.0 * even.back() * even.back());
  }
  const CatmullRom q(even, parabola);
  for (std::size_t i = 0; i < even.size(); ++i) EXPECT_NEAR(q(even[i]), parabola[i], 1e-14);
  for (double x = 0.25; x <= 1.25; x += 0.01) EXPECT_NEAR(q(x), 1.0 + x - 2.0 * x * x, 1e-12) << x;  // inner segments
  EXPECT_GT(std::abs(q(0.1) - (1.0 + 0.1 - 0.02)), 1e-4);  // the end segments use one-sided tangents
}

struct UltrasoundCase {
  test::SyntheticPoke p;
  double clock = 0.15;  // ultrasound time = true time + clock
  double fat = 8e-3, fat_share = 0.6;
  double bone = 24e-3, bone_share = 0.9;
};

TEST(AcquireUltrasound, RecoversRestDepthsClockAndDepthAgainstForce) {
  const UltrasoundCase c;
  test::ScratchDir dir;
  const auto force = dir.write("force.csv", test::make_poke_logs(c.p).force_csv);
  const auto fat = dir.write("fat.csv", test::make_interface_picks(c.p, c.fat, c.fat_share, c.clock));
  const auto bone = dir.write("bone.csv", test::make_interface_picks(c.p, c.bone, c.bone_share, c.clock));
  const UltrasoundResult r = process_ultrasound(force, {{"fat", fat}, {"bone", bone}}, {});
  // The offset (guess 0) is found within 10 ms.
  EXPECT_NEAR(r.clock_shift, -c.clock, 0.01);
  EXPECT_GT(r.correlation, 0.97);
  ASSERT_EQ(r.rest_depth.size(), 2u);
  EXPECT_NEAR(r.rest_depth[0], c.fat, 0.05e-3);
  EXPECT_NEAR(r.rest_depth[1], c.bone, 0.05e-3);
  ASSERT_GT(r.time.size(), 50u);
  double worst = 0.0;
  for (std::size_t i = 0; i < r.time.size(); ++i) {
    worst = std::max(worst, std::abs(r.depth[0][i] - test::interface_depth(c.p, c.fat, c.fat_share, r.time[i])));
    worst = std::max(worst, std::abs(r.depth[1][i] - test::interface_depth(c.p, c.bone, c.bone_share, r.time[i])));
  }
  EXPECT_LT(worst, 0.06e-3);  // 0.06 mm: 2% of the largest compression (4.5 mm)
  // The last loading sample is at the maximum force, where the bone is closest.
  EXPECT_NEAR(r.depth[1].back(), c.bone - c.bone_share * c.p.depth, 0.06e-3);
  EXPECT_NEAR(r.force.back(), c.p.expected_force(c.p.depth), 0.02 * c.p.expected_force(c.p.depth));
}

TEST(AcquireUltrasound, RefusesPicksThatMissThePokeOrAreUnsorted) {
  const UltrasoundCase c;
  test::ScratchDir dir;
  const auto force = dir.write("force.csv", test::make_poke_logs(c.p).force_csv);
  // Picks on a clock 10 s ahead, aligned with no offset: they miss the poke.
  const auto late = dir.write("late.csv", test::make_interface_picks(c.p, c.fat, c.fat_share, 10.0));
  UltrasoundOptions o;
  o.align = false;
  EXPECT_TRUE(test::throws_error([&] { process_ultrasound(force, {{"fat", late}}, o); }, ErrorKind::Input,
                                 {"late.csv", "interface 'fat' cover 10.5 s .. 14.5 s", "--offset"}));
  o.offset = -10.0;
  EXPECT_NO_THROW(process_ultrasound(force, {{"fat", late}}, o));
  const auto bad = dir.write("bad.csv", "time_s,depth_mm\n0.5,8\n0.4,8\n1,7\n");
  EXPECT_TRUE(test::throws_error([&] { process_ultrasound(force, {{"fat", bad}}, {}); }, ErrorKind::Input,
                                 {"bad.csv:3", "not after the previous pick"}));
  const auto neg = dir.write("neg.csv", "time_s,depth_mm\n0.5,8\n0.6,-1\n");
  EXPECT_TRUE(test::throws_error([&] { process_ultrasound(force, {{"fat", neg}}, {}); }, ErrorKind::Input,
                                 {"neg.csv:3", "negative"}));
}

}  // namespace
}  // namespace palpa::acquire
