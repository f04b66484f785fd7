// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Writing the results of `palpa rest` into a folder: body.vtu (deformed layer
// with displacement_m, contact_force_N, pressure_Pa, attached; von Mises stress
// per tet), skin.ply (deformed skin with pressure_Pa), support.vtu and
// support.ply (pressure_Pa from the reverse query), pressure_histogram.svg
// (contact pressures on body and support), summary.json. Each file is atomic.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "palpa/core/json.hpp"
#include "palpa/io/ply.hpp"
#include "palpa/report/plot.hpp"
#include "palpa/rest/rest.hpp"
#include "palpa/rest/scene.hpp"

namespace palpa::rest {

// The deformed skin, compacted to its own vertices, with per-body-vertex
// fields (each #body vertices) carried along, as a PLY file.
void write_skin_ply(const std::filesystem::path& path, const RestSimulation& sim,
                    const std::vector<std::pair<std::string, Eigen::VectorXd>>& fields);
// The support in world coordinates.
SurfaceMesh world_support(const RestSimulation& sim);
// A histogram of the positive values [Pa] as a step line over [0, top] in
// `bins` bins, x in kPa.
report::Series pressure_histogram(const std::string& label, const Eigen::VectorXd& v, double top, int bins);

// The summary (also written as summary.json).
Json write_rest_outputs(const std::filesystem::path& out, const RestScene& scene, const RestSimulation& sim,
                        const RestResult& r);

}  // namespace palpa::rest
