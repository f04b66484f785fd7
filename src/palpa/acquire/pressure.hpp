// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Pressure-sensor measurements -> pressure map on a support surface (thesis
// §7.6, `palpa acquire pressure`).
//
// A thin force sensor is placed at one marked location of the support (a shoe
// sole) at a time and records samples (e.g. 600 at 10 Hz) while the subject
// stands; a second, reference sensor at a fixed place records at the same time.
// Per location: drop the `trim` smallest and largest samples, take the mean p_i
// and standard deviation s_i (and the reference's mean r_i); compensate posture
// changes by scaling with α_i = C / r_i (so α_i r_i is the same constant C for
// every location); interpolate C p_i / r_i onto the support's vertices with
// linearly precise biharmonic weights (harmonic as a fallback), each location a
// handle, over the part of the surface the sensors cover (within `reach` of a
// location along the surface; beyond it nothing was measured and the map is
// 0); choose C so the net force of the interpolated pressure over the
// surface equals a given load (e.g. half the body weight). Sensor readings may
// be in any unit proportional to the force (volts of the sensor circuit): the
// load fixes the scale, so no calibration is needed.
//
// Files (CSV, io/csv.hpp):
//   locations:  location,x_<unit>,y_<unit>,z_<unit>   (integer ids, positions on the support)
//   samples:    location,reading[,reference]           (one row per sample, any order
//                                                       of locations; readings and
//                                                       reference may carry units,
//                                                       only ratios matter)

#include <Eigen/Core>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "palpa/geometry/mesh.hpp"
#include "palpa/geometry/surface_interpolation.hpp"

namespace palpa::acquire {

// Mean and sample standard deviation (n − 1) of `v` after dropping its `trim`
// smallest and `trim` largest values. Requires v.size() >= 2·trim + 2.
struct TrimmedStats {
  double mean = 0.0;
  double std = 0.0;
  std::size_t kept = 0;
};
TrimmedStats trimmed_stats(std::span<const double> v, std::size_t trim);

struct PressureOptions {
  std::size_t trim = 50;       // samples dropped at each end per location
  std::size_t clip_run = 10;   // identical samples in a row at a location's maximum = saturated
  std::string reading_column = "reading";
  std::string reference_column = "reference";  // used when present
  geometry::InterpolationOptions interpolation;  // method, max_distance, clamping
  double load = 0.0;           // net force the map must carry [N], > 0
  // How far along the surface the map reaches from its nearest location [m];
  // 0: the largest distance from a location to its nearest neighbour (the
  // sensors' spacing), unlimited for a single location.
  double reach = 0.0;
};

struct SensorLocation {
  long id = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // [m]
  std::size_t samples = 0;
  TrimmedStats reading, reference;  // reference = {1, 0} without a reference column
  double pressure = 0.0;            // C p_i / r_i [Pa]
  double pressure_std = 0.0;        // C s_i / r_i [Pa]
  double distance = 0.0;            // from the support surface [m]
};

struct PressureMap {
  std::vector<SensorLocation> locations;  // in the locations file's order
  bool compensated = false;               // a reference column was used
  double constant = 0.0;                  // C [Pa per reading/reference]
  Eigen::VectorXd pressure;               // #V [Pa]
  Eigen::VectorXd pressure_std;           // #V [Pa]
  Eigen::Vector3d net_force = Eigen::Vector3d::Zero();  // ∫ p n dA [N]
  double contact_area = 0.0;              // area where p > 0 [m²]
  double reach = 0.0;                     // the reach used [m] (+inf: unlimited)
  double covered_area = 0.0;              // area within reach of a location [m²]
};

// Reads the two files and builds the map on `mesh`. Throws palpa::Error
// (Input) naming the file, line and location for: missing columns, a location
// id that is not an integer or appears twice in the locations file, samples of
// an unknown location, a location without enough samples (2·trim + 2), a
// saturated sensor (clip_run identical readings in a row at the location's
// maximum), a reference mean <= 0, a location farther than max_distance from
// the surface (geometry/surface_interpolation.hpp), a map with no net force, a
// load <= 0.
PressureMap pressure_map(const SurfaceMesh& mesh, const std::filesystem::path& locations,
                         const std::filesystem::path& samples, const PressureOptions& options);


}  // namespace palpa::acquire
