// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Scenes of `palpa rest` (JSON, every quantity with its unit):
//
// {
//   "palpa_rest": 1,
//   "body": {
//     "surface": "foot.obj", "unit": "m", "depth": "10 mm", "edge": "10 mm",
//        // depth may be {"samples": "depths.csv", "column": "depth"}; optional
//        // "clamp_depth": true, "scale": 0.2 (normalized scans),
//        // "remove_self_intersections": true,
//        // "clip": {"min": [...], "max": [...]}, "cut": [{"min", "max"}, ...]
//        // or "layer": "foot.vtu" (from palpa mesh layer: point data "attached")
//        // or "generate": {"shape": "foot", "length": "260 mm"}, "depth", "edge"
//        // optional "refine": {"edge": "3 mm", "within": "15 mm"}: the skin
//        // within 15 mm of the support (where the body is placed) at 3 mm,
//        // growing to "edge" around it (mesh/graded_remesh.hpp)
//     "material": "tissue.json",          // or an inline material object
//     "stiffness": {"samples": "moduli.csv", "column": "youngs_modulus"},
//        // optional: Young's moduli measured on the skin (mesh/samples.hpp),
//        // interpolated over it as the depth is; each tet takes the
//        // material's shape scaled to its modulus (tet/material_field.hpp).
//        // With "layer": "stiffness": "layer" takes the layer's own cell data
//        // youngs_modulus_Pa (palpa mesh layer --stiffness-samples).
//     "density": "1000 kg/m^3",
//     "element": "linear",                // or "nodal-pressure" for ν near 0.5
//                                         // (tet/model.hpp), with an optional
//                                         // "stabilization": β (default 0)
//     "position": ["0 mm", "0 mm", "2 mm"],             // moves the body
//     "rotation": {"axis": [0, 0, 1], "angle": "0 deg"}
//   },
//   "core": {"mass": "1 kg", "free": ["z", "ry"],      // of x y z rx ry rz
//            "force": ["0 N", "0 N", "-343 N"], "torque": ["0 N*m", "4 N*m", "0 N*m"],
//            "centre": ["0 mm", "0 mm", "40 mm"]},     // default: mean of the attached vertices
//   "support": {"box": {"size": ["300 mm", "150 mm", "20 mm"], "divisions": 60},
//               "position": ["130 mm", "0 mm", "0 mm"]},  // box: top face centre
//              // box: optional "bevel": {"radius": "60 mm", "side": "-y"}
//              // or {"spheres": [{"centre": [...], "radius": "20 mm"}, ...], "level": 3,
//              //     "smoothing": 4}                 (overlapping spheres are united)
//              // or {"negative_image": {"box": {...}, "press": "50 mm", "edge": "10 mm",
//              //     "smoothing": 10, "band": "20 mm", "clearance": "2 mm"}}
//              // or {"file": "chair.obj", "unit": "m"}
//   "gravity": ["0 m/s^2", "0 m/s^2", "-9.81 m/s^2"],
//   "contact": {"max_penetration": "0.3 mm"},          // or {"stiffness": "5000 N/m"}
//   "solver": {"line_search": "backtracking+brent", "max_iterations": 300}
// }
//
// Relative paths resolve against the scene's folder.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "palpa/core/json.hpp"
#include "palpa/geometry/mesh.hpp"
#include "palpa/mesh/layer.hpp"
#include "palpa/report/pressure_template.hpp"
#include "palpa/rest/rest.hpp"

namespace palpa::rest {

// A measured pressure map to compare the body side with
// (report/pressure_template.hpp): "template": {"grid": "MUN104L.csv",
// "unit": "kPa", "pixel": "5 mm", "title": "MUN104, left foot"}.
struct TemplateSpec {
  std::filesystem::path file;
  report::PressureGrid grid;  // read with the scene
  std::string title;
};

struct RestScene {
  std::filesystem::path file;
  RestBody body;
  std::string body_source;        // what the body was made from, for the summary
  Eigen::Index body_repaired_pairs = 0;  // crossing triangle pairs removed from the scan
  Eigen::Index body_depth_clamped = 0;   // skin vertices whose depth was thinned to fit
  SurfaceMesh support;            // world coordinates
  Eigen::Vector3d body_shift = Eigen::Vector3d::Zero();  // the body moved into a negative image [m]
  std::string support_source;
  RestOptions options;
  std::optional<TemplateSpec> reference_map;
};

// Reads a scene and builds the body (meshing a surface with mesh::make_layer
// when asked). Throws palpa::Error (Input) naming the file and field.
// version_key: the member holding the format version ("palpa_rest"; a
// design scene is a rest scene under "palpa_design"); extra_keys: further
// top-level members the caller reads itself.
RestScene read_rest_scene(const std::filesystem::path& path, const std::string& version_key = "palpa_rest",
                          const std::vector<std::string>& extra_keys = {});
// The same from a scene already parsed; `path` names it in messages and is
// what relative paths in it are relative to (its folder).
RestScene read_rest_scene(const Json& doc, const std::filesystem::path& path,
                          const std::string& version_key = "palpa_rest", const std::vector<std::string>& extra_keys = {});

// The closed skin surface a "body" object describes with "surface" or
// "generate" (read, scaled, repaired, clipped and cut as the keys say; in the
// scan's frame, before "rotation" and "position") [m]. source is set to what
// it was made from; repaired_pairs (may be null) to the crossing triangle
// pairs removed. Throws palpa::Error (Input) naming the field.
SurfaceMesh read_body_surface(const JsonView& body, const std::filesystem::path& file, std::string& source,
                              Eigen::Index* repaired_pairs = nullptr);

// The layer's options a "body" object gives ("edge", "refine", "clamp_depth",
// "core_offset"; the grading's distance to the support is the caller's to
// set), and its "density" [kg/m³] (default 1000). Throw palpa::Error (Input)
// naming the field; nothing is built.
mesh::LayerOptions read_layer_options(const JsonView& body);
double read_body_density(const JsonView& body);

// Builds s.support (and s.support_source) from a "support" object for the
// body of s as it stands; a negative image moves s.body into its hollow
// (adding to s.body_shift). file: the scene, for relative paths and messages.
void read_scene_support(const JsonView& support, const std::filesystem::path& file, RestScene& s);

}  // namespace palpa::rest
