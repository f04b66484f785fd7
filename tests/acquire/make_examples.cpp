// SPDX-License-Identifier: AGPL-3.0-or-later
// Writes the synthetic example recordings of examples/acquire from the same
// generators the tests use:
//   palpa_acquire_make_examples <examples/acquire folder>
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "synthetic.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    fmt::print(stderr, "usage: {} EXAMPLES_ACQUIRE_FOLDER\n", argv[0]);
    return 2;
  }
  const std::filesystem::path out = argv[1];
  auto write = [&](const std::filesystem::path& rel, const std::string& text) {
    std::filesystem::create_directories((out / rel).parent_path());
    std::ofstream f(out / rel, std::ios::binary);
    f << text;
    if (!f) {
      fmt::print(stderr, "cannot write {}\n", (out / rel).string());
      std::exit(1);
    }
  };
  palpa::test::SyntheticPoke p;
  p.force_rate = 100.0;
  p.laser_rate = 500.0;
  const palpa::test::SyntheticLogs logs = palpa::test::make_poke_logs(p);
  write("poke/force.csv", logs.force_csv);
  write("poke/laser.csv", logs.laser_csv);
  write("poke/laser-calibration.csv", logs.calibration_csv);
  // Ultrasound: the probe's clock runs 0.15 s ahead of the gauge's; the fat
  // layer (8 mm) takes 60% of the indentation, the bone (24 mm) 90%.
  palpa::test::SyntheticPoke u;
  u.force_rate = 100.0;
  u.seed = 2;
  write("ultrasound/force.csv", palpa::test::make_poke_logs(u).force_csv);
  write("ultrasound/fat.csv", palpa::test::make_interface_picks(u, 8e-3, 0.6, 0.15));
  write("ultrasound/bone.csv", palpa::test::make_interface_picks(u, 24e-3, 0.9, 0.15));
  // Pressure sensors on a 10 cm square plate (a stand-in for a sole), 12
  // locations, a peak near one corner; readings in volts with 2% noise.
  const palpa::SurfaceMesh plate = palpa::test::plate(10, 0.1);
  write("pressure/support.obj", palpa::test::obj_text(plate));
  palpa::test::SyntheticPressure s;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 4; ++i) s.positions.emplace_back(-0.03 + 0.02 * i, -0.02 + 0.02 * j, 0.0);
  }
  s.ratio = [](const Eigen::Vector3d& x) {
    return 0.5 + 2.0 * std::exp(-((x - Eigen::Vector3d(0.02, 0.01, 0.0)).squaredNorm()) / (2 * 0.02 * 0.02));
  };
  s.noise = 0.02;
  s.seed = 3;
  s.digits = 5;
  write("pressure/locations.csv", palpa::test::pressure_locations_csv(s));
  write("pressure/samples.csv", palpa::test::pressure_samples_csv(s));
  return 0;
}
