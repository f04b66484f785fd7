// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// What `palpa mesh layer` writes for a layer mesh: the tets as VTU (with the
// vertices attached to the core and the per-tet Young's modulus,
// youngs_modulus_Pa, when there is one) and as TetGen .node/.ele/.face, the core and outer surfaces (OBJ), the
// attached vertices (CSV) and a summary (JSON) — every file or none.

#include <filesystem>
#include <optional>
#include <string>

#include "palpa/core/json.hpp"
#include "palpa/mesh/layer.hpp"

namespace palpa::mesh {

// Where each file of a layer mesh written to `vtu` goes: beside it, named
// after it (layer.vtu: layer.node/.ele/.face, layer_core.obj, layer_outer.obj,
// layer_summary.json, layer_attached.csv).
struct LayerFiles {
  std::filesystem::path vtu, node, ele, face, core, outer, summary, attached;
};
LayerFiles layer_files(const std::filesystem::path& vtu);

Json tet_statistics_json(const TetStatistics& s);

// How the layer was asked for, as the summary records it.
struct LayerRequest {
  std::string surface;        // the scan file
  double edge_length = 0.0;   // [m]
  DepthSpec depth;
  std::string depth_samples;  // the depth samples' file, when depth.samples
  Json stage_seconds = Json::object();
};

Json layer_summary_json(const LayerMesh& layer, const LayerSummary& s, const LayerRequest& request);

// Writes every file of layer_files(vtu), or none (the folder must exist).
void write_layer(const LayerMesh& layer, const Json& summary, const std::filesystem::path& vtu);

// The whole of `palpa mesh layer` after its inputs are read: meshes the layer
// (logging each stage, timing it into the summary, checking for an interrupt
// between stages), summarizes it and writes every file of layer_files(vtu).
LayerSummary mesh_layer_to_files(const SurfaceMesh& scan, const std::optional<Samples>& stiffness, LayerOptions o,
                                 LayerRequest request, const std::filesystem::path& vtu);

}  // namespace palpa::mesh
