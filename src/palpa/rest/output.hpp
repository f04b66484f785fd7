#pragma once
// Writing the results of `palpa rest` into a folder: body.vtu (deformed layer
// with displacement_m, contact_force_N, pressure_Pa, attached; von Mises stress
// per tet), skin.ply (deformed skin with pressure_Pa), support.vtu and
// support.ply (pressure_Pa from the reverse query), pressure_histogram.svg
// (contact pressures on body and support), summary.json. Each file is atomic.

#include <filesystem>

#include "palpa/core/json.hpp"
#include "palpa/rest/rest.hpp"
#include "palpa/rest/scene.hpp"

namespace palpa::rest {

// The summary (also written as summary.json).
Json write_rest_outputs(const std::filesystem::path& out, const RestScene& scene, const RestSimulation& sim,
                        const RestResult& r);

}  // namespace palpa::rest
