// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The figures people who judge supports read off a pressure-mapping mat
// (seating and insole systems), for one side of a contact: a map of one
// pressure per vertex of a triangle surface [Pa] with the vertices' areas
// (a third of their triangles) [m²]. Over the contact patch C (p_i above the
// threshold):
//   force               Σ_i A_i p_i                                   [N]
//   contact_area        Σ_C A_i (or the areas in contact, if given)  [m²]
//   mean                force / contact_area                          [Pa]
//   peak                max p_i                                       [Pa]
//   peak_pressure_index the highest mean pressure over a window of about
//                       `window_area` (9 cm² by default, a 3 × 3 block of
//                       1 cm sensels): for each vertex of C the nearest
//                       vertices (itself first) until their areas reach
//                       the window, area-weighted mean of their pressures;
//                       robust to a one-vertex spike, unlike the peak  [Pa]
//   p95                 the area-weighted 95th percentile of p over C  [Pa]
//   centre              the centre of pressure Σ A_i p_i x_i / force  [m]
//   dispersion_index    the share of the force carried within the peak
//                       pressure index's window (1: all of it on one
//                       spot; a support that spreads the load has a low
//                       one)                                          [-]
// Measured maps (`palpa acquire pressure`) and simulated ones use the same
// code, so `palpa compare` compares like with like.

#include <Eigen/Core>

#include "palpa/core/json.hpp"
#include "palpa/geometry/mesh.hpp"

namespace palpa::report {

struct PressureMetricsOptions {
  double window_area = 9e-4;  // [m²]
  double threshold = 0.0;     // pressures above it are in contact [Pa]
};

struct PressureMetrics {
  double force = 0.0;
  double contact_area = 0.0;
  double mean = 0.0;
  double peak = 0.0;
  double peak_pressure_index = 0.0;
  double p95 = 0.0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double dispersion_index = 0.0;
  int contact_vertices = 0;
};

// V: #V×3 vertex positions [m]; area: #V vertex areas [m²]; pressure: #V
// [Pa]. All zero without contact. Throws palpa::Error (Input) for sizes that
// differ, a negative or non-finite pressure or area, or a window ≤ 0.
PressureMetrics pressure_metrics(const Eigen::MatrixX3d& V, const Eigen::VectorXd& area,
                                 const Eigen::VectorXd& pressure, const PressureMetricsOptions& options = {});
// The same with each vertex's area in contact given (#V, each between 0 and
// its area: the patch's edge cuts through vertices): the contact area is
// their sum and the p95 is weighted by them (the patch C and the windows
// stay as above).
PressureMetrics pressure_metrics(const Eigen::MatrixX3d& V, const Eigen::VectorXd& area,
                                 const Eigen::VectorXd& pressure, const Eigen::VectorXd& contact_area,
                                 const PressureMetricsOptions& options = {});
// The same with the vertex areas of a triangle surface.
PressureMetrics pressure_metrics(const SurfaceMesh& mesh, const Eigen::VectorXd& pressure,
                                 const PressureMetricsOptions& options = {});

// The figures as a JSON object with units in the keys (force_N,
// contact_area_m2, mean_Pa, peak_Pa, peak_pressure_index_Pa, p95_Pa,
// centre_m, dispersion_index, contact_vertices).
Json to_json(const PressureMetrics& m);

}  // namespace palpa::report
