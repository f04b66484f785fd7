// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Writing the results of `palpa rest` into a folder: body.vtu (deformed layer
// with displacement_m, contact_force_N, pressure_Pa, attached; von Mises stress
// and youngs_modulus_Pa per tet), skin.ply (deformed skin with pressure_Pa,
// youngs_modulus_Pa and layer_depth_m), support.vtu and support.ply
// (pressure_Pa from the reverse query), pressure_histogram.svg (contact
// pressures on body and support), body_pressure.svg and support_pressure.svg
// (each side's map as a picture, report/pressure_map_svg.hpp),
// body_depth.svg and body_stiffness.svg (the layer's depth and modulus over
// the skin, seen as the body's pressures), summary.json. Each file is atomic.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "palpa/core/json.hpp"
#include "palpa/io/ply.hpp"
#include "palpa/io/vtu.hpp"
#include "palpa/report/plot.hpp"
#include "palpa/report/pressure_map_svg.hpp"
#include "palpa/rest/rest.hpp"
#include "palpa/rest/scene.hpp"

namespace palpa::rest {

// The deformed body at the state of the result r (tets, point data
// displacement_m, contact_force_N, pressure_Pa, attached; cell data
// von_mises_stress_Pa) and the support where it is now with pressure_Pa (and
// displacement_m when deformable).
UnstructuredGrid body_grid(const RestSimulation& sim, const RestResult& r);
UnstructuredGrid support_grid(const RestSimulation& sim, const RestResult& r);
// A deformable support's deformed tets (point data displacement_m, cell data
// von_mises_stress_Pa); palpa::Error (Internal) for a rigid one.
UnstructuredGrid support_volume_grid(const RestSimulation& sim);
// The deformed outer skin (tet-mesh vertex numbering kept).
SurfaceMesh deformed_skin(const RestSimulation& sim);

// The deformed skin, compacted to its own vertices, with per-body-vertex
// fields (each #body vertices) carried along, as a PLY file.
void write_skin_ply(const std::filesystem::path& path, const RestSimulation& sim,
                    const std::vector<std::pair<std::string, Eigen::VectorXd>>& fields);
// The support in world coordinates.
SurfaceMesh world_support(const RestSimulation& sim);
// A histogram of the positive values [Pa] as a step line over [0, top] in
// `bins` bins, x in kPa.
report::Series pressure_histogram(const std::string& label, const Eigen::VectorXd& v, double top, int bins);

// Per body vertex: the mean small-strain Young's modulus of its tets [Pa].
Eigen::VectorXd vertex_young(const RestSimulation& sim);
// Per body vertex: on the skin, the soft layer's depth there (the distance
// at rest to the core's surface) [m]; 0 elsewhere.
Eigen::VectorXd skin_layer_depth(const RestSimulation& sim);

// The direction from the support toward the body (unit): against the load
// that presses the body onto the support (its weight and the external
// force), else along the contact force; +z without either.
Eigen::Vector3d support_to_body(const RestResult& r);
// Each side's pressure map at the simulation's current state, which is that
// of the result r, for a picture: the body's on its deformed skin (r's
// body_pressure and body_metrics), the support's on its surface where it is
// now (support_pressure, support_metrics); with r's load for the caption.
report::PressureMapPanel body_pressure_panel(const RestSimulation& sim, const RestResult& r, std::string title);
report::PressureMapPanel support_pressure_panel(const RestSimulation& sim, const RestResult& r, std::string title);
// The pictures' views: the body seen from the support's side, looking along
// `support_to_body`; the support seen from the body's side, looking the
// other way (its back faces left out: it is a closed surface).
report::PressureMapOptions body_pressure_view(const Eigen::Vector3d& support_to_body);
report::PressureMapOptions support_pressure_view(const Eigen::Vector3d& support_to_body);

// The summary (also written as summary.json).
Json write_rest_outputs(const std::filesystem::path& out, const RestScene& scene, const RestSimulation& sim,
                        const RestResult& r);

// A whole `palpa rest` run: the scene solved and its folder written (refused
// when it holds files, unless `overwrite`; nothing written on bad input).
struct RestRun {
  RestResult result;
  Json summary;         // summary.json
  SurfaceMesh skin;     // the deformed skin [m]
  SurfaceMesh support;  // the support where it is now [m]
};
RestRun run_rest(const RestScene& scene, const std::filesystem::path& out, bool overwrite);

}  // namespace palpa::rest
