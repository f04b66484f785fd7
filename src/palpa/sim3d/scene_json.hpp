// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Reading the pieces scene files share (`palpa sim3d`, `palpa rest`): 3-vectors
// of quantities, positive quantities, rotations, solver settings, paths
// relative to the scene. Every error names the file and field (JsonView).

#include <Eigen/Core>
#include <filesystem>

#include "palpa/body/contact_term.hpp"
#include "palpa/core/json.hpp"
#include "palpa/solve/newton.hpp"
#include "palpa/tet/model.hpp"

namespace palpa::sim3d {

// [x, y, z], each a quantity of dimension d, in SI.
Eigen::Vector3d read_quantity3(const JsonView& v, Dimension d);
// [x, y, z] of plain numbers.
Eigen::Vector3d read_number3(const JsonView& v);
// A quantity that must be > 0.
double read_positive(const JsonView& v, Dimension d);
// {"axis": [x, y, z], "angle": "30 deg"}.
Eigen::Matrix3d read_rotation(const JsonView& v);
// A path in the scene, relative to the scene file's folder unless absolute.
std::filesystem::path resolve_scene_path(const std::filesystem::path& scene_file, const std::string& p);
// Relative paths in (a part of) a scene made absolute against the scene
// file's folder, so that it can be read from elsewhere: every string member
// that names a file by its key ("file", "grid", "surface", "samples",
// "layer", "material").
void absolutize_scene_paths(Json& j, const std::filesystem::path& scene_file);
// "backtracking" | "golden" | "brent" | "backtracking+brent".
LineSearchKind read_line_search(const JsonView& v);
// A whole number in [lo, hi].
int read_count(const JsonView& v, int lo, int hi);
// "vertices" | "surface" (body/contact_term.hpp).
body::ContactSampling read_contact_sampling(const JsonView& v);

// The tet element of a body: its optional "element" ("linear" |
// "nodal-pressure", the default) and "stabilization" (β in [0, 1),
// nodal-pressure only, default tet::kDefaultStabilization).
tet::ElementChoice read_element(const JsonView& body);
// The element a model uses, as summaries report it: {"element", "stabilization"}.
Json element_json(const tet::ElasticModel& model);

}  // namespace palpa::sim3d
