// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Comparing two pressure maps on the same support (thesis §7.6, §7.8): a
// simulated map against a measured one (`palpa acquire pressure` on the same
// mesh), or two simulations.
//
// A map is a triangle surface with one pressure per vertex [Pa]. The two must
// be on the same mesh: the same number of vertices at the same places (to
// 1e-6 of the mesh's size). Figures, over the vertices where either map is
// positive (the union of the two contact patches; U below), with vertex areas
// A_i (a third of the incident triangles):
//   rms_difference      sqrt(Σ_U A_i (a_i − b_i)² / Σ_U A_i)          [Pa]
//   relative_rms        rms_difference / (Σ_U A_i b_i / Σ_U A_i)      (b: the reference)
//   max_difference      max_U |a_i − b_i|                             [Pa]
//   correlation         area-weighted Pearson correlation over U (NaN where a
//                       map is uniform over U: no correlation is defined)
// and each map's own figures, as every rest and design summary reports them
// (pressure_metrics.hpp: force Σ A_i p_i, contact area, mean, peak, Peak
// Pressure Index, 95th percentile, centre of pressure, dispersion index).

#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "palpa/geometry/mesh.hpp"
#include "palpa/report/pressure_metrics.hpp"

namespace palpa::report {

struct PressureMap {
  SurfaceMesh mesh;
  Eigen::VectorXd pressure;  // per vertex [Pa]
  std::string source;        // file name, for messages
};

// The largest pressure a map may hold [Pa]: 1 GPa, far beyond any contact
// of tissue (sums and squares of larger values overflow).
inline constexpr double kMaxMapPressure = 1e9;

// Reads a PLY or VTU surface with a per-vertex scalar `field` (pressure_Pa by
// default). Throws palpa::Error (Input) naming the file for a missing field,
// a pressure that is not finite, negative or above kMaxMapPressure, or a mesh that is not triangles.
PressureMap read_pressure_map(const std::filesystem::path& path, const std::string& field = "pressure_Pa");

struct MapComparison {
  int vertices = 0;         // in the union of the contact patches
  double rms_difference = 0.0, relative_rms = 0.0, max_difference = 0.0, correlation = 0.0;
  PressureMetrics a, b;
};

// a against the reference b. Throws palpa::Error (Input) for maps on
// different meshes (naming transfer_pressure_map's way) or with no contact
// at all.
MapComparison compare_pressure_maps(const PressureMap& a, const PressureMap& b);

// How far a transfer reached.
struct MapTransfer {
  double max_distance = 0.0;   // from a target vertex to its closest point on the source [m]
  double mean_distance = 0.0;  // [m]
};

// The pressures of `from` moved onto the vertices of `onto` (maps on two
// different supports: before and after a design, a measured mat against a
// simulated support): each vertex of `onto` takes the pressure at its closest
// point on `from`, interpolated linearly in that triangle. t (may be null)
// receives how far the closest points were.
PressureMap transfer_pressure_map(const PressureMap& from, const SurfaceMesh& onto, MapTransfer* t = nullptr);

// a against a reference b on another mesh: b moved onto a's vertices
// (transfer_pressure_map), the difference figures over a's mesh; each map's
// own figures on its own mesh.
MapComparison compare_across_meshes(const PressureMap& a, const PressureMap& b, MapTransfer* t = nullptr);

}  // namespace palpa::report
